/// Translation of sinks, sensors and trackers (contract in translate_sensors.hpp).
///
/// Field paths follow the JSON: "components[i].<kind>.region.box.size.x",
/// "...surface.disc.normal", "...sample_interval", "...tracker.mesh_bodies[k]". Values
/// the engine checks again (positive sizes, non-zero normals, finite vectors) are checked
/// here with the declaration's own path, so that the error points into the scene file.
#include "demlink/server/scene/translate_sensors.hpp"

#include <charconv>
#include <memory>
#include <optional>
#include <string>

#include "demlink/core/components/flow_sensor.hpp"
#include "demlink/core/base/input_error.hpp"
#include "demlink/core/base/log_text.hpp"
#include "demlink/core/components/particle_sink.hpp"
#include "demlink/core/components/node_tracker.hpp"
#include "demlink/core/components/particle_tracker.hpp"
#include "demlink/core/deformable/deformable_body.hpp"
#include "demlink/core/components/region_sensor.hpp"
#include "demlink/server/scene/proto_convert.hpp"

namespace demlink::server {
namespace {

using core::InputError;

std::string quoted(const std::string& text) { return core::quotedLogText(text); }

/// Index of the mesh body declared under `name`; throws naming `field` if none.
std::size_t meshIndex(const core::World& world, const std::string& name, const std::string& field) {
  std::string declared;
  for (std::size_t k = 0; k < world.meshes().size(); ++k) {
    if (world.meshes()[k].name() == name) return k;
    declared += (declared.empty() ? "" : ", ") + world.meshes()[k].name();
  }
  throw InputError(field, quoted(name),
                   "unknown mesh body (declared: " + (declared.empty() ? std::string("none") : declared) + ")");
}

/// A tracker's "<body>:<node>": the deformable body's index and the node (checked by the tracker).
core::TrackedNode trackedNode(const core::World& world, const std::string& text, const std::string& field) {
  const std::size_t colon = text.rfind(':');
  if (colon == std::string::npos || colon + 1 == text.size()) {
    throw InputError(field, quoted(text), "expected \"<body>:<node>\", e.g. \"sheet:60\"");
  }
  const std::string name = text.substr(0, colon);
  const std::string digits = text.substr(colon + 1);
  std::size_t node = 0;
  const auto [end, error] = std::from_chars(digits.data(), digits.data() + digits.size(), node);
  if (error != std::errc() || end != digits.data() + digits.size()) {
    throw InputError(field, quoted(text), "the node after ':' must be a non-negative integer");
  }
  std::string declared;
  for (std::size_t k = 0; k < world.deformableBodies().size(); ++k) {
    if (world.deformableBodies()[k]->name() == name) return {k, node};
    declared += (declared.empty() ? "" : ", ") + world.deformableBodies()[k]->name();
  }
  throw InputError(field, quoted(text),
                   "unknown deformable body \"" + name + "\" (declared: " + (declared.empty() ? std::string("none") : declared) + ")");
}

/// Velocity and attachment shared by Volume and Surface.
template <class Region>
core::RegionPlacement placementOf(const Region& region, const core::World& world, const std::string& prefix) {
  core::RegionPlacement placement;
  placement.velocity = toFiniteVec3(region.velocity(), prefix + ".velocity");
  if (!region.attached_to().empty()) {
    placement.attached_mesh = meshIndex(world, region.attached_to(), prefix + ".attached_to");
  }
  return placement;
}

}  // namespace

TranslatedVolume toVolume(const v1::Volume& volume, bool present, const core::World& world,
                          const std::string& prefix) {
  if (!present) throw InputError(prefix, "(missing)", "a region (box or sphere) is required");
  core::RegionPlacement placement = placementOf(volume, world, prefix);
  switch (volume.shape_case()) {
    case v1::Volume::kBox: {
      const v1::BoxRegion& box = volume.box();
      const std::string field = prefix + ".box";
      if (!box.has_size()) throw InputError(field + ".size", "(missing)", "the box's side lengths are required");
      placement.centre = toFiniteVec3(box.centre(), field + ".centre");
      if (box.has_orientation()) placement.orientation = toUnitQuat(box.orientation(), field + ".orientation");
      return {core::VolumeShape::box(toVec3(box.size()), field), placement};
    }
    case v1::Volume::kSphere: {
      const v1::SphereRegion& sphere = volume.sphere();
      const std::string field = prefix + ".sphere";
      placement.centre = toFiniteVec3(sphere.centre(), field + ".centre");
      return {core::VolumeShape::sphere(sphere.radius(), field), placement};
    }
    case v1::Volume::SHAPE_NOT_SET: break;
  }
  throw InputError(prefix, "{}", "declares no shape (box or sphere)");
}

namespace {

struct TranslatedSurface {
  core::SurfaceShape shape;
  core::RegionPlacement placement;
};

TranslatedSurface toSurface(const v1::Surface& surface, bool present, const core::World& world,
                            const std::string& prefix) {
  if (!present) throw InputError(prefix, "(missing)", "a surface (rectangle or disc) is required");
  core::RegionPlacement placement = placementOf(surface, world, prefix);
  switch (surface.shape_case()) {
    case v1::Surface::kRectangle: {
      const v1::RectangleSurface& rectangle = surface.rectangle();
      const std::string field = prefix + ".rectangle";
      if (!rectangle.has_normal()) throw InputError(field + ".normal", "(missing)", "a surface needs a normal");
      placement.centre = toFiniteVec3(rectangle.centre(), field + ".centre");
      placement.orientation =
          core::surfaceOrientation(toVec3(rectangle.normal()), toVec3(rectangle.length_axis()), field);
      return {core::SurfaceShape::rectangle(rectangle.length(), rectangle.width(), field), placement};
    }
    case v1::Surface::kDisc: {
      const v1::DiscSurface& disc = surface.disc();
      const std::string field = prefix + ".disc";
      if (!disc.has_normal()) throw InputError(field + ".normal", "(missing)", "a surface needs a normal");
      placement.centre = toFiniteVec3(disc.centre(), field + ".centre");
      placement.orientation = core::surfaceOrientation(toVec3(disc.normal()), core::Vec3::Zero(), field);
      return {core::SurfaceShape::disc(disc.radius(), field), placement};
    }
    case v1::Surface::SHAPE_NOT_SET: break;
  }
  throw InputError(prefix, "{}", "declares no shape (rectangle or disc)");
}

template <class Declaration>
core::SampleSchedule scheduleOf(const Declaration& declaration, const std::string& prefix) {
  core::SampleSchedule schedule{declaration.sample_interval(), declaration.sample_every_steps()};
  if (schedule.every_steps > 0 && schedule.interval != 0.0) {
    throw InputError(prefix + ".sample_every_steps", std::to_string(schedule.every_steps),
                     "give sample_interval or sample_every_steps, not both");
  }
  return schedule;
}

}  // namespace

void addSensorComponents(const v1::Scene& scene, core::World& world) {
  for (int i = 0; i < scene.components_size(); ++i) {
    const v1::ComponentDeclaration& component = scene.components(i);
    const std::string path = componentPath(i);
    switch (component.kind_case()) {
      case v1::ComponentDeclaration::kParticleSink: {
        const v1::ParticleSink& sink = component.particle_sink();
        const std::string prefix = path + ".particle_sink";
        TranslatedVolume region = toVolume(sink.region(), sink.has_region(), world, prefix + ".region");
        world.addComponent(std::make_unique<core::ParticleSink>(component.name(), region.shape, region.placement,
                                                                scheduleOf(sink, prefix), prefix));
        break;
      }
      case v1::ComponentDeclaration::kRegionSensor: {
        const v1::RegionSensor& sensor = component.region_sensor();
        const std::string prefix = path + ".region_sensor";
        TranslatedVolume region = toVolume(sensor.region(), sensor.has_region(), world, prefix + ".region");
        world.addComponent(std::make_unique<core::RegionSensor>(component.name(), region.shape, region.placement,
                                                                scheduleOf(sensor, prefix), prefix));
        break;
      }
      case v1::ComponentDeclaration::kFlowSensor: {
        const v1::FlowSensor& sensor = component.flow_sensor();
        const std::string prefix = path + ".flow_sensor";
        TranslatedSurface surface = toSurface(sensor.surface(), sensor.has_surface(), world, prefix + ".surface");
        world.addComponent(std::make_unique<core::FlowSensor>(component.name(), surface.shape, surface.placement,
                                                              scheduleOf(sensor, prefix), prefix));
        break;
      }
      case v1::ComponentDeclaration::kTracker: {
        const v1::Tracker& tracker = component.tracker();
        const std::string prefix = path + ".tracker";
        std::vector<std::uint64_t> ids(tracker.particle_ids().begin(), tracker.particle_ids().end());
        std::vector<std::size_t> meshes;
        for (int k = 0; k < tracker.mesh_bodies_size(); ++k) {
          meshes.push_back(
              meshIndex(world, tracker.mesh_bodies(k), prefix + ".mesh_bodies[" + std::to_string(k) + "]"));
        }
        std::vector<core::TrackedNode> nodes;
        for (int k = 0; k < tracker.nodes_size(); ++k) {
          nodes.push_back(trackedNode(world, tracker.nodes(k), prefix + ".nodes[" + std::to_string(k) + "]"));
        }
        // Nodes go to a node tracker of their own (same name, or "<name>.nodes" next to a
        // particle tracker): a tracker of nodes only needs no particle.
        if (!ids.empty() || !meshes.empty() || nodes.empty()) {
          world.addComponent(std::make_unique<core::ParticleTracker>(component.name(), std::move(ids),
                                                                     std::move(meshes), scheduleOf(tracker, prefix),
                                                                     prefix));
        }
        if (!nodes.empty()) {
          const bool alone = tracker.particle_ids().empty() && tracker.mesh_bodies().empty();
          world.addComponent(std::make_unique<core::NodeTracker>(alone ? component.name() : component.name() + ".nodes",
                                                                 std::move(nodes), scheduleOf(tracker, prefix),
                                                                 prefix));
        }
        break;
      }
      default: break;
    }
  }
}

}  // namespace demlink::server
