// SimulationBox.fidelity: each preset sets the knobs a box leaves unset, explicit fields
// always win, no preset changes nothing, and the report says what was chosen and warns
// when the time step is above the preset's share of the critical limit.
#include <algorithm>
#include <string>

#include <gtest/gtest.h>

#include "scene_test_support.hpp"

namespace demlink::server {
namespace {

v1::Scene sceneWith(const std::string& boxFields) {
  return test::sceneOf({R"({"name": "box", "simulation_box": {"end_time": 1)" + boxFields + "}}",
                        R"({"name": "glass", "material": {"youngs_modulus": 1e7}})",
                        R"({"name": "ball", "particle_lattice": {"material": "glass", "radius": 0.005, "spacing": 1,
                            "counts": {"nx": 1, "ny": 1, "nz": 1}}})"});
}

bool hasLine(const std::vector<std::string>& lines, const std::string& text) {
  return std::any_of(lines.begin(), lines.end(), [&](const std::string& l) { return l.find(text) != std::string::npos; });
}

TEST(FidelityPreset, NoPresetKeepsTheFieldDefaults) {
  TranslatedScene t = translateScene(sceneWith(""), {});
  EXPECT_EQ(t.world.settings().restitution_tolerance, 0.01);
  EXPECT_EQ(t.world.settings().contact_model, core::ContactModel::HertzMindlin);
  EXPECT_TRUE(t.fidelity.preset.empty());
  t.world.initialize();
  EXPECT_TRUE(fidelityReportLines(t.fidelity, t.world).empty());
}

TEST(FidelityPreset, EachPresetSetsTheUnsetKnobs) {
  for (const char* name : {"DRAFT", "ENGINEERING", "VALIDATION"}) {
    v1::SimulationBox::Fidelity preset{};
    ASSERT_TRUE(v1::SimulationBox::Fidelity_Parse(name, &preset));
    const FidelityKnobs knobs = fidelityKnobs(preset, "fidelity");
    TranslatedScene t = translateScene(sceneWith(std::string(R"(, "fidelity": ")") + name + "\""), {});
    EXPECT_EQ(t.fidelity.preset, name);
    EXPECT_EQ(t.world.settings().restitution_tolerance, knobs.restitution_tolerance) << name;
    EXPECT_EQ(t.world.settings().contact_model, knobs.contact_model) << name;
    EXPECT_EQ(t.world.settings().integrator, knobs.integrator) << name;
    EXPECT_EQ(t.fidelity.max_step_fraction, knobs.max_step_fraction) << name;
    EXPECT_TRUE(hasLine(t.fidelity.lines, "restitution_tolerance = ")) << name;
    EXPECT_TRUE(hasLine(t.fidelity.lines, "(preset)")) << name;
  }
  // VALIDATION is the one that tightens the limit below the scene default.
  EXPECT_LT(fidelityKnobs(v1::SimulationBox::VALIDATION, "f").restitution_tolerance, 0.1);
}

TEST(FidelityPreset, ExplicitFieldsAlwaysWin) {
  TranslatedScene t = translateScene(
      sceneWith(R"(, "fidelity": "VALIDATION", "restitution_tolerance": 0.05, "contact_model": "LINEAR_SPRING_DASHPOT",
                  "integrator": "EXPLICIT_EULER")"),
      {});
  EXPECT_EQ(t.world.settings().restitution_tolerance, 0.05);
  EXPECT_EQ(t.world.settings().contact_model, core::ContactModel::LinearSpringDashpot);
  EXPECT_EQ(t.world.settings().integrator, core::IntegratorKind::ExplicitEuler);
  EXPECT_TRUE(hasLine(t.fidelity.lines, "restitution_tolerance = 0.05 (explicit)"));
  EXPECT_TRUE(hasLine(t.fidelity.lines, "contact_model = linear_spring_dashpot (explicit)"));
  EXPECT_FALSE(hasLine(t.fidelity.lines, "(preset)"));
}

TEST(FidelityPreset, ReportWarnsAboveThePresetsShareOfTheLimit) {
  // ENGINEERING recommends at most half the limit: 0.4 of it passes, 0.8 warns.
  const double limit = [] {
    TranslatedScene t = translateScene(sceneWith(R"(, "fidelity": "ENGINEERING", "time_step": 1e-9)"), {});
    t.world.initialize();
    return t.world.timeStepReport().limit;
  }();
  for (double fraction : {0.4, 0.8}) {
    TranslatedScene t = translateScene(
        sceneWith(R"(, "fidelity": "ENGINEERING", "time_step": )" + std::to_string(fraction * limit)), {});
    t.world.initialize();
    const std::vector<std::string> lines = fidelityReportLines(t.fidelity, t.world);
    EXPECT_TRUE(hasLine(lines, "fidelity ENGINEERING")) << fraction;
    EXPECT_TRUE(hasLine(lines, "time step <= 50 % of the critical limit")) << fraction;
    EXPECT_EQ(hasLine(lines, "warning: "), fraction > 0.5) << fraction;
  }
}

TEST(FidelityPreset, UnknownValueNamesTheField) {
  v1::Scene scene = sceneWith("");
  scene.mutable_components(0)->mutable_simulation_box()->set_fidelity(static_cast<v1::SimulationBox::Fidelity>(9));
  try {
    (void)translateScene(scene, {});
    FAIL() << "accepted";
  } catch (const core::InputError& error) {
    EXPECT_EQ(error.field(), "components[0].simulation_box.fidelity");
  }
}

}  // namespace
}  // namespace demlink::server
