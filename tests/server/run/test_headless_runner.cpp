/// The headless runner: frames on exact steps, .pvd / summary.csv consistent with
/// them, start-up errors named by their scene path.
#include <gtest/gtest.h>

#include <cmath>

#include "demlink/core/base/input_error.hpp"
#include "demlink/core/checkpoint_file.hpp"
#include "demlink/core/step/watchdog.hpp"
#include "demlink/server/run/headless_runner.hpp"
#include "demlink/server/scene/scene_loader.hpp"
#include "csv_test_support.hpp"
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

/// A state that turns non-finite is never written. With the watchdog off (every_steps 0)
/// the writers stop the run themselves: the frame due after the NaN appears is refused, the
/// final checkpoint of that state is not written, and every file already on disk is finite.
/// With the watchdog on, it stops the run first, with the same outcome on disk.
TEST(HeadlessRunner, NonFiniteStateIsNeverWritten) {
  for (const char* watchdog : {"0", "100"}) {
    SCOPED_TRACE(std::string("watchdog every_steps ") + watchdog);
    const test::ScratchDir scratch;
    const std::filesystem::path& dir = scratch.path();
    std::string json = test::tinySceneJson(0.01, 0.003);
    json.replace(json.find(R"("restitution_tolerance": 0.2,)"), 29,
                 std::string(R"("restitution_tolerance": 0.2, "watchdog": {"every_steps": )") + watchdog + "},");
    TranslatedScene scene = translateScene(parseSceneJson(json, "tiny"), {});
    scene.run.output_directory = dir.string();
    core::World& world = scene.world;
    const auto poison = [&](const core::World& seen) {
      if (seen.stepCount() == 450) world.particles().velocity[3].x() = std::nan("");
    };
    try {
      (void)runHeadless(scene, poison);
      ADD_FAILURE() << "the run went on with a NaN velocity";
    } catch (const core::SimulationFault& fault) {
      EXPECT_EQ(fault.check(), "non_finite");
      EXPECT_NE(std::string(fault.what()).find("particle"), std::string::npos) << fault.what();
    }
    // Frames at steps 0 and 300 only, both finite; no final checkpoint of the NaN state.
    EXPECT_TRUE(std::filesystem::exists(dir / "particles_000001.vtp"));
    EXPECT_FALSE(std::filesystem::exists(dir / "particles_000002.vtp"));
    EXPECT_FALSE(std::filesystem::exists(dir / core::kFinalCheckpointFileName));
    for (const auto& entry : std::filesystem::directory_iterator(dir)) {
      const std::string extension = entry.path().extension().string();
      if (extension != ".csv" && extension != ".pvd" && extension != ".txt") continue;  // the text files
      const std::string text = test::readText(entry.path());
      EXPECT_EQ(text.find("nan"), std::string::npos) << entry.path();
      EXPECT_EQ(text.find("inf"), std::string::npos) << entry.path();
    }
  }
}

/// Every file of a run's output folder states a value that does not exist as an empty
/// cell, never as "nan" or "inf": a region sensor that is empty at every sample, one that
/// holds every particle, and a tracker of an id no particle has yet, in a scene with
/// contacts output. Every CSV row has its header's column count.
TEST(HeadlessRunner, NoOutputFileSpellsANonFiniteNumber) {
  const test::ScratchDir scratch;
  const std::filesystem::path& dir = scratch.path();
  std::string json = test::tinySceneJson(0.003, 0.001);
  json.replace(json.find("\n  ]}"), 5, R"(,
    {"name": "empty", "region_sensor": {"sample_every_steps": 50,
      "region": {"box": {"centre": {"x": 1}, "size": {"x": 0.01, "y": 0.01, "z": 0.01}}}}},
    {"name": "all", "region_sensor": {"sample_every_steps": 50,
      "region": {"box": {"size": {"x": 1, "y": 1, "z": 1}}}}},
    {"name": "watch", "tracker": {"sample_every_steps": 50, "particle_ids": [1, 99]}}
  ]})");
  json.replace(json.find(R"("progress_interval_s": 60)"), 25,
               R"("progress_interval_s": 60, "contact_interval": 0.001)");
  TranslatedScene scene = translateScene(parseSceneJson(json, "tiny"), {});
  scene.run.output_directory = dir.string();
  (void)runHeadless(scene);

  std::size_t emptyCells = 0;
  std::size_t csvFiles = 0;
  for (const auto& entry : std::filesystem::directory_iterator(dir)) {
    const std::string extension = entry.path().extension().string();
    if (extension == ".csv") {
      ++csvFiles;
      const auto rows = core::test::readCsvRows(entry.path());
      ASSERT_GE(rows.size(), 1u) << entry.path() << ": no header";
      for (std::size_t r = 0; r < rows.size(); ++r) {
        // run_log.csv quotes values with commas; the others are plain numbers.
        if (entry.path().filename() != "run_log.csv") {
          ASSERT_EQ(rows[r].size(), rows[0].size()) << entry.path() << r;
        }
        for (const std::string& cell : rows[r]) {
          EXPECT_FALSE(core::test::spellsNonFinite(cell)) << entry.path() << " row " << r << ": " << cell;
          emptyCells += cell.empty() ? 1 : 0;
        }
      }
    } else if (extension == ".pvd" || extension == ".txt") {
      const std::string text = test::readText(entry.path());
      EXPECT_EQ(text.find("nan"), std::string::npos) << entry.path();
      EXPECT_EQ(text.find("inf"), std::string::npos) << entry.path();
    }
  }
  EXPECT_TRUE(std::filesystem::exists(dir / "region_sensor_empty.csv"));
  EXPECT_TRUE(std::filesystem::exists(dir / "contacts_000001.csv"));
  EXPECT_GE(csvFiles, 7u) << "summary, run log, two sensors, tracker, contacts";
  // 7 samples x (6 of the empty sensor + 12 of the absent particle) at least.
  EXPECT_GE(emptyCells, 7u * 18u) << "the missing values are there, as empty cells";
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
