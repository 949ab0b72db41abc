/// The headless runner: frames on exact steps, .pvd / summary.csv consistent with
/// them, start-up errors named by their scene path.
#include <gtest/gtest.h>

#include "demlink/core/input_error.hpp"
#include "demlink/server/run/headless_runner.hpp"
#include "demlink/server/scene/scene_loader.hpp"
#include "test_support.hpp"

namespace demlink::server {
namespace {

std::vector<std::string> lines(const std::string& text) {
  std::vector<std::string> out;
  std::istringstream in(text);
  for (std::string line; std::getline(in, line);) out.push_back(line);
  return out;
}

TEST(HeadlessRunner, WritesAFramePerIntervalPlusFirstAndLast) {
  const test::ScratchDir scratch;
  const std::filesystem::path& dir = scratch.path();
  TranslatedScene scene = translateScene(parseSceneJson(test::tinySceneJson(0.01, 0.003), "tiny"), {});
  scene.run.output_directory = (dir / "out").string();
  const RunSummary summary = runHeadless(scene);

  // Frames at steps 0, 300, 600, 900 and the end (1000).
  EXPECT_EQ(summary.steps, 1000u);
  EXPECT_EQ(summary.frames, 5u);
  EXPECT_NEAR(summary.final_time, 0.01, 1e-12);
  EXPECT_EQ(summary.final_particles, 8u);
  const std::vector<std::string> csv = lines(test::readText(dir / "out" / "summary.csv"));
  ASSERT_EQ(csv.size(), 6u);
  EXPECT_EQ(csv[0], "time_s,particles,kinetic_energy_J,mean_z_m,max_z_m,neighbour_builds,wall_s");
  EXPECT_EQ(csv[1].rfind("0,8,0,", 0), 0u) << csv[1];
  EXPECT_EQ(csv[2].rfind("0.003,8,", 0), 0u) << csv[2];
  EXPECT_EQ(csv[5].rfind("0.01,8,", 0), 0u) << csv[5];

  const std::string pvd = test::readText(dir / "out" / "particles.pvd");
  EXPECT_EQ(test::countOccurrences(pvd, "<DataSet "), 5u);
  for (int k = 0; k < 5; ++k) {
    const std::string file = "particles_00000" + std::to_string(k) + ".vtp";
    EXPECT_NE(pvd.find("file=\"" + file + "\""), std::string::npos) << file;
    EXPECT_TRUE(std::filesystem::exists(dir / "out" / file)) << file;
  }
  const std::string planes = test::readText(dir / "out" / "planes.vtp");
  EXPECT_NE(planes.find("NumberOfPolys=\"2\""), std::string::npos) << "one plane = one quad = two triangles";
}

TEST(HeadlessRunner, ParticlesFallUnderGravity) {
  const test::ScratchDir scratch;
  const std::filesystem::path& dir = scratch.path();
  TranslatedScene scene = translateScene(parseSceneJson(test::tinySceneJson(0.01, 0.0), "tiny"), {});
  scene.run.output_directory = dir.string();
  const double zBefore = scene.world.particles().position[7].z();
  const RunSummary summary = runHeadless(scene);
  EXPECT_EQ(summary.frames, 2u) << "vtk_interval 0: first and last frame only";
  EXPECT_GT(summary.final_kinetic_energy, 0.0);
  EXPECT_LT(scene.world.particles().position[7].z(), zBefore);
}

TEST(HeadlessRunner, TimeStepAboveTheLimitNamesTheSceneField) {
  std::string json = test::tinySceneJson(0.01, 0.0);
  json.replace(json.find("1e-5"), 4, "1e-3");
  TranslatedScene scene = translateScene(parseSceneJson(json, "tiny"), {});
  const test::ScratchDir scratch;
  scene.run.output_directory = scratch.path().string();
  try {
    (void)runHeadless(scene);
    FAIL() << "dt = 1e-3 s is far above the critical limit";
  } catch (const core::InputError& error) {
    EXPECT_EQ(error.field(), "components[0].simulation_box.time_step");
    EXPECT_EQ(error.value(), "0.001");
    EXPECT_NE(std::string(error.what()).find("critical limit"), std::string::npos) << error.what();
  }
}

TEST(HeadlessRunner, RefusesAnEndTimeShorterThanAStepAndAMissingDirectory) {
  TranslatedScene scene = translateScene(parseSceneJson(test::tinySceneJson(0.01, 0.0), "tiny"), {});
  EXPECT_THROW((void)runHeadless(scene), core::InputError) << "no output directory";
  const test::ScratchDir scratch;
  scene.run.output_directory = scratch.path().string();
  scene.run.end_time = 1e-7;
  try {
    (void)runHeadless(scene);
    FAIL();
  } catch (const core::InputError& error) {
    EXPECT_EQ(error.field(), "components[0].simulation_box.end_time");
  }
}

}  // namespace
}  // namespace demlink::server
