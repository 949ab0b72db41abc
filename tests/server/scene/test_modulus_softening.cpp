// SimulationBox.modulus_scale: every contact material's Young's modulus is softened by the
// factor, the critical time step grows as the Rayleigh and Hertz laws say, no preset
// softens by itself, a softened cohesive material is warned about, and a value outside
// (0, 1] is refused naming the field.
#include <cmath>
#include <limits>
#include <string>

#include <gtest/gtest.h>

#include "scene_test_support.hpp"

namespace demlink::server {
namespace {

v1::Scene sceneWith(const std::string& boxFields, const std::string& glassFields = "", const std::string& extra = "") {
  std::vector<std::string> components{
      R"({"name": "box", "simulation_box": {"end_time": 1, "time_step": 1e-9)" + boxFields + "}}",
      R"({"name": "glass", "material": {"youngs_modulus": 1e7)" + glassFields + "}}",
      R"({"name": "steel", "material": {"youngs_modulus": 2e11}})",
      R"({"name": "balls", "particle_lattice": {"material": "glass", "radius": 0.005, "spacing": 0.0105,
          "counts": {"nx": 2, "ny": 1, "nz": 1}}})"};
  if (!extra.empty()) components.push_back(extra);
  return test::sceneOf(components);
}

bool hasLine(const std::vector<std::string>& lines, const std::string& text) {
  for (const std::string& line : lines) {
    if (line.find(text) != std::string::npos) return true;
  }
  return false;
}

TEST(ModulusSoftening, ExplicitScaleSoftensEveryMaterialAndRaisesTheLimit) {
  TranslatedScene stiff = translateScene(sceneWith(""), {});
  TranslatedScene soft = translateScene(sceneWith(R"(, "modulus_scale": 0.25)"), {});
  ASSERT_EQ(soft.world.materials().size(), 2u);
  EXPECT_EQ(soft.world.materials()[0].youngs_modulus, 0.25 * 1e7);
  EXPECT_EQ(soft.world.materials()[1].youngs_modulus, 0.25 * 2e11);
  EXPECT_EQ(soft.world.materials()[0].density, stiff.world.materials()[0].density);
  stiff.world.initialize();
  soft.world.initialize();
  // Rayleigh: T_R ~ R sqrt(rho / G), so 4x softer is 2x longer; a Hertz contact lasts
  // ~ E*^(-2/5), so 4^(2/5) longer (the contact duration is integrated numerically).
  EXPECT_NEAR(soft.world.timeStepReport().rayleigh_time_step / stiff.world.timeStepReport().rayleigh_time_step, 2.0,
              1e-12);
  EXPECT_NEAR(soft.world.timeStepReport().contact_duration / stiff.world.timeStepReport().contact_duration,
              std::pow(4.0, 0.4), 1e-3);
  EXPECT_TRUE(hasLine(softeningReportLines(soft.softening), "modulus_scale 0.25"));
  EXPECT_FALSE(hasLine(softeningReportLines(soft.softening), "warning: "));
  // Both runners print the scene's choices from one list.
  EXPECT_TRUE(hasLine(choiceReportLines(soft, soft.world), "modulus_scale 0.25"));
  EXPECT_FALSE(hasLine(choiceReportLines(stiff, stiff.world), "modulus_scale"));
}

TEST(ModulusSoftening, NoPresetSoftens) {
  // The presets change the step, not the material: softening halved the excavator site's
  // digging force (docs/accuracy.md "Softening"), so it stays the user's explicit choice.
  for (const char* preset : {"", R"(, "fidelity": "DRAFT")", R"(, "fidelity": "ENGINEERING")",
                             R"(, "fidelity": "VALIDATION")"}) {
    TranslatedScene t = translateScene(sceneWith(preset), {});
    EXPECT_EQ(t.world.materials()[0].youngs_modulus, 1e7) << preset;
    EXPECT_EQ(t.softening.factor, 1.0) << preset;
    EXPECT_TRUE(softeningReportLines(t.softening).empty()) << preset;
  }
}

TEST(ModulusSoftening, WarnsForEachCohesiveMaterialOrPairItSoftens) {
  const std::string wetPair =
      R"({"name": "wet", "material_pair": {"material_a": "glass", "material_b": "steel", "cohesion_energy_density": 1e4}})";
  TranslatedScene t =
      translateScene(sceneWith(R"(, "modulus_scale": 0.5)", R"(, "cohesion_energy_density": 1e4)", wetPair), {});
  EXPECT_EQ(t.world.materials()[0].youngs_modulus, 0.5e7);
  EXPECT_EQ(t.world.materials()[0].cohesion_energy_density, 1e4);
  const std::vector<std::string> lines = softeningReportLines(t.softening);
  EXPECT_TRUE(hasLine(lines, "warning: modulus_scale 0.5 softens cohesive material glass"));
  EXPECT_TRUE(hasLine(lines, "warning: modulus_scale 0.5 softens cohesive material_pair wet"));
  EXPECT_FALSE(hasLine(lines, "material steel"));
}

TEST(ModulusSoftening, OutOfRangeNamesTheField) {
  for (double bad : {0.0, -0.5, 1.5, std::numeric_limits<double>::quiet_NaN()}) {
    v1::Scene scene = sceneWith("");
    scene.mutable_components(0)->mutable_simulation_box()->set_modulus_scale(bad);
    try {
      (void)translateScene(scene, {});
      ADD_FAILURE() << "accepted " << bad;
    } catch (const core::InputError& error) {
      EXPECT_EQ(error.field(), "components[0].simulation_box.modulus_scale") << bad;
    }
  }
}

}  // namespace
}  // namespace demlink::server
