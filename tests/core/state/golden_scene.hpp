#pragma once
/// The scene behind the golden checkpoint (tests/core/state/golden/): every kind of
/// state a checkpoint holds is non-trivial when it is saved: free spheres and
/// clumps in contact, two planes with near lists, a translating and turning mesh
/// with a near list and a wrench, a translating frame, bounds removal, and a seeded
/// source, a sink, a flow sensor, a region sensor and a tracker (following a
/// sphere and the mesh). Self-contained on purpose: changing a shared test scene
/// must not silently change the golden file's meaning.
#include <memory>
#include <string>

#include "demlink/core/components/flow_sensor.hpp"
#include "demlink/core/components/particle_sink.hpp"
#include "demlink/core/components/particle_source.hpp"
#include "demlink/core/components/particle_tracker.hpp"
#include "demlink/core/components/region_sensor.hpp"
#include "demlink/core/world.hpp"

namespace demlink::core::test {

/// The floor is z = -0.35 x (tilted, but less than the friction angle); spheres and
/// clumps start just above it. Steps run before the golden checkpoint is written.
inline constexpr int kGoldenSteps = 2000;

inline std::unique_ptr<World> buildGoldenScene() {
  SimulationSettings s;
  s.time_step = 2.0e-5;
  s.gravity = Vec3(0.0, 0.0, -9.81);
  s.max_impact_velocity = 2.0;
  // These scenes test bookkeeping, not restitution: a loose restitution tolerance keeps
  // the step they were written for inside the limit (docs/physics.md "Critical time step").
  s.restitution_tolerance = 0.2;
  s.sort_every_builds = 3;
  // The golden bytes come from the portable pair loop; the AVX2/FMA one rounds differently.
  s.portable_kernel = true;
  s.bounds = DomainBounds{Vec3(-0.08, -0.08, -0.02), Vec3(0.045, 0.08, 0.2)};
  s.frame.linear_acceleration = Vec3(0.8, 0.0, 0.0);
  s.frame.origin = Vec3(0.001, 0.0, 0.0);
  auto world = std::make_unique<World>(s);
  Material grains;
  grains.name = "grains";
  grains.density = 2500.0;
  grains.youngs_modulus = 1.0e7;
  grains.poisson_ratio = 0.3;
  grains.restitution = 0.3;
  grains.sliding_friction = 0.5;
  grains.rolling_friction = 0.05;
  const std::uint32_t material = world->addMaterial(grains);
  world->addPlane({"floor", Vec3::Zero(), Vec3(0.35, 0.0, 1.0).normalized(), material});
  world->addPlane({"front", Vec3(0.04, 0.0, 0.0), -Vec3::UnitX(), material});  // catches what slides

  const TriangleMesh plate = rectangleMesh(Vec3::Zero(), 0.01, 0.01, 2, 2);
  MeshBody paddle("paddle", plate.vertices, plate.triangles, material);
  paddle.setPose(Vec3(0.0, 0.0, 0.012), Quat::Identity());
  paddle.setVelocity(Vec3(0.05, 0.0, 0.0), Vec3(0.0, 0.0, 2.0));
  world->addMesh(std::move(paddle));

  for (int k = 0; k < 16; ++k) {
    ParticleSpec p;
    p.radius = 0.0018;
    const double x = -0.02 + 0.004 * (k % 4);
    p.position = Vec3(x, -0.006 + 0.004 * (k / 4), -0.35 * x + 0.0022 + 0.0005 * (k % 3));  // just above the floor
    p.velocity = Vec3(0.0, 0.0, -0.2);
    p.material = material;
    world->addParticle(p);
  }
  const auto rod = world->addClumpTemplate(
      ClumpTemplate("rod", {{Vec3(-0.003, 0, 0), 0.002}, {Vec3(0, 0.0005, 0), 0.0022}, {Vec3(0.003, 0, 0), 0.002}}));
  for (int k = 0; k < 3; ++k) {
    ClumpSpec spec;
    spec.template_index = rod;
    spec.material = material;
    const double x = -0.015 + 0.008 * k;
    spec.position = Vec3(x, 0.012, -0.35 * x + 0.003 + 0.002 * k);
    spec.orientation = Quat(Eigen::AngleAxisd(0.4 * k, Vec3(1, 2, 3).normalized()));
    spec.velocity = Vec3(0.0, 0.0, -0.3);
    spec.angular_velocity = Vec3(5.0, -3.0 * k, 2.0);
    world->addClump(spec);
  }

  ParticleSourceSpec source;
  source.region.kind = SourceRegion::Kind::Box;
  source.region.centre = Vec3(0.0, 0.0, 0.04);
  source.region.half_extents = Vec3(0.02, 0.02, 0.005);
  source.rate_particles_per_s = 3000.0;
  source.sizes = SizeDistribution::uniform(0.0015, 0.002);
  source.velocity = Vec3(0.0, 0.0, -1.0);
  source.material = material;
  source.seed = 11;
  addParticleSource(*world, "src", source, "components[0].particle_source");
  RegionPlacement drain;
  drain.centre = Vec3(0.02, 0.0, 0.005);
  world->addComponent(std::make_unique<ParticleSink>("drain", VolumeShape::sphere(0.006, "drain"), drain,
                                                     SampleSchedule{.every_steps = 100}, "sink"));
  RegionPlacement gate;
  gate.centre = Vec3(0.0, 0.0, 0.025);
  world->addComponent(std::make_unique<FlowSensor>("gate", SurfaceShape::disc(0.03, "gate"), gate,
                                                   SampleSchedule{.interval = 0.0025}, "flow"));
  RegionPlacement column;
  column.centre = Vec3(0.0, 0.0, 0.02);
  world->addComponent(std::make_unique<RegionSensor>("column", VolumeShape::box(Vec3(0.1, 0.1, 0.03), "column"),
                                                     column, SampleSchedule{.every_steps = 50}, "region"));
  world->addComponent(std::make_unique<ParticleTracker>("follow", std::vector<std::uint64_t>{3, 30},
                                                        std::vector<std::size_t>{0},
                                                        SampleSchedule{.every_steps = 100}, "tracker"));
  world->initialize();
  return world;
}

}  // namespace demlink::core::test
