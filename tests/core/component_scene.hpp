#pragma once
/// A scene where every kind of stateful component acts during a short run: a seeded
/// source inserting spheres that fall (with an initial downward speed) through a flow
/// sensor and a region sensor; part of the stream falls into a sink, the rest lands on
/// a tilted floor, slides off it and leaves the domain bounds; a tracker follows two
/// inserted ids. Shared by the component-checkpoint, mass-balance and determinism tests.
#include <functional>
#include <memory>

#include "demlink/core/components/flow_sensor.hpp"
#include "demlink/core/components/particle_sink.hpp"
#include "demlink/core/components/particle_source.hpp"
#include "demlink/core/components/particle_tracker.hpp"
#include "demlink/core/components/region_sensor.hpp"
#include "test_scenes.hpp"

namespace demlink::core::test {

struct ComponentScene {
  std::unique_ptr<World> world;
  ParticleSource* source = nullptr;
  ParticleSink* sink = nullptr;
  FlowSensor* flow = nullptr;
  RegionSensor* region = nullptr;
  ParticleTracker* tracker = nullptr;
};

inline constexpr double kComponentSceneDt = 5.0e-5;  ///< [s]

/// `seed` seeds the source; `threads` the force loop; `beforeInitialize` may add more
/// components.
inline ComponentScene buildComponentScene(std::uint64_t seed = 7, std::uint32_t threads = 1,
                                          const std::function<void(World&)>& beforeInitialize = {}) {
  SimulationSettings s;
  s.time_step = kComponentSceneDt;
  s.gravity = Vec3(0.0, 0.0, -9.81);
  s.max_impact_velocity = 2.0;  // grains land at about 1.4 m/s
  // These scenes test bookkeeping, not restitution: a loose restitution tolerance keeps
  // the step they were written for inside the limit (docs/physics.md "Critical time step").
  s.restitution_tolerance = 0.2;
  s.threads = threads;
  s.bounds = DomainBounds{Vec3(-0.08, -0.08, -0.02), Vec3(0.045, 0.08, 0.2)};
  ComponentScene scene;
  scene.world = std::make_unique<World>(s);
  World& world = *scene.world;
  const std::uint32_t grains = world.addMaterial(testMaterial(0.3, 0.1));
  // Tilted floor: tan(angle) = 0.35 > friction 0.1, so grains slide towards +x and
  // leave over the bounds at x = 0.045 m.
  world.addPlane({"floor", Vec3::Zero(), Vec3(0.35, 0.0, 1.0).normalized(), grains});

  ParticleSourceSpec spec;
  spec.region.kind = SourceRegion::Kind::Box;
  spec.region.centre = Vec3(0.0, 0.0, 0.05);
  spec.region.half_extents = Vec3(0.03, 0.03, 0.01);
  spec.rate_particles_per_s = 3000.0;
  spec.sizes = SizeDistribution::uniform(0.003, 0.004);
  spec.velocity = Vec3(0.0, 0.0, -1.0);
  spec.material = grains;
  spec.seed = seed;
  scene.source = &addParticleSource(world, "src", spec, "components[0].particle_source");

  RegionPlacement drain;
  drain.centre = Vec3(-0.02, 0.0, 0.012);
  scene.sink = static_cast<ParticleSink*>(&world.addComponent(std::make_unique<ParticleSink>(
      "drain", VolumeShape::sphere(0.012, "drain"), drain, SampleSchedule{.every_steps = 100}, "sink")));

  RegionPlacement gate;
  gate.centre = Vec3(0.0, 0.0, 0.03);
  scene.flow = static_cast<FlowSensor*>(&world.addComponent(std::make_unique<FlowSensor>(
      "gate", SurfaceShape::disc(0.045, "gate"), gate, SampleSchedule{.interval = 0.0025}, "flow")));

  RegionPlacement column;
  column.centre = Vec3(0.0, 0.0, 0.02);
  scene.region = static_cast<RegionSensor*>(&world.addComponent(std::make_unique<RegionSensor>(
      "column", VolumeShape::box(Vec3(0.1, 0.1, 0.03), "column"), column, SampleSchedule{.every_steps = 50},
      "region")));

  scene.tracker = static_cast<ParticleTracker*>(&world.addComponent(std::make_unique<ParticleTracker>(
      "follow", std::vector<std::uint64_t>{3, 60}, std::vector<std::size_t>{}, SampleSchedule{.every_steps = 100},
      "tracker")));
  if (beforeInitialize) beforeInitialize(world);
  world.initialize();
  return scene;
}

}  // namespace demlink::core::test
