/// Copies what the view shows out of a world (contract in view_snapshot.hpp).
#include "demlink/server/view/view_snapshot.hpp"

#include <spdlog/fmt/fmt.h>

#include <algorithm>
#include <limits>

#include "demlink/core/components/flow_sensor.hpp"
#include "demlink/core/components/particle_sink.hpp"
#include "demlink/core/components/particle_source.hpp"
#include "demlink/core/components/region_sensor.hpp"
#include "demlink/core/deformable/mass_spring_body.hpp"
#include "json_text.hpp"

namespace demlink::server {
namespace {

ViewPose poseOf(const core::Vec3& position, const core::Quat& orientation) {
  ViewPose pose;
  pose.position = {static_cast<float>(position.x()), static_cast<float>(position.y()),
                   static_cast<float>(position.z())};
  pose.orientation = {static_cast<float>(orientation.x()), static_cast<float>(orientation.y()),
                      static_cast<float>(orientation.z()), static_cast<float>(orientation.w())};
  return pose;
}

ViewRegion volumeRegion(const core::World& world, const core::VolumeShape& shape,
                        const core::RegionPlacement& placement) {
  const core::RegionPose pose = placement.poseAt(world.meshes(), world.time());
  ViewRegion region;
  region.pose = poseOf(pose.centre, core::Quat(pose.rotation));
  if (shape.kind() == core::VolumeShape::Kind::Box) {
    region.kind = 0;
    region.half_size = {static_cast<float>(shape.halfSides().x()), static_cast<float>(shape.halfSides().y()),
                        static_cast<float>(shape.halfSides().z())};
  } else {
    region.kind = 1;
    region.half_size = {static_cast<float>(shape.radius()), 0.0f, 0.0f};
  }
  return region;
}

ViewRegion surfaceRegion(const core::World& world, const core::SurfaceShape& shape,
                         const core::RegionPlacement& placement) {
  const core::RegionPose pose = placement.poseAt(world.meshes(), world.time());
  ViewRegion region;
  region.pose = poseOf(pose.centre, core::Quat(pose.rotation));
  if (shape.kind() == core::SurfaceShape::Kind::Rectangle) {
    region.kind = 2;
    region.half_size = {static_cast<float>(shape.halfLength()), static_cast<float>(shape.halfWidth()), 0.0f};
  } else {
    region.kind = 3;
    region.half_size = {static_cast<float>(shape.radius()), 0.0f, 0.0f};
  }
  return region;
}

void appendVectors(std::string& out, const std::vector<core::Vec3>& points) {
  out += '[';
  for (std::size_t i = 0; i < points.size(); ++i) {
    if (i > 0) out += ',';
    out += jsonNumber(points[i].x()) + ',' + jsonNumber(points[i].y()) + ',' + jsonNumber(points[i].z());
  }
  out += ']';
}

void appendTriangles(std::string& out, const std::vector<std::array<std::uint32_t, 3>>& triangles) {
  out += '[';
  for (std::size_t i = 0; i < triangles.size(); ++i) {
    if (i > 0) out += ',';
    out += fmt::format("{},{},{}", triangles[i][0], triangles[i][1], triangles[i][2]);
  }
  out += ']';
}

}  // namespace

void captureSnapshot(const core::World& world, const CaptureFields& fields, ViewSnapshot& snapshot) {
  const core::ParticleArrays& particles = world.particles();
  const std::size_t n = particles.size();
  snapshot.position.resize(3 * n);
  snapshot.radius.resize(n);
  snapshot.material.resize(n);
  snapshot.id.resize(n);
  snapshot.speed.resize(fields.speed ? n : 0);
  snapshot.force.resize(fields.force ? n : 0);
  constexpr double kInfinity = std::numeric_limits<double>::infinity();
  core::Vec3 lower = core::Vec3::Constant(kInfinity);
  core::Vec3 upper = core::Vec3::Constant(-kInfinity);
  double largestRadius = 0.0;
  for (std::size_t i = 0; i < n; ++i) {
    const core::Vec3& x = particles.position[i];
    snapshot.position[3 * i] = static_cast<float>(x.x());
    snapshot.position[3 * i + 1] = static_cast<float>(x.y());
    snapshot.position[3 * i + 2] = static_cast<float>(x.z());
    lower = lower.cwiseMin(x);
    upper = upper.cwiseMax(x);
    largestRadius = std::max(largestRadius, particles.radius[i]);
    snapshot.radius[i] = static_cast<float>(particles.radius[i]);
  }
  std::copy(particles.material.begin(), particles.material.end(), snapshot.material.begin());
  std::copy(particles.id.begin(), particles.id.end(), snapshot.id.begin());
  if (fields.speed) {
    for (std::size_t i = 0; i < n; ++i) snapshot.speed[i] = static_cast<float>(particles.velocity[i].norm());
  }
  if (fields.force) {
    for (std::size_t i = 0; i < n; ++i) snapshot.force[i] = static_cast<float>(particles.force[i].norm());
  }
  if (const std::optional<core::DomainBounds> bounds = world.currentBounds()) {
    lower = bounds->lower;
    upper = bounds->upper;
  } else if (n == 0) {
    lower = upper = core::Vec3::Zero();
  } else {
    lower.array() -= largestRadius;
    upper.array() += largestRadius;
  }
  for (int axis = 0; axis < 3; ++axis) {
    snapshot.box_lower[static_cast<std::size_t>(axis)] = static_cast<float>(lower[axis]);
    snapshot.box_upper[static_cast<std::size_t>(axis)] = static_cast<float>(upper[axis]);
  }

  snapshot.meshes.resize(world.meshes().size());
  for (std::size_t m = 0; m < world.meshes().size(); ++m) {
    snapshot.meshes[m] = poseOf(world.meshes()[m].position(), world.meshes()[m].orientation());
  }
  snapshot.surfaces.resize(world.deformableBodies().size());
  for (std::size_t b = 0; b < world.deformableBodies().size(); ++b) {
    const core::DeformableSurface& surface = world.deformableBodies()[b]->surface();
    ViewSurface& out = snapshot.surfaces[b];
    out.positions.resize(3 * surface.positions().size());
    for (std::size_t k = 0; k < surface.positions().size(); ++k) {
      for (int axis = 0; axis < 3; ++axis) {
        out.positions[3 * k + static_cast<std::size_t>(axis)] = static_cast<float>(surface.positions()[k][axis]);
      }
    }
    out.triangle_active.assign(surface.active().begin(), surface.active().end());
    if (const auto* springs = dynamic_cast<const core::MassSpringBody*>(world.deformableBodies()[b].get())) {
      out.spring_intact.assign(springs->intact().begin(), springs->intact().end());
    } else {
      out.spring_intact.clear();
    }
  }

  snapshot.regions.clear();
  double inserted = 0.0;
  double removed = world.removedAtBounds().mass;
  for (const auto& component : world.components()) {
    if (const auto* sensor = dynamic_cast<const core::RegionSensor*>(component.get())) {
      snapshot.regions.push_back(volumeRegion(world, sensor->shape(), sensor->placement()));
    } else if (const auto* sink = dynamic_cast<const core::ParticleSink*>(component.get())) {
      snapshot.regions.push_back(volumeRegion(world, sink->shape(), sink->placement()));
      removed += sink->total().mass;
    } else if (const auto* flow = dynamic_cast<const core::FlowSensor*>(component.get())) {
      snapshot.regions.push_back(surfaceRegion(world, flow->shape(), flow->placement()));
    } else if (const auto* source = dynamic_cast<const core::ParticleSource*>(component.get())) {
      inserted += source->report().inserted_mass;
    }
  }
  snapshot.status.time = world.time();
  snapshot.status.step = world.stepCount();
  snapshot.status.particle_mass = world.totalMass();
  snapshot.status.inserted_mass = inserted;
  snapshot.status.removed_mass = removed;
}

std::string describeScene(const core::World& world) {
  std::string out = "{\"kind\":\"scene\",\"planes\":[";
  for (std::size_t p = 0; p < world.planes().size(); ++p) {
    const core::PlaneWall& plane = world.planes()[p];
    if (p > 0) out += ',';
    out += "{\"point\":";
    appendVectors(out, {plane.spec.point});
    out += ",\"normal\":";
    appendVectors(out, {plane.spec.normal});
    out += '}';
  }
  out += "],\"meshes\":[";
  for (std::size_t m = 0; m < world.meshes().size(); ++m) {
    const core::MeshBody& mesh = world.meshes()[m];
    if (m > 0) out += ',';
    out += "{\"name\":" + jsonString(mesh.name()) + ",\"vertices\":";
    appendVectors(out, mesh.localVertices());
    out += ",\"triangles\":";
    appendTriangles(out, mesh.triangles());
    out += '}';
  }
  out += "],\"surfaces\":[";
  for (std::size_t b = 0; b < world.deformableBodies().size(); ++b) {
    const core::DeformableBody& body = *world.deformableBodies()[b];
    if (b > 0) out += ',';
    out += "{\"name\":" + jsonString(body.name()) + ",\"triangles\":";
    appendTriangles(out, body.surface().triangles());
    out += ",\"springs\":[";
    if (const auto* massSpring = dynamic_cast<const core::MassSpringBody*>(&body)) {
      const std::vector<core::SpringSpec>& springs = massSpring->springs();
      for (std::size_t k = 0; k < springs.size(); ++k) {
        out += fmt::format("{}{},{}", k == 0 ? "" : ",", springs[k].a, springs[k].b);
      }
    }
    out += "]}";
  }
  out += "],\"regions\":[";
  bool first = true;
  for (const auto& component : world.components()) {
    const bool region = dynamic_cast<const core::RegionSensor*>(component.get()) != nullptr ||
                        dynamic_cast<const core::ParticleSink*>(component.get()) != nullptr ||
                        dynamic_cast<const core::FlowSensor*>(component.get()) != nullptr;
    if (!region) continue;
    if (!first) out += ',';
    first = false;
    out += jsonString(component->name());
  }
  out += "],\"materials\":[";
  for (std::size_t m = 0; m < world.materials().size(); ++m) {
    if (m > 0) out += ',';
    out += jsonString(world.materials()[m].name);
  }
  out += "]}";
  return out;
}

}  // namespace demlink::server
