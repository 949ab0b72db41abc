/// demlink-calibrate's TARGETS file: a good file is read with its defaults, every kind of
/// bad one is refused naming the file, the field and the value, and the calibrated entry
/// the tool writes loads through a scene's simulation_box.materials_file.
#include <gtest/gtest.h>

#include <ostream>
#include <string>

#include "calibration_entry.hpp"
#include "calibration_targets.hpp"
#include "demlink/core/base/input_error.hpp"
#include "demlink/server/scene/scene_loader.hpp"
#include "demlink/server/scene/scene_translator.hpp"
#include "test_support.hpp"

namespace demlink::calibrate {
namespace {

constexpr const char* kGood = R"({
  "material": "Wheat",
  "fit": [{"name": "sliding_friction", "min": 0.2, "max": 0.9},
          {"name": "rolling_friction", "min": 0.0, "max": 0.3}],
  "measurements": {"angle_of_repose": 9.0, "hopper_discharge": {"rate": 0.045, "orifice": 0.02}}
})";

TEST(CalibrationTargets, AGoodFileIsReadWithItsDefaults) {
  const Targets t = parseTargets(kGood, "t.json");
  EXPECT_EQ(t.base.material.name, "wheat");
  EXPECT_EQ(t.name, "wheat_calibrated");
  ASSERT_EQ(t.fit.size(), 2u);
  EXPECT_EQ(t.fit[1].parameter, Parameter::RollingFriction);
  EXPECT_EQ(t.fit[1].bounds.max, 0.3);
  ASSERT_EQ(t.measurements.size(), 2u);
  EXPECT_EQ(t.measurements[1].quantity, Quantity::HopperDischarge);
  EXPECT_EQ(t.measurements[1].orifice, 0.02);
  EXPECT_EQ(t.fit_seeds, 2u);
  EXPECT_EQ(t.uncertainty_seeds, 4u);
}

struct BadTargets {
  const char* what;
  std::string json;
  std::string field;
  std::string value;
};

std::ostream& operator<<(std::ostream& out, const BadTargets& bad) { return out << bad.what; }

class CalibrationTargetsErrors : public ::testing::TestWithParam<BadTargets> {};

TEST_P(CalibrationTargetsErrors, NameTheFileTheFieldAndTheValue) {
  try {
    (void)parseTargets(GetParam().json, "t.json");
    FAIL() << "expected an InputError";
  } catch (const core::InputError& e) {
    EXPECT_EQ(e.field(), GetParam().field) << e.what();
    EXPECT_EQ(e.value(), GetParam().value) << e.what();
  }
}

std::string with(const std::string& fit, const std::string& measurements, const std::string& material = "wheat") {
  return R"({"material": ")" + material + R"(", "fit": [)" + fit + R"(], "measurements": {)" + measurements + "}}";
}

const std::string kMu = R"({"name": "sliding_friction", "min": 0.2, "max": 0.9})";
const std::string kAngle = R"("angle_of_repose": 9)";

INSTANTIATE_TEST_SUITE_P(
    Cases, CalibrationTargetsErrors,
    ::testing::Values(
        BadTargets{"unknown_material", with(kMu, kAngle, "granite"), "t.json:material", "\"granite\""},
        BadTargets{"missing_material", R"({"fit": [)" + kMu + R"(], "measurements": {)" + kAngle + "}}",
                   "t.json:material", "(missing)"},
        BadTargets{"unknown_parameter", with(R"({"name": "friction", "min": 0, "max": 1})", kAngle),
                   "t.json:fit[0].name", "\"friction\""},
        BadTargets{"parameter_twice", with(kMu + ", " + kMu, kAngle + R"(, "bulk_density": 700)"),
                   "t.json:fit[1].name", "\"sliding_friction\""},
        BadTargets{"inverted_bounds", with(R"({"name": "sliding_friction", "min": 0.8, "max": 0.2})", kAngle),
                   "t.json:fit[0].max", "0.2"},
        BadTargets{"negative_bound", with(R"({"name": "rolling_friction", "min": -0.1, "max": 0.2})", kAngle),
                   "t.json:fit[0].min", "-0.1"},
        BadTargets{"missing_bound", with(R"({"name": "rolling_friction", "min": 0})", kAngle), "t.json:fit[0].max",
                   "(missing)"},
        BadTargets{"no_parameters", with("", kAngle), "t.json:fit", "(missing)"},
        BadTargets{"negative_angle", with(kMu, R"("angle_of_repose": -5)"), "t.json:measurements.angle_of_repose",
                   "-5"},
        BadTargets{"slump_ratio_above_one", with(kMu, R"("slump_height_ratio": 1.2)"),
                   "t.json:measurements.slump_height_ratio", "1.2"},
        BadTargets{"zero_slump_ratio", with(kMu, R"("slump_height_ratio": 0)"),
                   "t.json:measurements.slump_height_ratio", "0"},
        BadTargets{"denser_than_grains", with(kMu, R"("bulk_density": 2000)"), "t.json:measurements.bulk_density",
                   "2000"},
        BadTargets{"negative_rate", with(kMu, R"("hopper_discharge": {"rate": -0.1, "orifice": 0.02})"),
                   "t.json:measurements.hopper_discharge.rate", "-0.1"},
        BadTargets{"missing_orifice", with(kMu, R"("hopper_discharge": {"rate": 0.1})"),
                   "t.json:measurements.hopper_discharge.orifice", "(missing)"},
        BadTargets{"orifice_jams", with(kMu, R"("hopper_discharge": {"rate": 0.1, "orifice": 0.01})"),
                   "t.json:measurements.hopper_discharge.orifice", "0.01"},
        BadTargets{"orifice_too_wide", with(kMu, R"("hopper_discharge": {"rate": 0.1, "orifice": 0.2})"),
                   "t.json:measurements.hopper_discharge.orifice", "0.2"},
        BadTargets{"fewer_measurements", with(kMu + R"(, {"name": "rolling_friction", "min": 0, "max": 0.3})", kAngle),
                   "t.json:measurements", "1 given"},
        BadTargets{"built_in_name", R"({"material": "wheat", "name": "Corn", "fit": [)" + kMu +
                                        R"(], "measurements": {)" + kAngle + "}}",
                   "t.json:name", "\"Corn\""},
        BadTargets{"unknown_field", R"({"material": "wheat", "fitt": []})", "t.json", "(calibration targets JSON)"},
        BadTargets{"not_an_object", "[1, 2]", "t.json", "(calibration targets JSON)"}),
    [](const ::testing::TestParamInfo<BadTargets>& param) { return std::string(param.param.what); });

TEST(CalibrationTargets, TheExampleFilesAreValid) {
  for (const char* name : {"wheat_targets.json", "synthetic_heap.json", "synthetic_heap_hopper.json",
                           "synthetic_slump.json"}) {
    const Targets t = readTargets(std::string(DEMLINK_SOURCE_DIR) + "/examples/calibration/" + name);
    EXPECT_GE(t.measurements.size(), t.fit.size()) << name;
  }
}

TEST(CalibrationTargets, AMaterialsFileBesideTheTargetsGivesTheBase) {
  const server::test::ScratchDir scratch;
  server::test::writeText(scratch.path() / "mine.csv",
                          "name,density,youngs_modulus,poisson_ratio,restitution,sliding_friction,rolling_friction,"
                          "size_kind,radius_min,radius_max,source\n"
                          "my beans,1200,1e7,0.3,0.5,0.4,0.05,uniform,0.003,0.004,estimate\n");
  const Targets t = parseTargets(
      R"({"material": "my_beans", "materials_file": "mine.csv", "fit": [)" + kMu + R"(], "measurements": {)" +
          kAngle + "}}",
      scratch.path() / "t.json");
  EXPECT_EQ(t.base.material.density, 1200.0);
  EXPECT_EQ(t.base.size.radius_max, 0.004);
  try {
    (void)parseTargets(R"({"material": "my_beans", "materials_file": "absent.csv", "fit": [)" + kMu +
                           R"(], "measurements": {)" + kAngle + "}}",
                       scratch.path() / "t.json");
    FAIL() << "expected an InputError";
  } catch (const core::InputError& e) {
    EXPECT_EQ(e.field(), (scratch.path() / "t.json").string() + ":materials_file") << e.what();
  }
}

TEST(CalibrationTargets, TheWrittenEntryLoadsThroughASceneMaterialsFile) {
  const server::test::ScratchDir scratch;
  const Targets t = parseTargets(kGood, scratch.path() / "t.json");
  writeMaterialsFile(scratch.path() / "calibrated.csv", calibratedRecord(t, {0.6172, 0.1384}),
                     "report line 1\n| a | table |\n");
  const v1::Scene scene = server::parseSceneJson(
      R"({"components": [{"name": "box", "simulation_box": {"end_time": 0.1, "materials_file": "calibrated.csv"}},
                         {"name": "grain", "material": {"database_name": "wheat_calibrated"}}]})",
      "scene.json");
  const server::TranslatedScene translated = server::translateScene(scene, server::FileScope(scratch.path()));
  const core::Material& grain = translated.world.materials().at(0);
  EXPECT_EQ(grain.sliding_friction, 0.6172);
  EXPECT_EQ(grain.rolling_friction, 0.1384);
  EXPECT_EQ(grain.density, t.base.material.density) << "the base's other values are kept";
  EXPECT_EQ(grain.restitution, t.base.material.restitution);
}

}  // namespace
}  // namespace demlink::calibrate
