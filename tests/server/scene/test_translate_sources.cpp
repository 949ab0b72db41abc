/// Sources family in scenes: single_particle, particle_source and pit_generator
/// translate to the engine objects, and every bad field is named by its scene path.
#include <gtest/gtest.h>

#include "demlink/core/base/input_error.hpp"
#include "demlink/core/components/particle_source.hpp"
#include "demlink/server/scene/scene_loader.hpp"
#include "demlink/server/scene/scene_translator.hpp"
#include "scene_test_support.hpp"

namespace demlink::server {
namespace {

constexpr const char* kBox = R"({"name": "box", "simulation_box": {"end_time": 0.1}})";
constexpr const char* kGlass = R"({"name": "glass", "material": {}})";

using test::sceneOf;

/// A particle_source declaration with `body` spliced into its fields.
std::string source(const std::string& body) {
  return R"({"name": "src", "particle_source": {"material": "glass", )" + body + "}}";
}

constexpr const char* kGood =
    R"("sizes": {"uniform": {"r_min": 0.004, "r_max": 0.005}},
       "box": {"lower": {"x": -0.1, "y": -0.1, "z": 0.5}, "upper": {"x": 0.1, "y": 0.1, "z": 0.7}},
       "rate_particles_per_s": 1000)";

std::string errorField(const v1::Scene& scene) { return test::errorFieldAfterInitialize(scene); }

TEST(TranslateSources, SingleParticleUsesHalfTheDiameter) {
  const TranslatedScene t = translateScene(
      sceneOf({kBox, kGlass,
               R"({"name": "p", "single_particle": {"material": "glass", "diameter": 0.02,
                   "position": {"x": 1, "y": 2, "z": 3}, "velocity": {"z": -1}}})"}),
      {});
  ASSERT_EQ(t.world.particles().size(), 1u);
  EXPECT_EQ(t.world.particles().radius[0], 0.01);
  EXPECT_EQ(t.world.particles().position[0], core::Vec3(1, 2, 3));
  EXPECT_EQ(t.world.particles().velocity[0], core::Vec3(0, 0, -1));
}

TEST(TranslateSources, ParticleSourceBecomesAComponentThatInserts) {
  TranslatedScene t = translateScene(sceneOf({kBox, kGlass, source(kGood)}), {});
  ASSERT_EQ(t.world.components().size(), 1u);
  const auto* src = dynamic_cast<const core::ParticleSource*>(t.world.components()[0].get());
  ASSERT_NE(src, nullptr);
  EXPECT_EQ(src->spec().region.centre, core::Vec3(0.0, 0.0, 0.6));
  EXPECT_NEAR(src->spec().region.half_extents.z(), 0.1, 1e-15);
  t.world.initialize();
  for (int n = 0; n < 1000; ++n) t.world.step();  // 0.01 s at 1000/s
  EXPECT_NEAR(static_cast<double>(src->report().inserted_count), 10.0, 1.0);
  EXPECT_EQ(src->report().inserted_count, t.world.particles().size());
}

TEST(TranslateSources, BadSourceFieldsAreNamed) {
  const std::string p = "components[2].particle_source";
  auto field = [&](const std::string& body) { return errorField(sceneOf({kBox, kGlass, source(body)})); };
  const std::string sizes = R"("sizes": {"radius": 0.005}, )";
  const std::string box = R"("box": {"half_extents": {"x": 0.1, "y": 0.1, "z": 0.1}}, )";
  EXPECT_EQ(field(kGood), "(accepted)");
  EXPECT_EQ(field(sizes + box + R"("rate_particles_per_s": -5)"), p + ".rate_particles_per_s");
  EXPECT_EQ(field(sizes + box + R"("rate_particles_per_s": 5, "rate_kg_per_s": 1)"), p + ".rate_particles_per_s");
  EXPECT_EQ(field(sizes + box + R"("seed": 1)"), p + ".rate_particles_per_s");
  EXPECT_EQ(field(sizes + R"("box": {"half_extents": {"x": 0.1, "z": 0.1}}, "rate_kg_per_s": 1)"),
            p + ".box.half_extents[1]");
  EXPECT_EQ(field(sizes + R"("box": {"lower": {"x": 1}, "upper": {"x": 0, "y": 1, "z": 1}}, "rate_kg_per_s": 1)"),
            p + ".box.upper[0]");
  EXPECT_EQ(field(sizes + R"("box": {}, "rate_kg_per_s": 1)"), p + ".box.half_extents");
  EXPECT_EQ(field(sizes + R"("rate_kg_per_s": 1)"), p + ".box");
  EXPECT_EQ(field(sizes + R"("disc": {"radius": 0.1, "normal": {}}, "rate_kg_per_s": 1)"), p + ".disc.normal");
  EXPECT_EQ(field(box + R"("rate_kg_per_s": 1)"), p + ".sizes");
  EXPECT_EQ(field(R"("sizes": {"uniform": {"r_min": 0.005, "r_max": 0.004}}, )" + box + R"("rate_kg_per_s": 1)"),
            p + ".sizes.uniform.r_max");
  EXPECT_EQ(field(R"("sizes": {"linear": {"r_min": 0.004, "r_max": 0.005, "weight_at_min": -1}}, )" + box +
                  R"("rate_kg_per_s": 1)"),
            p + ".sizes.linear.weight_at_min");
  EXPECT_EQ(field(R"("sizes": {"normal": {"mean": 0.004, "std": 0, "r_min": 0.003, "r_max": 0.005}}, )" + box +
                  R"("rate_kg_per_s": 1)"),
            p + ".sizes.normal.std");
  EXPECT_EQ(field(R"("sizes": {"discrete": {"radii": [0.004, 0.005], "weights": [1]}}, )" + box +
                  R"("rate_kg_per_s": 1)"),
            p + ".sizes.discrete.weights");
  EXPECT_EQ(field(sizes + box + R"("rate_kg_per_s": 1, "stop_time": 0)"), p + ".stop_time");
  EXPECT_EQ(field(sizes + box + R"("rate_kg_per_s": 1, "attached_mesh": "nowhere")"), p + ".attached_mesh");
  EXPECT_EQ(errorField(sceneOf({kBox, kGlass,
                                R"({"name": "src", "particle_source": {"material": "steel", )" + sizes + box +
                                    R"("rate_kg_per_s": 1}})"})),
            p + ".material");
  EXPECT_EQ(errorField(sceneOf({kBox, kGlass, R"({"name": "p", "single_particle": {"material": "glass"}})"})),
            "components[2].single_particle.diameter");
}

TEST(TranslateSources, PitGeneratorSettlesABedAndNamesBadFields) {
  const std::string pit =
      R"({"name": "pit", "pit_generator": {"material": "glass", "sizes": {"radius": 0.02},
          "centre": {"x": 0, "y": 0, "z": 0.1}, "size": {"x": 0.3, "y": 0.2, "z": 0.2}, "target_height": 0.08,
          "seed": 3)";
  const TranslatedScene t = translateScene(sceneOf({kBox, kGlass, pit + "}}"}), {});
  ASSERT_GT(t.world.particles().size(), 10u);
  for (std::size_t i = 0; i < t.world.particles().size(); ++i) {
    EXPECT_LE(t.world.particles().position[i].z() + 0.02, 0.0 + 0.08 + 1e-12);
  }
  const std::string p = "components[2].pit_generator";
  EXPECT_EQ(errorField(sceneOf({kBox, kGlass, pit + R"(, "lower": {}}})"})), p + ".lower");
  EXPECT_EQ(errorField(sceneOf({kBox, kGlass, pit + R"(, "packing_fraction": 2}})"})), p + ".packing_fraction");
  EXPECT_EQ(errorField(sceneOf(
                {kBox, kGlass,
                 R"({"name": "pit", "pit_generator": {"material": "glass", "sizes": {"radius": 0.02},
                     "lower": {"x": 0, "y": 0, "z": 0}, "upper": {"x": 1, "y": -1, "z": 1}, "target_height": 0.5}})"})),
            p + ".upper[1]");
  EXPECT_EQ(errorField(sceneOf(
                {kBox, kGlass,
                 R"({"name": "pit", "pit_generator": {"material": "sand", "sizes": {"radius": 0.02},
                     "lower": {"x": 0, "y": 0, "z": 0}, "upper": {"x": 1, "y": 1, "z": 1}, "target_height": 0.5}})"})),
            p + ".material");
}

}  // namespace
}  // namespace demlink::server
