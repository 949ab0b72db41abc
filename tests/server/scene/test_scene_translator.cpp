/// The scene compiler: structure checks, field paths in errors, defaults,
/// references between components, file paths relative to the scene.
#include <algorithm>

#include <gtest/gtest.h>

#include "demlink/core/walls/mesh_body.hpp"
#include "demlink/core/geometry/stl_reader.hpp"

#include "demlink/core/base/input_error.hpp"
#include "demlink/server/scene/scene_loader.hpp"
#include "demlink/server/scene/scene_translator.hpp"
#include "test_support.hpp"
#include "scene_test_support.hpp"

namespace demlink::server {
namespace {

constexpr const char* kBox = R"({"name": "box", "simulation_box": {"end_time": 0.1}})";
constexpr const char* kGlass = R"({"name": "glass", "material": {}})";

using test::sceneOf;

/// Translates and returns the InputError (fails the test if none is thrown).
core::InputError translationError(const v1::Scene& scene, const std::filesystem::path& dir = {}) {
  try {
    (void)translateScene(scene, dir);
  } catch (const core::InputError& error) {
    return error;
  }
  ADD_FAILURE() << "expected an InputError";
  return core::InputError("(none)", "", "");
}

TEST(SceneTranslator, OmittedValuesTakeEngineDefaults) {
  const TranslatedScene t = translateScene(sceneOf({kBox, kGlass}), {});
  const core::SimulationSettings defaults;
  const core::Material material;
  EXPECT_EQ(t.world.settings().time_step, defaults.time_step);
  EXPECT_EQ(t.world.settings().gravity, defaults.gravity);
  EXPECT_EQ(t.world.settings().max_impact_velocity, defaults.max_impact_velocity);
  EXPECT_EQ(t.world.settings().contact_model, core::ContactModel::HertzMindlin);
  EXPECT_EQ(t.world.settings().integrator, core::IntegratorKind::VelocityVerlet);
  EXPECT_FALSE(t.world.settings().bounds.has_value());
  ASSERT_EQ(t.world.materials().size(), 1u);
  EXPECT_EQ(t.world.materials()[0].name, "glass") << "material name defaults to the component name";
  EXPECT_EQ(t.world.materials()[0].density, material.density);
  EXPECT_EQ(t.world.materials()[0].youngs_modulus, material.youngs_modulus);
  EXPECT_EQ(t.run.end_time, 0.1);
  EXPECT_EQ(t.run.progress_interval, 2.0);
  EXPECT_EQ(t.run.field_prefix, "components[0].simulation_box");
}

TEST(SceneTranslator, ExplicitValuesAreUsed) {
  const TranslatedScene t = translateScene(
      sceneOf({R"({"name": "m", "material": {"name": "steel", "density": 7800, "rolling_friction": 0.1}})",
               R"({"name": "box", "simulation_box": {"end_time": 2, "time_step": 1e-6, "gravity": {},
                   "contact_model": "LINEAR_SPRING_DASHPOT", "integrator": "EXPLICIT_EULER",
                   "bounds": {"lower": {"x": -1, "y": -1, "z": -1}, "upper": {"x": 1, "y": 1, "z": 1}},
                   "output": {"directory": "res", "vtk_interval": 0.5, "progress_interval_s": 7}}})"}),
      {});
  EXPECT_EQ(t.world.settings().time_step, 1e-6);
  EXPECT_EQ(t.world.settings().gravity, core::Vec3::Zero()) << "an explicit empty vector is zero gravity";
  EXPECT_EQ(t.world.settings().contact_model, core::ContactModel::LinearSpringDashpot);
  EXPECT_EQ(t.world.settings().integrator, core::IntegratorKind::ExplicitEuler);
  ASSERT_TRUE(t.world.settings().bounds.has_value());
  EXPECT_EQ(t.world.settings().bounds->upper, core::Vec3(1, 1, 1));
  EXPECT_EQ(t.world.materials()[0].name, "steel");
  EXPECT_EQ(t.world.materials()[0].density, 7800.0);
  EXPECT_EQ(t.world.materials()[0].rolling_friction, 0.1);
  EXPECT_EQ(t.run.output_directory, "res");
  EXPECT_EQ(t.run.vtk_interval, 0.5);
  EXPECT_EQ(t.run.progress_interval, 7.0);
  EXPECT_EQ(t.run.field_prefix, "components[1].simulation_box");
}

TEST(SceneTranslator, MissingSimulationBoxIsAnError) {
  const core::InputError error = translationError(sceneOf({kGlass}));
  EXPECT_EQ(error.field(), "components");
  EXPECT_NE(std::string(error.what()).find("found 0"), std::string::npos) << error.what();
}

TEST(SceneTranslator, TwoSimulationBoxesAreAnError) {
  const core::InputError error = translationError(
      sceneOf({kBox, kGlass, R"({"name": "box2", "simulation_box": {"end_time": 1}})"}));
  EXPECT_EQ(error.field(), "components");
  const std::string message = error.what();
  EXPECT_NE(message.find("found 2"), std::string::npos) << message;
  EXPECT_NE(message.find("components[2]"), std::string::npos) << message;
}

TEST(SceneTranslator, UnknownMaterialNamesComponentAndField) {
  const core::InputError error = translationError(sceneOf(
      {kBox, kGlass, R"({"name": "steel", "material": {}})",
       R"({"name": "floor", "plane": {"normal": {"z": 1}, "material": "stel"}})"}));
  EXPECT_EQ(error.field(), "components[3].plane.material");
  EXPECT_EQ(error.value(), "\"stel\"");
  EXPECT_NE(std::string(error.what()).find("unknown material"), std::string::npos) << error.what();
}

TEST(SceneTranslator, MaterialMayBeDeclaredAfterItsUse) {
  const TranslatedScene t = translateScene(
      sceneOf({R"({"name": "floor", "plane": {"normal": {"z": 2}, "material": "glass"}})", kBox, kGlass}), {});
  ASSERT_EQ(t.world.planes().size(), 1u);
  EXPECT_NEAR(t.world.planes()[0].spec.normal.z(), 1.0, 1e-15) << "normal is normalised";
}

TEST(SceneTranslator, InvalidMaterialValuesNameTheField) {
  const core::InputError density =
      translationError(sceneOf({kBox, R"({"name": "glass", "material": {"density": -2500}})"}));
  EXPECT_EQ(density.field(), "components[1].material.density");

  const core::InputError youngs =
      translationError(sceneOf({kGlass, kBox, R"({"name": "rubber", "material": {"youngs_modulus": 0}})"}));
  EXPECT_EQ(youngs.field(), "components[2].material.youngs_modulus");
}

TEST(SceneTranslator, NamesMustBeUniqueAndPresent) {
  EXPECT_EQ(translationError(sceneOf({kBox, kGlass, R"({"name": "glass", "material": {"name": "other"}})"})).field(),
            "components[2].name");
  EXPECT_EQ(translationError(sceneOf({kBox, R"({"material": {}})"})).field(), "components[1].name");
  EXPECT_EQ(translationError(sceneOf({kBox, kGlass, R"({"name": "x", "material": {"name": "glass"}})"})).field(),
            "components[2].material.name");
  EXPECT_EQ(translationError(sceneOf({kBox, R"({"name": "empty"})"})).field(), "components[1]");
}

TEST(SceneTranslator, SimulationBoxFieldsAreValidated) {
  EXPECT_EQ(translationError(sceneOf({R"({"name": "b", "simulation_box": {"end_time": 1, "time_step": -1}})"}))
                .field(),
            "components[0].simulation_box.time_step");
  EXPECT_EQ(translationError(sceneOf({kGlass, R"({"name": "b", "simulation_box": {}})"})).field(),
            "components[1].simulation_box.end_time");
  EXPECT_EQ(translationError(sceneOf({R"({"name": "b", "simulation_box": {"end_time": 1,
                "bounds": {"lower": {"x": 1}, "upper": {"x": 0, "y": 1, "z": 1}}}})"}))
                .field(),
            "components[0].simulation_box.bounds.upper[0]");
  EXPECT_EQ(translationError(sceneOf({R"({"name": "b", "simulation_box": {"end_time": 1, "bounds": {}}})"})).field(),
            "components[0].simulation_box.bounds.lower");
  EXPECT_EQ(translationError(sceneOf({R"({"name": "b", "simulation_box": {"end_time": "NaN"}})"})).field(),
            "components[0].simulation_box.end_time");
}

TEST(SceneTranslator, PlaneWithoutNormalIsAnError) {
  EXPECT_EQ(translationError(sceneOf({kBox, kGlass, R"({"name": "p", "plane": {"material": "glass"}})"})).field(),
            "components[2].plane.normal");
}

TEST(SceneTranslator, LatticeIsGeneratedAndValidated) {
  const TranslatedScene t = translateScene(
      sceneOf({kBox, kGlass, R"({"name": "s", "particle_lattice": {"material": "glass", "radius": 0.001,
               "spacing": 0.003, "counts": {"nx": 2, "ny": 3, "nz": 4}, "velocity": {"z": -1}}})"}),
      {});
  ASSERT_EQ(t.world.particles().size(), 24u);
  EXPECT_EQ(t.world.particles().velocity[5], core::Vec3(0, 0, -1));

  EXPECT_EQ(translationError(sceneOf({kBox, kGlass, R"({"name": "s", "particle_lattice": {"material": "glass",
               "radius": 0.002, "spacing": 0.003, "counts": {"nx": 1, "ny": 1, "nz": 1}}})"}))
                .field(),
            "components[2].particle_lattice.spacing");
  EXPECT_EQ(translationError(sceneOf({kBox, kGlass, R"({"name": "s", "particle_lattice": {"material": "glass",
               "radius": 0.001, "spacing": 0.003}})"}))
                .field(),
            "components[2].particle_lattice.counts");
}

TEST(SceneTranslator, ParticleFileIsRelativeToTheSceneDirectory) {
  const test::ScratchDir scratch;
  const std::filesystem::path& dir = scratch.path();
  std::filesystem::create_directories(dir / "data");
  test::writeText(dir / "data" / "init.txt", "# id x y z r\n1 0.01 0.02 0.03 0.002\n2 0.05 0.02 0.03 0.0025\n");
  const v1::Scene scene =
      sceneOf({kBox, kGlass, R"({"name": "bed", "particle_file": {"path": "data/init.txt", "material": "glass"}})"});
  const TranslatedScene t = translateScene(scene, dir);
  ASSERT_EQ(t.world.particles().size(), 2u);
  EXPECT_EQ(t.world.particles().position[1], core::Vec3(0.05, 0.02, 0.03));
  EXPECT_EQ(t.world.particles().radius[1], 0.0025);

  const core::InputError missing = translationError(scene, dir / "elsewhere");
  EXPECT_NE(std::string(missing.what()).find("not found"), std::string::npos) << missing.what();
}

TEST(SceneTranslator, MeshBodyIsLoadedPlacedAndMoving) {
  const test::ScratchDir scratch;
  const std::filesystem::path& dir = scratch.path();
  const core::TriangleMesh box = core::axisAlignedBoxMesh(core::Vec3(0, 0, 0), core::Vec3(0.1, 0.2, 0.3));
  core::writeStlBinary((dir / "part.stl").string(), box.vertices, box.triangles);
  const v1::Scene scene = sceneOf({kBox, kGlass, R"({"name": "bucket", "mesh_body": {"stl_file": "part.stl",
      "material": "glass", "position": {"x": 1.0}, "reference_point": {"x": 0.05},
      "linear_velocity": {"z": -0.5}}})"});
  TranslatedScene translated = translateScene(scene, dir);
  ASSERT_EQ(translated.world.meshes().size(), 1u);
  const core::MeshBody& mesh = translated.world.meshes()[0];
  EXPECT_EQ(mesh.name(), "bucket");
  EXPECT_EQ(mesh.triangles().size(), 12u);
  // The file's x = 0.05 (reference point) sits at world x = 1.0: x in [0.95, 1.05].
  double minX = 1e9;
  double maxX = -1e9;
  for (const core::Vec3& v : mesh.worldVertices()) {
    minX = std::min(minX, v.x());
    maxX = std::max(maxX, v.x());
  }
  // Binary STL stores float32 coordinates: 1e-7 relative.
  EXPECT_NEAR(minX, 0.95, 1e-7);
  EXPECT_NEAR(maxX, 1.05, 1e-7);
  EXPECT_EQ(mesh.linearVelocity(), core::Vec3(0, 0, -0.5));

  test::writeText(dir / "empty.stl", "solid x\nendsolid x\n");
  const v1::Scene empty =
      sceneOf({kBox, kGlass, R"({"name": "bucket", "mesh_body": {"stl_file": "empty.stl", "material": "glass"}})"});
  const core::InputError error = translationError(empty, dir);
  EXPECT_EQ(error.field(), "components[2].mesh_body.stl_file");
  const core::InputError missing = translationError(scene, dir / "elsewhere");
  EXPECT_EQ(missing.field(), "components[2].mesh_body.stl_file");
}

TEST(SceneTranslator, MeshBodyDeclarationIsTranslated) {
  const test::ScratchDir scratch;
  const std::filesystem::path& dir = scratch.path();
  test::writeText(dir / "part.stl", "solid x\nendsolid x\n");
  v1::MeshBody mesh;
  mesh.set_stl_file("part.stl");
  mesh.mutable_orientation()->set_w(2.0);
  mesh.mutable_orientation()->set_z(2.0);
  mesh.mutable_position()->set_x(1.5);
  mesh.mutable_reference_point()->set_y(-0.25);
  const MeshBodyDeclaration d = translateMeshBody(mesh, "bucket", 3, dir, "components[4].mesh_body");
  EXPECT_EQ(d.name, "bucket");
  EXPECT_EQ(d.material, 3u);
  EXPECT_EQ(d.stl_file, dir / "part.stl");
  EXPECT_NEAR(d.orientation.norm(), 1.0, 1e-15);
  EXPECT_NEAR(d.orientation.w(), std::sqrt(0.5), 1e-15);
  EXPECT_EQ(d.position, core::Vec3(1.5, 0, 0));
  EXPECT_EQ(d.reference_point, core::Vec3(0, -0.25, 0));

  mesh.mutable_orientation()->Clear();
  try {
    (void)translateMeshBody(mesh, "bucket", 0, dir, "components[4].mesh_body");
    FAIL() << "a zero quaternion must be refused";
  } catch (const core::InputError& error) {
    EXPECT_EQ(error.field(), "components[4].mesh_body.orientation");
  }
}

TEST(SceneTranslator, ExampleDepositionSceneTranslates) {
  const std::filesystem::path scenes = std::filesystem::path(DEMLINK_EXAMPLES_DIR) / "scenes";
  const TranslatedScene t = translateScene(loadSceneFile((scenes / "deposition_small.json").string()), scenes);
  EXPECT_GE(t.world.particles().size(), 1000u);
  EXPECT_EQ(t.world.planes().size(), 5u);
  EXPECT_GT(t.run.end_time, 0.0);
}

TEST(SceneTranslator, EveryExampleSceneTranslates) {
  // Each example must stay valid as the schema and the engine evolve.
  const std::filesystem::path scenes = std::filesystem::path(DEMLINK_EXAMPLES_DIR) / "scenes";
  std::size_t count = 0;
  for (const auto& entry : std::filesystem::directory_iterator(scenes)) {
    if (entry.path().extension() != ".json") continue;
    SCOPED_TRACE(entry.path().string());
    TranslatedScene t = translateScene(loadSceneFile(entry.path().string()), scenes);
    // A scene starts with particles, or a source inserts them during the run.
    const bool hasSource = std::ranges::any_of(
        t.world.components(), [](const auto& component) { return component->kind() == "particle_source"; });
    EXPECT_TRUE(t.world.particles().size() > 0 || hasSource);
    EXPECT_NO_THROW(t.world.initialize());
    ++count;
  }
  EXPECT_GE(count, 2u);
}

TEST(SceneTranslator, ChuteExampleHasAMovingMesh) {
  const std::filesystem::path scenes = std::filesystem::path(DEMLINK_EXAMPLES_DIR) / "scenes";
  TranslatedScene t = translateScene(loadSceneFile((scenes / "chute_and_paddle.json").string()), scenes);
  ASSERT_EQ(t.world.meshes().size(), 2u);
  EXPECT_EQ(t.world.meshes()[0].triangles().size(), 36u);
  EXPECT_EQ(t.world.meshes()[1].angularVelocity(), core::Vec3(0, 0, 1.0));
  t.world.initialize();
  const core::Vec3 start = t.world.meshes()[1].position();
  for (int n = 0; n < 1000; ++n) t.world.step();
  EXPECT_NEAR((t.world.meshes()[1].position() - start).x(), -0.1 * t.world.time(), 1e-12);
}

}  // namespace
}  // namespace demlink::server
