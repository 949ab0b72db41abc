/// Clumps from particle_source and pit_generator in scene files: a named template
/// is resolved and inserted, the example scene pours clumps, and bad fields (unknown
/// template, sizes given together with clump_template) are named by their path.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>

#include "demlink/core/base/input_error.hpp"
#include "demlink/core/components/particle_source.hpp"
#include "demlink/server/scene/scene_loader.hpp"
#include "demlink/server/scene/scene_translator.hpp"
#include "scene_test_support.hpp"

namespace demlink::server {
namespace {

constexpr const char* kBox = R"({"name": "box", "simulation_box": {"end_time": 0.1, "restitution_tolerance": 0.2}})";
constexpr const char* kGlass = R"({"name": "glass", "material": {}})";
constexpr const char* kPair = R"({"name": "pair", "clump_template": {"spheres": [
    {"offset": {"x": -0.001}, "radius": 0.001}, {"offset": {"x": 0.001}, "radius": 0.001}]}})";

using test::sceneOf;

std::string source(const std::string& body) {
  return R"({"name": "src", "particle_source": {"material": "glass",
             "box": {"half_extents": {"x": 0.02, "y": 0.02, "z": 0.02}}, "rate_particles_per_s": 2000)" +
         body + "}}";
}

std::string pit(const std::string& body) {
  return R"({"name": "bed", "pit_generator": {"material": "glass", "lower": {"x": -0.01, "y": -0.01},
             "upper": {"x": 0.01, "y": 0.01, "z": 0.05}, "max_settle_time": 0.001)" +
         body + "}}";
}

std::string errorField(const v1::Scene& scene) { return test::errorFieldAfterInitialize(scene); }

TEST(TranslateClumpSources, SourceInsertsClumpsOfTheNamedTemplate) {
  TranslatedScene t = translateScene(sceneOf({kBox, kGlass, kPair, source(R"(, "clump_template": "pair")")}), {});
  t.world.initialize();
  for (int n = 0; n < 100; ++n) t.world.step();
  const double elapsed = t.world.time();  // [s]
  const auto expected = std::floor(2000.0 * elapsed);
  EXPECT_NEAR(static_cast<double>(t.world.clumps().size()), expected, 1.0);
  EXPECT_GT(t.world.clumps().size(), 0u);
  EXPECT_EQ(t.world.particles().size(), 2 * t.world.clumps().size());
}

TEST(TranslateClumpSources, BadFieldsAreNamed) {
  const std::string s = "components[3].particle_source";
  const std::string sizes = R"(, "sizes": {"radius": 0.001})";
  EXPECT_EQ(errorField(sceneOf({kBox, kGlass, kPair, source(R"(, "clump_template": "pair")")})), "(accepted)");
  EXPECT_EQ(errorField(sceneOf({kBox, kGlass, kPair, source(R"(, "clump_template": "trio")")})),
            s + ".clump_template");
  EXPECT_EQ(errorField(sceneOf({kBox, kGlass, kPair, source(R"(, "clump_template": "pair")" + sizes)})),
            s + ".sizes");
  EXPECT_EQ(errorField(sceneOf({kBox, kGlass, kPair, source("")})), s + ".sizes");
  const std::string p = "components[3].pit_generator";
  EXPECT_EQ(errorField(sceneOf({kBox, kGlass, kPair, pit(R"(, "target_height": 0.008, "clump_template": "pair")")})),
            "(accepted)");
  EXPECT_EQ(errorField(sceneOf({kBox, kGlass, kPair, pit(R"(, "target_height": 0.008, "clump_template": "trio")")})), p + ".clump_template");
  EXPECT_EQ(errorField(sceneOf({kBox, kGlass, kPair, pit(R"(, "target_height": 0.008, "clump_template": "pair")" + sizes)})), p + ".sizes");
  EXPECT_EQ(errorField(sceneOf({kBox, kGlass, kPair, pit(R"(, "clump_template": "pair", "target_height": 0.001)")})),
            p + ".target_height");
}

TEST(TranslateClumpSources, ExampleScenePoursClumps) {
  const std::filesystem::path file = std::filesystem::path(DEMLINK_EXAMPLES_DIR) / "scenes" / "clump_source.json";
  TranslatedScene t = translateScene(loadSceneFile(file.string()), file.parent_path());
  t.world.initialize();
  for (int n = 0; n < 200 && t.world.clumps().empty(); ++n) t.world.step();
  EXPECT_FALSE(t.world.clumps().empty());
}

}  // namespace
}  // namespace demlink::server
