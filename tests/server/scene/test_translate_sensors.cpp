/// Translation of sinks, sensors and trackers: every kind reaches the engine with its
/// values, attachment is by mesh body component name (declared in any order), bad
/// values name their field path, and a headless run writes one CSV per component.
#include <gtest/gtest.h>

#include "demlink/core/components/flow_sensor.hpp"
#include "demlink/core/base/input_error.hpp"
#include "demlink/core/components/particle_sink.hpp"
#include "demlink/core/components/particle_tracker.hpp"
#include "demlink/core/components/region_sensor.hpp"
#include "demlink/server/run/headless_runner.hpp"
#include "demlink/server/scene/scene_loader.hpp"
#include "demlink/server/scene/scene_translator.hpp"
#include "test_support.hpp"
#include "scene_test_support.hpp"

namespace demlink::server {
namespace {

const std::filesystem::path kScenes = std::filesystem::path(DEMLINK_EXAMPLES_DIR) / "scenes";

constexpr const char* kBox =
    R"({"name": "box", "simulation_box": {"end_time": 0.002, "restitution_tolerance": 0.2, "output": {"progress_interval_s": 60}}})";
constexpr const char* kGlass = R"({"name": "glass", "material": {}})";
constexpr const char* kLattice = R"({"name": "grains", "particle_lattice": {"material": "glass", "radius": 0.002,
    "spacing": 0.006, "origin": {"z": 0.01}, "counts": {"nx": 2, "ny": 2, "nz": 2}}})";
constexpr const char* kPaddle = R"({"name": "paddle", "mesh_body": {"stl_file": "meshes/paddle.stl",
    "material": "glass", "position": {"x": 1}}})";

using test::sceneOf;

/// The error of translating (and initialising) the scene base + `extra`.
core::InputError errorOf(const std::string& extra) {
  try {
    TranslatedScene t = translateScene(sceneOf({kBox, kGlass, kLattice, kPaddle, extra}), kScenes);
    t.world.initialize();
  } catch (const core::InputError& error) {
    return error;
  }
  ADD_FAILURE() << "expected an InputError for " << extra;
  return core::InputError("(none)", "", "");
}

template <class T>
T* find(core::World& world, const std::string& name) {
  for (const auto& component : world.components()) {
    if (component->name() == name) return dynamic_cast<T*>(component.get());
  }
  return nullptr;
}

TEST(TranslateSensors, EveryKindReachesTheEngine) {
  TranslatedScene t = translateScene(
      sceneOf({kBox, kGlass, kLattice,
               R"({"name": "fill", "region_sensor": {"sample_interval": 1e-4, "region": {"attached_to": "paddle",
                   "box": {"centre": {"x": 0.1}, "size": {"x": 0.1, "y": 0.2, "z": 0.3},
                           "orientation": {"w": 2}}}}})",
               kPaddle,
               R"({"name": "drain", "particle_sink": {"sample_every_steps": 7, "region": {
                   "velocity": {"z": -1}, "sphere": {"centre": {"z": -1}, "radius": 0.5}}}})",
               R"({"name": "gate", "flow_sensor": {"sample_interval": 2e-4, "surface": {"rectangle": {
                   "normal": {"z": -3}, "length_axis": {"x": 1}, "length": 0.4, "width": 0.2}}}})",
               R"({"name": "hole", "flow_sensor": {"sample_interval": 2e-4, "surface": {"disc": {
                   "centre": {"z": 0.005}, "normal": {"z": 1}, "radius": 0.1}}}})",
               R"({"name": "watch", "tracker": {"sample_every_steps": 10, "particle_ids": [1, "8"],
                   "mesh_bodies": ["paddle"]}})"}),
      kScenes);
  t.world.initialize();
  auto* fill = find<core::RegionSensor>(t.world, "fill");
  ASSERT_NE(fill, nullptr);
  EXPECT_EQ(fill->placement().attached_mesh, std::optional<std::size_t>(0));
  EXPECT_EQ(fill->shape().kind(), core::VolumeShape::Kind::Box);
  EXPECT_EQ(fill->shape().halfSides(), core::Vec3(0.05, 0.1, 0.15));
  EXPECT_EQ(fill->sampleEvery(), 10u);
  auto* drain = find<core::ParticleSink>(t.world, "drain");
  ASSERT_NE(drain, nullptr);
  EXPECT_EQ(drain->shape().radius(), 0.5);
  EXPECT_EQ(drain->placement().velocity, core::Vec3(0, 0, -1));
  EXPECT_EQ(drain->sampleEvery(), 7u);
  auto* gate = find<core::FlowSensor>(t.world, "gate");
  ASSERT_NE(gate, nullptr);
  const core::Mat3 r = gate->placement().orientation.toRotationMatrix();
  EXPECT_LT((r.col(2) - core::Vec3(0, 0, -1)).norm(), 1e-14) << "normal normalised";
  EXPECT_LT((r.col(0) - core::Vec3(1, 0, 0)).norm(), 1e-14) << "length along length_axis";
  EXPECT_EQ(gate->shape().halfLength(), 0.2);
  auto* hole = find<core::FlowSensor>(t.world, "hole");
  ASSERT_NE(hole, nullptr);
  EXPECT_EQ(hole->shape().radius(), 0.1);
  auto* watch = find<core::ParticleTracker>(t.world, "watch");
  ASSERT_NE(watch, nullptr);
  ASSERT_EQ(watch->particles().size(), 2u);
  EXPECT_EQ(watch->particles()[1].id, 8u);
  ASSERT_EQ(watch->meshes().size(), 1u);
  EXPECT_EQ(watch->meshes()[0].position, core::Vec3(1, 0, 0));
}

TEST(TranslateSensors, BadValuesNameTheirField) {
  struct Case {
    std::string json;
    std::string field;
  };
  const std::vector<Case> cases = {
      {R"({"name": "s", "region_sensor": {"sample_interval": 1e-3, "region": {"attached_to": "bucket",
          "sphere": {"radius": 0.1}}}})",
       "components[4].region_sensor.region.attached_to"},
      {R"({"name": "s", "region_sensor": {"sample_interval": 1e-3, "region": {"sphere": {"radius": -0.1}}}})",
       "components[4].region_sensor.region.sphere.radius"},
      {R"({"name": "s", "particle_sink": {"sample_interval": 1e-3, "region": {"box": {
          "size": {"x": 1, "y": 1, "z": 0}}}}})",
       "components[4].particle_sink.region.box.size.z"},
      {R"({"name": "s", "particle_sink": {"sample_interval": 1e-3, "region": {"box": {}}}})",
       "components[4].particle_sink.region.box.size"},
      {R"({"name": "s", "particle_sink": {"sample_interval": 1e-3, "region": {"box": {
          "size": {"x": 1, "y": 1, "z": 1}, "orientation": {}}}}})",
       "components[4].particle_sink.region.box.orientation"},
      {R"({"name": "s", "particle_sink": {"sample_interval": 1e-3}})", "components[4].particle_sink.region"},
      {R"({"name": "s", "particle_sink": {"sample_interval": 1e-3, "region": {}}})",
       "components[4].particle_sink.region"},
      {R"({"name": "s", "particle_sink": {"sample_interval": 1e-3, "region": {"attached_to": "paddle",
          "velocity": {"x": 1}, "sphere": {"radius": 1}}}})",
       "components[4].particle_sink.region.velocity"},
      {R"({"name": "s", "flow_sensor": {"sample_interval": 1e-3, "surface": {"disc": {"normal": {},
          "radius": 0.1}}}})",
       "components[4].flow_sensor.surface.disc.normal"},
      {R"({"name": "s", "flow_sensor": {"sample_interval": 1e-3, "surface": {"disc": {"radius": 0.1}}}})",
       "components[4].flow_sensor.surface.disc.normal"},
      {R"({"name": "s", "flow_sensor": {"sample_interval": 1e-3, "surface": {"rectangle": {"normal": {"z": 1},
          "length": 1, "width": -1}}}})",
       "components[4].flow_sensor.surface.rectangle.width"},
      {R"({"name": "s", "flow_sensor": {"sample_interval": 1e-3, "surface": {"rectangle": {"normal": {"z": 1},
          "length_axis": {"z": 2}, "length": 1, "width": 1}}}})",
       "components[4].flow_sensor.surface.rectangle.length_axis"},
      {R"({"name": "s", "flow_sensor": {"sample_interval": 0, "surface": {"disc": {"normal": {"z": 1},
          "radius": 0.1}}}})",
       "components[4].flow_sensor.sample_interval"},
      {R"({"name": "s", "region_sensor": {"sample_interval": -1, "region": {"sphere": {"radius": 0.1}}}})",
       "components[4].region_sensor.sample_interval"},
      {R"({"name": "s", "region_sensor": {"sample_interval": 1e-3, "sample_every_steps": 3,
          "region": {"sphere": {"radius": 0.1}}}})",
       "components[4].region_sensor.sample_every_steps"},
      {R"({"name": "s", "tracker": {"sample_interval": 1e-3, "mesh_bodies": ["paddle", "shovel"]}})",
       "components[4].tracker.mesh_bodies[1]"},
      {R"({"name": "s", "tracker": {"sample_interval": 1e-3, "particle_ids": [0]}})",
       "components[4].tracker.particle_ids[0]"},
      {R"({"name": "s", "tracker": {"sample_interval": 1e-3}})", "components[4].tracker.particle_ids"},
      {R"({"name": "s", "tracker": {"particle_ids": [1]}})", "components[4].tracker.sample_interval"},
  };
  for (const Case& c : cases) {
    SCOPED_TRACE(c.json);
    const core::InputError error = errorOf(c.json);
    EXPECT_EQ(error.field(), c.field) << error.what();
  }
  const core::InputError unknown = errorOf(R"({"name": "s", "region_sensor": {"sample_interval": 1e-3,
      "region": {"attached_to": "bucket", "sphere": {"radius": 0.1}}}})");
  EXPECT_EQ(unknown.value(), "\"bucket\"");
  EXPECT_NE(std::string(unknown.what()).find("paddle"), std::string::npos) << "lists the declared bodies";
}

TEST(TranslateSensors, HeadlessRunWritesOneCsvPerComponent) {
  const test::ScratchDir scratch;
  TranslatedScene t = translateScene(
      sceneOf({kBox, kGlass, kLattice,
               R"({"name": "all", "region_sensor": {"sample_interval": 5e-4, "region": {"box": {
                   "size": {"x": 1, "y": 1, "z": 1}}}}})",
               R"({"name": "low_drain", "particle_sink": {"sample_interval": 5e-4, "region": {"box": {
                   "centre": {"z": -1}, "size": {"x": 1, "y": 1, "z": 1}}}}})",
               R"({"name": "floor", "flow_sensor": {"sample_interval": 1e-3, "surface": {"disc": {
                   "normal": {"z": 1}, "radius": 1}}}})"}),
      kScenes);
  t.run.output_directory = scratch.path().string();
  (void)runHeadless(t);
  // 2e-3 s at dt 1e-5: 200 steps; rows at t = 0 and every 50 (or 100) steps.
  const auto region = test::readText(scratch.path() / "region_sensor_all.csv");
  EXPECT_EQ(test::countOccurrences(region, "\n"), 1u + 5u);
  EXPECT_EQ(region.rfind("time_s,count,mass_kg,", 0), 0u);
  EXPECT_NE(region.find("\n0,8,"), std::string::npos) << "all 8 lattice spheres inside at t = 0";
  const auto sink = test::readText(scratch.path() / "particle_sink_low_drain.csv");
  EXPECT_EQ(test::countOccurrences(sink, "\n"), 1u + 5u);
  const auto flow = test::readText(scratch.path() / "flow_sensor_floor.csv");
  EXPECT_EQ(test::countOccurrences(flow, "\n"), 1u + 3u);
}

}  // namespace
}  // namespace demlink::server
