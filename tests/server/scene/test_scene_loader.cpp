/// Scene files: JSON <-> demlink.v1.Scene, strict parsing, presence of optional fields.
#include <google/protobuf/util/message_differencer.h>
#include <gtest/gtest.h>

#include "demlink/core/base/input_error.hpp"
#include "demlink/server/scene/scene_loader.hpp"
#include "test_support.hpp"

namespace demlink::server {
namespace {

v1::Scene everyKindScene() {
  v1::Scene scene;
  auto* box = scene.add_components();
  box->set_name("box");
  v1::SimulationBox* sb = box->mutable_simulation_box();
  sb->set_time_step(2.5e-6);
  sb->set_end_time(0.75);
  sb->mutable_gravity()->set_y(-3.0);
  sb->set_contact_model(v1::SimulationBox::LINEAR_SPRING_DASHPOT);
  sb->set_integrator(v1::SimulationBox::EXPLICIT_EULER);
  sb->set_neighbour_skin(4e-4);
  sb->set_max_impact_velocity(0.0);  // explicitly zero: must survive the round trip as "set"
  sb->set_linear_normal_stiffness(1.5e4);
  sb->set_allow_unsafe_time_step(true);
  sb->mutable_bounds()->mutable_lower()->set_x(-1.0);
  sb->mutable_bounds()->mutable_upper()->set_z(2.0);
  sb->mutable_output()->set_directory("results/run 1");
  sb->mutable_output()->set_vtk_interval(0.01);
  sb->mutable_output()->set_progress_interval_s(0.5);

  auto* material = scene.add_components();
  material->set_name("steel");
  material->mutable_material()->set_density(7800.0);
  material->mutable_material()->set_rolling_friction(0.01);

  auto* plane = scene.add_components();
  plane->set_name("floor");
  plane->mutable_plane()->mutable_normal()->set_z(1.0);
  plane->mutable_plane()->set_material("steel");

  auto* mesh = scene.add_components();
  mesh->set_name("bucket");
  v1::MeshBody* mb = mesh->mutable_mesh_body();
  mb->set_stl_file("meshes/bucket.stl");
  mb->set_material("steel");
  mb->mutable_orientation()->set_w(0.5);
  mb->mutable_orientation()->set_z(0.5);
  mb->mutable_reference_point()->set_x(0.1);

  auto* lattice = scene.add_components();
  lattice->set_name("spheres");
  v1::ParticleLattice* pl = lattice->mutable_particle_lattice();
  pl->set_material("steel");
  pl->set_radius(0.002);
  pl->set_radius_max(0.003);
  pl->set_spacing(0.0065);
  pl->mutable_counts()->set_nx(3);
  pl->mutable_counts()->set_ny(4);
  pl->mutable_counts()->set_nz(5);
  pl->set_seed(18446744073709551615ULL);  // needs the string form of uint64 in JSON
  pl->mutable_velocity()->set_z(-1.0);

  auto* file = scene.add_components();
  file->set_name("bed");
  file->mutable_particle_file()->set_path("init_5000.txt");
  file->mutable_particle_file()->set_material("steel");
  return scene;
}

TEST(SceneLoader, JsonRoundTripPreservesEveryField) {
  const v1::Scene original = everyKindScene();
  const test::ScratchDir scratch;
  const std::filesystem::path& dir = scratch.path();
  const std::string json = sceneToJson(original);
  EXPECT_NE(json.find("\"simulation_box\""), std::string::npos) << "scene files use the proto field names";
  test::writeText(dir / "scene.json", json);

  const v1::Scene loaded = loadSceneFile((dir / "scene.json").string());
  std::string difference;
  google::protobuf::util::MessageDifferencer differencer;
  differencer.ReportDifferencesToString(&difference);
  EXPECT_TRUE(differencer.Compare(original, loaded)) << difference;
  EXPECT_TRUE(loaded.components(0).simulation_box().has_max_impact_velocity());
  EXPECT_EQ(loaded.components(4).particle_lattice().seed(), 18446744073709551615ULL);
}

TEST(SceneLoader, OmittedOptionalScalarsAreNotSet) {
  const v1::Scene scene = parseSceneJson(R"({"components": [
      {"name": "box", "simulation_box": {"end_time": 1}},
      {"name": "m", "material": {"density": 0}}]})",
                                         "inline");
  const v1::SimulationBox& box = scene.components(0).simulation_box();
  EXPECT_FALSE(box.has_time_step());
  EXPECT_FALSE(box.has_max_impact_velocity());
  EXPECT_FALSE(box.has_gravity());
  EXPECT_TRUE(scene.components(1).material().has_density()) << "an explicit 0 must be distinguishable";
  EXPECT_FALSE(scene.components(1).material().has_youngs_modulus());
}

TEST(SceneLoader, AcceptsLowerCamelCaseNames) {
  const v1::Scene scene =
      parseSceneJson(R"({"components": [{"name": "box", "simulationBox": {"timeStep": 2e-5, "endTime": 1}}]})",
                     "inline");
  EXPECT_DOUBLE_EQ(scene.components(0).simulation_box().time_step(), 2e-5);
}

TEST(SceneLoader, UnknownFieldIsAnErrorNamingIt) {
  const test::ScratchDir scratch;
  const std::filesystem::path& dir = scratch.path();
  const std::string path = (dir / "typo.json").string();
  test::writeText(dir / "typo.json",
                  R"({"components": [{"name": "box", "simulation_box": {"time_stepp": 1e-5}}]})");
  try {
    (void)loadSceneFile(path);
    FAIL() << "an unknown field must be refused";
  } catch (const core::InputError& error) {
    EXPECT_EQ(error.field(), path);
    const std::string message = error.what();
    EXPECT_NE(message.find("time_stepp"), std::string::npos) << message;
    EXPECT_NE(message.find("components[0].simulation_box"), std::string::npos) << message;
  }
}

TEST(SceneLoader, InvalidJsonAndBadEnumAreInputErrors) {
  EXPECT_THROW((void)parseSceneJson("{\"components\": [", "broken"), core::InputError);
  EXPECT_THROW((void)parseSceneJson("", "empty"), core::InputError);
  try {
    (void)parseSceneJson(R"({"components": [{"name": "b", "simulation_box": {"contact_model": "HERTZ"}}]})", "s");
    FAIL() << "an unknown enum value must be refused";
  } catch (const core::InputError& error) {
    EXPECT_NE(std::string(error.what()).find("contact_model"), std::string::npos) << error.what();
  }
}

TEST(SceneLoader, MissingFileIsAnInputError) {
  const test::ScratchDir scratch;
  const std::filesystem::path& dir = scratch.path();
  const std::string path = (dir / "nope.json").string();
  try {
    (void)loadSceneFile(path);
    FAIL() << "a missing file must be refused";
  } catch (const core::InputError& error) {
    EXPECT_EQ(error.field(), "scene file");
    EXPECT_NE(std::string(error.what()).find(path), std::string::npos) << error.what();
    EXPECT_NE(std::string(error.what()).find("no such file"), std::string::npos) << error.what();
  }
  EXPECT_THROW((void)loadSceneFile(dir.string()), core::InputError) << "a directory is not a scene file";
}

TEST(SceneLoader, ExampleScenesParse) {
  const std::filesystem::path examples = std::filesystem::path(DEMLINK_EXAMPLES_DIR) / "scenes";
  std::size_t count = 0;
  for (const auto& entry : std::filesystem::directory_iterator(examples)) {
    if (entry.path().extension() != ".json") continue;
    SCOPED_TRACE(entry.path().string());
    EXPECT_NO_THROW((void)loadSceneFile(entry.path().string()));
    ++count;
  }
  EXPECT_GE(count, 1u);
}

}  // namespace
}  // namespace demlink::server
