/// Scene translation of the materials family: database materials with explicit
/// overrides, unknown database names, material_pair components and their errors.
#include <gtest/gtest.h>

#include <algorithm>
#include <ostream>

#include "demlink/core/base/input_error.hpp"
#include "demlink/core/materials/material_database.hpp"
#include "demlink/server/scene/scene_loader.hpp"
#include "demlink/server/scene/scene_translator.hpp"
#include "scene_test_support.hpp"
#include "test_support.hpp"

namespace demlink::server {
namespace {

constexpr const char* kBox = R"({"name": "box", "simulation_box": {"end_time": 0.1}})";

using test::sceneOf;

core::InputError translationError(const v1::Scene& scene) {
  try {
    (void)translateScene(scene, {});
  } catch (const core::InputError& error) {
    return error;
  }
  ADD_FAILURE() << "expected an InputError";
  return core::InputError("(none)", "", "");
}

TEST(TranslateMaterials, DatabaseValuesWithExplicitOverride) {
  const TranslatedScene t = translateScene(
      sceneOf({kBox, R"({"name": "grain", "material": {"database_name": "Wheat", "restitution": 0.7}})",
               R"({"name": "stones", "material": {"database_name": "gravel"}})"}),
      {});
  const core::MaterialDatabase& db = core::MaterialDatabase::builtIn();
  const core::Material& wheat = db.at("wheat", "test").material;
  const core::Material& gravel = db.at("gravel", "test").material;
  ASSERT_EQ(t.world.materials().size(), 2u);
  const core::Material& grain = t.world.materials()[0];
  EXPECT_EQ(grain.name, "grain") << "the name is the component's, not the database's";
  EXPECT_EQ(grain.restitution, 0.7) << "explicit field overrides the database";
  EXPECT_NE(wheat.restitution, 0.7) << "test needs an override that differs from the database";
  EXPECT_EQ(grain.density, wheat.density);
  EXPECT_EQ(grain.youngs_modulus, wheat.youngs_modulus);
  EXPECT_EQ(grain.poisson_ratio, wheat.poisson_ratio);
  EXPECT_EQ(grain.sliding_friction, wheat.sliding_friction);
  EXPECT_EQ(grain.rolling_friction, wheat.rolling_friction);
  const core::Material& stones = t.world.materials()[1];
  EXPECT_EQ(stones.density, gravel.density);
  EXPECT_EQ(stones.restitution, gravel.restitution);
  EXPECT_EQ(stones.rolling_friction, gravel.rolling_friction);
}

TEST(TranslateMaterials, CustomMaterialsKeepEngineDefaults) {
  const TranslatedScene t = translateScene(sceneOf({kBox, R"({"name": "m", "material": {"density": 7800}})"}), {});
  const core::Material defaults;
  EXPECT_EQ(t.world.materials()[0].density, 7800.0);
  EXPECT_EQ(t.world.materials()[0].restitution, defaults.restitution);
}

TEST(TranslateMaterials, UnknownDatabaseNameNamesFieldAndListsKnownNames) {
  const core::InputError e =
      translationError(sceneOf({kBox, R"({"name": "m", "material": {"database_name": "granite"}})"}));
  EXPECT_EQ(e.field(), "components[1].material.database_name");
  const std::string what = e.what();
  for (const char* name : {"gravel", "sand", "hard_coal", "brown_coal", "iron_ore", "potash", "corn", "wheat"}) {
    EXPECT_NE(what.find(name), std::string::npos) << name << " missing from: " << what;
  }
}

TEST(TranslateMaterials, OverrideOfDatabaseValueIsValidated) {
  const core::InputError e = translationError(
      sceneOf({kBox, R"({"name": "m", "material": {"database_name": "sand", "restitution": 1.5}})"}));
  EXPECT_EQ(e.field(), "components[1].material.restitution");
}

TEST(TranslateMaterials, MaterialPairReachesThePairTable) {
  TranslatedScene t = translateScene(
      sceneOf({R"({"name": "pair", "material_pair": {"material_a": "wheat", "material_b": "gravel",
                  "restitution": 0.2, "sliding_friction": 0.9}})",
               kBox, R"({"name": "wheat", "material": {"database_name": "wheat"}})",
               R"({"name": "gravel", "material": {"database_name": "gravel"}})"}),
      {});
  t.world.initialize();
  const core::ContactPairParams& p = t.world.pairTable()(0, 1);
  EXPECT_EQ(p.restitution, 0.2);
  EXPECT_EQ(p.sliding_friction, 0.9);
  const core::Material& wheat = t.world.materials()[0];
  const core::Material& gravel = t.world.materials()[1];
  EXPECT_EQ(p.rolling_friction, 0.5 * (wheat.rolling_friction + gravel.rolling_friction)) << "not overridden";
  EXPECT_EQ(t.world.pairTable()(0, 0).restitution, wheat.restitution);
  EXPECT_EQ(t.world.pairTable()(1, 1).restitution, gravel.restitution);
}

TEST(TranslateMaterials, CohesionFromAMaterialTheDatabaseAndAPair) {
  TranslatedScene t = translateScene(
      sceneOf({kBox, R"({"name": "soil", "material": {"database_name": "moist_soil"}})",
               R"({"name": "clay", "material": {"cohesion_energy_density": 4e4}})",
               R"({"name": "steel", "material": {"youngs_modulus": 2e8}})",
               R"({"name": "pair", "material_pair": {"material_a": "steel", "material_b": "clay",
                  "cohesion_energy_density": 1e3}})",
               R"({"name": "soil_on_steel", "material_pair": {"material_a": "soil", "material_b": "steel",
                  "restitution": 0.3}})"}),
      {});
  t.world.initialize();
  EXPECT_GT(t.world.materials()[0].cohesion_energy_density, 0.0) << "moist_soil is cohesive";
  EXPECT_EQ(t.world.pairTable()(1, 1).cohesion_energy_density, 4e4);
  EXPECT_EQ(t.world.pairTable()(0, 2).cohesion_energy_density, 0.5 * t.world.materials()[0].cohesion_energy_density)
      << "mean of soil and (dry) steel";
  EXPECT_EQ(t.world.pairTable()(1, 2).cohesion_energy_density, 1e3) << "the pair's own value";
  const std::vector<std::string> stages = t.world.activeStages();
  EXPECT_NE(std::find(stages.begin(), stages.end(), "cohesion"), stages.end());
  EXPECT_EQ(translationError(sceneOf({kBox, R"({"name": "wet", "material": {"cohesion_energy_density": -1}})"}))
                .field(),
            "components[1].material.cohesion_energy_density");
}

struct PairError {
  const char* what;
  std::string pair;   ///< material_pair JSON body
  std::string field;  ///< expected error field
};

void PrintTo(const PairError& c, std::ostream* os) { *os << c.what; }

class MaterialPairErrors : public ::testing::TestWithParam<PairError> {};

TEST_P(MaterialPairErrors, NameTheField) {
  const PairError& c = GetParam();
  const core::InputError e = translationError(sceneOf(
      {kBox, R"({"name": "a", "material": {}})", R"({"name": "b", "material": {}})",
       R"({"name": "p1", "material_pair": {"material_a": "a", "material_b": "b", "restitution": 0.4}})",
       R"({"name": "p2", "material_pair": )" + c.pair + "}"}));
  EXPECT_EQ(e.field(), c.field) << e.what();
}

INSTANTIATE_TEST_SUITE_P(
    Cases, MaterialPairErrors,
    ::testing::Values(
        PairError{"unknown_a", R"({"material_a": "steel", "material_b": "a", "restitution": 0.4})",
                  "components[4].material_pair.material_a"},
        PairError{"unknown_b", R"({"material_a": "a", "material_b": "stel", "restitution": 0.4})",
                  "components[4].material_pair.material_b"},
        PairError{"missing_b", R"({"material_a": "a", "restitution": 0.4})", "components[4].material_pair.material_b"},
        PairError{"bad_restitution", R"({"material_a": "a", "material_b": "a", "restitution": 0})",
                  "components[4].material_pair.restitution"},
        PairError{"bad_friction", R"({"material_a": "a", "material_b": "a", "sliding_friction": -1})",
                  "components[4].material_pair.sliding_friction"},
        PairError{"bad_rolling", R"({"material_a": "a", "material_b": "a", "rolling_friction": -0.1})",
                  "components[4].material_pair.rolling_friction"},
        PairError{"nothing", R"({"material_a": "a", "material_b": "a"})", "components[4].material_pair"},
        PairError{"duplicate", R"({"material_a": "b", "material_b": "a", "sliding_friction": 0.1})",
                  "components[4].material_pair.material_b"}),
    [](const ::testing::TestParamInfo<PairError>& param) { return std::string(param.param.what); });


// A user's materials file (simulation_box.materials_file): its entries are found by
// database_name beside the built-in ones; a bad file or a built-in name again is an
// error naming the box's field, then the file's line and column.
constexpr const char* kUserMaterials =
    "name,density,youngs_modulus,poisson_ratio,restitution,sliding_friction,rolling_friction,size_kind,"
    "radius_min,radius_max,source\n"
    "my sand,2600,3e7,0.28,0.35,0.62,0.21,uniform,0.001,0.0015,\"lab: shear box, 2026\"\n";

core::InputError translationError(const v1::Scene& scene, const FileScope& files) {
  try {
    (void)translateScene(scene, files);
  } catch (const core::InputError& error) {
    return error;
  }
  ADD_FAILURE() << "expected an InputError";
  return core::InputError("(none)", "", "");
}

std::string boxWithMaterialsFile(const std::string& file) {
  return R"({"name": "box", "simulation_box": {"end_time": 0.1, "materials_file": ")" + file + "\"}}";
}

TEST(TranslateMaterials, UserMaterialsFileEntriesJoinTheBuiltInDatabase) {
  const test::ScratchDir scratch;
  test::writeText(scratch.path() / "my_materials.csv", kUserMaterials);
  const TranslatedScene t = translateScene(
      sceneOf({boxWithMaterialsFile("my_materials.csv"),
               R"({"name": "mine", "material": {"database_name": "My-Sand", "restitution": 0.4}})",
               R"({"name": "grain", "material": {"database_name": "wheat"}})"}),
      FileScope(scratch.path()));
  ASSERT_EQ(t.world.materials().size(), 2u);
  const core::Material& mine = t.world.materials()[0];
  EXPECT_EQ(mine.name, "mine");
  EXPECT_EQ(mine.density, 2600.0);
  EXPECT_EQ(mine.youngs_modulus, 3e7);
  EXPECT_EQ(mine.poisson_ratio, 0.28);
  EXPECT_EQ(mine.sliding_friction, 0.62);
  EXPECT_EQ(mine.rolling_friction, 0.21);
  EXPECT_EQ(mine.restitution, 0.4) << "an explicit field still overrides the file's value";
  EXPECT_EQ(t.world.materials()[1].density, core::MaterialDatabase::builtIn().at("wheat", "test").material.density);
}

TEST(TranslateMaterials, UserMaterialsFileErrorsNameTheFieldTheFileAndTheValue) {
  const test::ScratchDir scratch;
  const FileScope files(scratch.path());
  const std::string mine = R"({"name": "mine", "material": {"database_name": "my_sand"}})";
  const std::string field = "components[0].simulation_box.materials_file";

  const core::InputError missing = translationError(sceneOf({boxWithMaterialsFile("absent.csv"), mine}), files);
  EXPECT_EQ(missing.field(), field);
  EXPECT_NE(missing.reason().find("not found"), std::string::npos) << missing.what();

  test::writeText(scratch.path() / "bad.csv",
                  std::string(kUserMaterials) + "soft,-5,1e7,0.3,0.5,0.5,0,uniform,0.001,0.002,estimate\n");
  const core::InputError bad = translationError(sceneOf({boxWithMaterialsFile("bad.csv"), mine}), files);
  EXPECT_EQ(bad.field(), field);
  EXPECT_EQ(bad.value(), "-5");
  EXPECT_NE(bad.reason().find("bad.csv:3.density"), std::string::npos) << bad.what();

  test::writeText(scratch.path() / "clash.csv",
                  std::string(kUserMaterials) + "Wheat,1300,1e7,0.4,0.5,0.4,0.05,uniform,0.0018,0.0024,mine\n");
  const core::InputError clash = translationError(sceneOf({boxWithMaterialsFile("clash.csv"), mine}), files);
  EXPECT_EQ(clash.field(), field);
  EXPECT_EQ(clash.value(), "\"Wheat\"");
  EXPECT_NE(clash.reason().find("clash.csv:3.name"), std::string::npos) << clash.what();
  EXPECT_NE(clash.reason().find("built-in"), std::string::npos) << clash.what();

  const core::InputError unknown = translationError(
      sceneOf({boxWithMaterialsFile("my_materials.csv"),
               R"({"name": "m", "material": {"database_name": "granite"}})"}),
      [&] {
        test::writeText(scratch.path() / "my_materials.csv", kUserMaterials);
        return files;
      }());
  EXPECT_EQ(unknown.field(), "components[1].material.database_name");
  EXPECT_NE(unknown.reason().find("my sand"), std::string::npos) << "the known names include the file's: "
                                                                  << unknown.what();
}

}  // namespace
}  // namespace demlink::server
