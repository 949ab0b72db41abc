/// Translation of parallel_bonds: a good declaration reaches the engine with its values
/// and makes its bonds at create_time, every bad field is named with its value, and a
/// headless run writes the bond network beside the particle frames.
#include <gtest/gtest.h>

#include "demlink/core/base/input_error.hpp"
#include "demlink/server/run/headless_runner.hpp"
#include "demlink/server/scene/scene_translator.hpp"
#include "scene_test_support.hpp"
#include "test_support.hpp"

namespace demlink::server {
namespace {

const std::filesystem::path kScenes = std::filesystem::path(DEMLINK_EXAMPLES_DIR) / "scenes";

constexpr const char* kBox = R"({"name": "box", "simulation_box": {"time_step": 1e-6, "end_time": 2e-4,
    "gravity": {}, "restitution_tolerance": 0.2, "output": {"vtk_interval": 1e-4, "progress_interval_s": 60}}})";
constexpr const char* kRock = R"({"name": "rock", "material": {"density": 2500, "youngs_modulus": 1e7}})";
constexpr const char* kSand = R"({"name": "sand", "material": {"density": 2500, "youngs_modulus": 1e7}})";
// 3 x 3 x 1 spheres, 10 um apart: 12 neighbouring pairs.
constexpr const char* kLattice = R"({"name": "grains", "particle_lattice": {"material": "rock", "radius": 0.001,
    "spacing": 0.00201, "origin": {"z": 0.01}, "counts": {"nx": 3, "ny": 3, "nz": 1}}})";

/// A parallel_bonds declaration: valid values for the required fields, replaced or
/// extended by `fields` (a JSON fragment of "key": value pairs).
std::string bonds(const std::string& fields) {
  const std::vector<std::pair<std::string, std::string>> defaults{
      {"normal_stiffness_per_area", "1e11"}, {"shear_stiffness_per_area", "5e10"}, {"tensile_strength", "1e6"},
      {"shear_strength", "2e6"}, {"gap_tolerance", "2e-5"}};
  std::string text = R"({"name": "cement", "parallel_bonds": {)" + fields;
  bool first = fields.empty();
  for (const auto& [key, value] : defaults) {
    if (fields.find("\"" + key + "\"") != std::string::npos) continue;
    text += (first ? "" : ", ") + ("\"" + key + "\": " + value);
    first = false;
  }
  return text + "}}";
}

core::InputError errorOf(const std::string& fields) {
  try {
    TranslatedScene t = translateScene(test::sceneOf({kBox, kRock, kSand, kLattice, bonds(fields)}), kScenes);
    t.world.initialize();
  } catch (const core::InputError& error) {
    return error;
  }
  ADD_FAILURE() << "expected an InputError for " << fields;
  return core::InputError("(none)", "", "");
}

TEST(TranslateBonds, GoodDeclarationReachesTheEngineAndBondsAtCreateTime) {
  TranslatedScene t = translateScene(
      test::sceneOf({kBox, kRock, kSand, kLattice,
                     bonds(R"("create_time": 5e-5, "radius_multiplier": 0.8, "fraction": 1, "seed": 3,
                              "materials": ["rock"],
                              "region": {"box": {"centre": {"z": 0.01}, "size": {"x": 1, "y": 1, "z": 1}}})")}),
      kScenes);
  const core::BondSet& set = t.world.bonds();
  ASSERT_EQ(set.rules().size(), 1u);
  const core::BondRule& rule = set.rules()[0];
  EXPECT_EQ(rule.name, "cement");
  EXPECT_EQ(rule.properties.normal_stiffness_per_area, 1e11);
  EXPECT_EQ(rule.properties.shear_stiffness_per_area, 5e10);
  EXPECT_EQ(rule.properties.tensile_strength, 1e6);
  EXPECT_EQ(rule.properties.shear_strength, 2e6);
  EXPECT_EQ(rule.properties.gap_tolerance, 2e-5);
  EXPECT_EQ(rule.properties.radius_multiplier, 0.8);
  EXPECT_EQ(rule.create_step, 50u);
  EXPECT_EQ(rule.seed, 3u);
  ASSERT_EQ(rule.materials.size(), 1u);
  EXPECT_TRUE(rule.region.has_value());
  t.world.advance(49);
  EXPECT_EQ(set.bonds().size(), 0u) << "no bond before create_time";
  t.world.advance(1);
  EXPECT_EQ(set.counts().intact, 12u);
}

TEST(TranslateBonds, EveryBadFieldIsNamedWithItsValue) {
  const std::string prefix = "components[4].parallel_bonds.";
  const struct {
    std::string fields;
    std::string field;
  } cases[] = {
      {R"("normal_stiffness_per_area": -1)", "normal_stiffness_per_area"},
      {R"("shear_stiffness_per_area": 0)", "shear_stiffness_per_area"},
      {R"("tensile_strength": 0)", "tensile_strength"},
      {R"("shear_strength": -5)", "shear_strength"},
      {R"("radius_multiplier": 2)", "radius_multiplier"},
      {R"("gap_tolerance": -1e-6)", "gap_tolerance"},
      {R"("fraction": 1.5)", "fraction"},
      {R"("create_time": -1)", "create_time"},
      {R"("materials": ["rock", "clay"])", "materials[1]"},
      {R"("region": {"box": {"size": {"x": 0, "y": 1, "z": 1}}})", "region.box.size.x"},
      {R"("region": {"sphere": {"radius": -1}})", "region.sphere.radius"},
      {R"("region": {"attached_to": "bucket", "sphere": {"radius": 1}})", "region.attached_to"},
  };
  for (const auto& c : cases) {
    const core::InputError error = errorOf(c.fields);
    EXPECT_EQ(error.field(), prefix + c.field) << c.fields << ": " << error.what();
    EXPECT_FALSE(error.value().empty()) << c.fields;
  }
  EXPECT_EQ(errorOf(R"("tensile_strength": -3)").value(), "-3");
}

TEST(TranslateBonds, HeadlessRunWritesTheBondNetwork) {
  const test::ScratchDir scratch;
  TranslatedScene t = translateScene(test::sceneOf({kBox, kRock, kLattice, bonds("")}), kScenes);
  t.run.output_directory = scratch.path().string();
  (void)runHeadless(t);
  // Frames at 0, 1e-4 and 2e-4 s: the first before the bonds are made.
  const std::string first = test::readText(scratch.path() / "bonds_000000.vtp");
  const std::string last = test::readText(scratch.path() / "bonds_000002.vtp");
  EXPECT_NE(first.find("NumberOfLines=\"0\""), std::string::npos) << first.substr(0, 400);
  EXPECT_NE(last.find("NumberOfLines=\"12\""), std::string::npos) << last.substr(0, 400);
  for (const char* array : {"normal_force", "shear_force", "intact", "tensile_stress"}) {
    EXPECT_NE(last.find(std::string("Name=\"") + array + "\""), std::string::npos) << array;
  }
  EXPECT_NE(test::readText(scratch.path() / "bonds.pvd").find("bonds_000002.vtp"), std::string::npos);
}

/// A small pit (0.12 x 0.12 m, r = 10 mm) whose clods `cement` joins; `clods` is a JSON
/// fragment of the pit's clod fields.
std::string clodPit(const std::string& clods) {
  return R"({"name": "pit", "pit_generator": {"material": "rock", "sizes": {"radius": 0.01},
      "lower": {"x": -0.06, "y": -0.06}, "upper": {"x": 0.06, "y": 0.06, "z": 0.1}, "target_height": 0.05,
      "seed": "3", "max_settle_time": 0.3)" + (clods.empty() ? std::string() : ", " + clods) + "}}";
}

constexpr const char* kPitBox = R"({"name": "box", "simulation_box": {"time_step": 2e-5, "end_time": 1e-3,
    "gravity": {"z": -9.81}, "restitution_tolerance": 0.2, "max_impact_velocity": 1,
    "output": {"vtk_interval": 1e-3, "progress_interval_s": 60}}})";
constexpr const char* kBedSensor = R"({"name": "bed", "region_sensor": {"sample_every_steps": 10,
    "region": {"box": {"size": {"x": 1, "y": 1, "z": 1}}}}})";

TEST(TranslateBonds, PitClodsAreBondedByTheirRuleAndCountedInTheRunSummaryAndSensor) {
  const test::ScratchDir scratch;
  TranslatedScene t = translateScene(
      test::sceneOf({kPitBox, kRock, clodPit(R"("clod_fraction": 0.5, "clod_radius": 0.025, "clod_bonds": "cement")"),
                     bonds(R"("normal_stiffness_per_area": 1e9, "shear_stiffness_per_area": 1e9,
                              "gap_tolerance": 0.001)"),
                     kBedSensor}),
      kScenes);
  const core::BondRule& rule = t.world.bonds().rules().at(0);
  ASSERT_TRUE(rule.groups.has_value()) << "the clods' rule bonds within clods only";
  ASSERT_FALSE(rule.groups->empty());
  const double grouped = static_cast<double>(rule.groups->size()) / static_cast<double>(t.world.particles().size());
  EXPECT_NEAR(grouped, 0.5, 0.02);
  t.run.output_directory = scratch.path().string();
  const RunSummary summary = runHeadless(t);
  const core::BondCounts& counts = t.world.bonds().counts();
  EXPECT_GT(counts.created(), 0u);
  EXPECT_EQ(summary.bonds_created, counts.created());
  EXPECT_EQ(summary.bonds_broken, counts.broken);
  for (const core::ParallelBond& bond : t.world.bonds().bonds()) {
    ASSERT_EQ(rule.groups->at(bond.id_a), rule.groups->at(bond.id_b)) << "no bond between two clods";
  }
  // The sensor over everything counts every bond, in its CSV file too.
  const std::string csv = test::readText(scratch.path() / "region_sensor_bed.csv");
  ASSERT_NE(csv.find(",bonds_intact,bonds_broken"), std::string::npos) << csv.substr(0, 200);
  const std::string lastRow = csv.substr(csv.rfind('\n', csv.size() - 2) + 1);
  const std::string lastTwo = lastRow.substr(lastRow.rfind(',', lastRow.rfind(',') - 1) + 1);
  EXPECT_EQ(lastTwo, std::to_string(counts.intact) + "," + std::to_string(counts.broken) + "\n") << lastRow;
}

TEST(TranslateBonds, BadClodFieldsAreNamedWithTheirValues) {
  const auto errorOfPit = [](const std::string& clods, const std::string& bondsName) {
    try {
      std::string rule = bonds("");
      rule.replace(rule.find("cement"), 6, bondsName);
      (void)translateScene(test::sceneOf({kPitBox, kRock, clodPit(clods), rule}), kScenes, SceneUse::CosimCheck);
    } catch (const core::InputError& error) {
      return error.field() + " = " + error.value();
    }
    return std::string("(accepted)");
  };
  const std::string prefix = "components[2].pit_generator.";
  EXPECT_EQ(errorOfPit(R"("clod_fraction": 0.3, "clod_radius": 0.02, "clod_bonds": "cement")", "cement"),
            "(accepted)");
  EXPECT_EQ(errorOfPit(R"("clod_fraction": 1.2, "clod_radius": 0.02, "clod_bonds": "cement")", "cement"),
            prefix + "clod_fraction = 1.2");
  EXPECT_EQ(errorOfPit(R"("clod_fraction": 0.3, "clod_radius": -0.02, "clod_bonds": "cement")", "cement"),
            prefix + "clod_radius = -0.02");
  EXPECT_EQ(errorOfPit(R"("clod_fraction": 0.3, "clod_radius": 0.02)", "cement"), prefix + "clod_bonds = \"\"");
  EXPECT_EQ(errorOfPit(R"("clod_fraction": 0.3, "clod_radius": 0.02, "clod_bonds": "glue")", "cement"),
            prefix + "clod_bonds = \"glue\"");
  EXPECT_EQ(errorOfPit(R"("clod_radius": 0.02)", "cement"), prefix + "clod_radius = 0.02");
  EXPECT_EQ(errorOfPit(R"("clod_bonds": "cement")", "cement"), prefix + "clod_bonds = \"cement\"");
}

}  // namespace
}  // namespace demlink::server
