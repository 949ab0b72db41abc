/// The output folder policy: a non-empty folder is refused unless overwrite, naming the
/// folder and --overwrite; co-simulation folders sim_NNN never reuse an existing one, so
/// a restarted server does not overwrite the previous server's results.
#include <gtest/gtest.h>

#include "cosim_test_support.hpp"
#include "demlink/core/base/input_error.hpp"
#include "demlink/server/run/headless_runner.hpp"
#include "demlink/server/run/output_directory.hpp"
#include "demlink/server/scene/scene_loader.hpp"
#include "test_support.hpp"

namespace demlink::server {
namespace {

TEST(OutputDirectory, NonEmptyFolderIsRefusedUnlessOverwrite) {
  const test::ScratchDir scratch;
  const std::filesystem::path dir = scratch.path() / "run";
  claimOutputDirectory(dir, false, "box.output.directory");  // missing: created
  EXPECT_TRUE(std::filesystem::is_directory(dir));
  claimOutputDirectory(dir, false, "box.output.directory");  // empty: fine
  test::writeText(dir / "summary.csv", "earlier run\n");
  try {
    claimOutputDirectory(dir, false, "box.output.directory");
    FAIL() << "a folder with an earlier run's files must be refused";
  } catch (const core::InputError& error) {
    EXPECT_EQ(error.field(), "box.output.directory");
    EXPECT_EQ(error.value(), "\"" + dir.string() + "\"");
    EXPECT_NE(std::string(error.what()).find("not empty"), std::string::npos) << error.what();
    EXPECT_NE(std::string(error.what()).find("--overwrite"), std::string::npos) << error.what();
  }
  claimOutputDirectory(dir, true, "box.output.directory");
  EXPECT_EQ(test::readText(dir / "summary.csv"), "earlier run\n") << "claiming deletes nothing";
  test::writeText(scratch.path() / "file", "x");
  EXPECT_THROW(claimOutputDirectory(scratch.path() / "file", false, "f"), core::InputError) << "a file, not a folder";
}

TEST(OutputDirectory, HeadlessRunRefusesToRerunIntoItsFolderUnlessOverwrite) {
  const test::ScratchDir scratch;
  const std::filesystem::path out = scratch.path() / "out";
  auto run = [&](bool overwrite) {
    TranslatedScene scene = translateScene(parseSceneJson(test::tinySceneJson(0.001, 0.0), "tiny"), {});
    scene.run.output_directory = out.string();
    scene.run.overwrite = overwrite;
    return runHeadless(scene);
  };
  EXPECT_EQ(run(false).frames, 2u);
  const std::string first = test::readText(out / "run_log.csv");
  try {
    (void)run(false);
    FAIL() << "the second run would overwrite the first";
  } catch (const core::InputError& error) {
    EXPECT_EQ(error.field(), "components[0].simulation_box.output.directory");
    EXPECT_NE(std::string(error.what()).find("--overwrite"), std::string::npos) << error.what();
  }
  EXPECT_EQ(test::readText(out / "run_log.csv"), first) << "the refused run wrote nothing";
  EXPECT_EQ(run(true).frames, 2u);
}

TEST(OutputDirectory, SimulationFoldersSkipEveryExistingNumber) {
  const test::ScratchDir scratch;
  const std::filesystem::path root = scratch.path() / "cosim";
  EXPECT_EQ(claimSimulationDirectory(root, 1), 1u);
  EXPECT_TRUE(std::filesystem::is_directory(root / "sim_001"));
  EXPECT_EQ(claimSimulationDirectory(root, 1), 2u) << "sim_001 exists (even empty)";
  std::filesystem::create_directories(root / "sim_003");
  EXPECT_EQ(claimSimulationDirectory(root, 2), 4u);
  EXPECT_EQ(simulationDirectory(root, 1234), root / "sim_1234");
}

/// One simulation of a small bed to its end step with the host's output root `root`.
std::filesystem::path runSimulation(const std::filesystem::path& root, bool overwrite = false) {
  test::CosimHarness h(root, v1::Scene(), std::filesystem::path(), overwrite);
  h.hello(1);
  h.declare(1, test::boxJson(1e-5, 2e-4, R"("coupling": {"expected_count": 4})"));
  for (const std::string& c : test::smallBedJson()) h.declare(1, c);
  EXPECT_TRUE(h.compiled(1));
  EXPECT_TRUE(h.finished(1)) << "no exchanged component: the world runs to the end step at once";
  return h.finished(1) ? std::filesystem::path(h.finished(1)->output_directory()) : std::filesystem::path();
}

TEST(OutputDirectory, RestartedServerDoesNotOverwriteTheLastServersSimulation) {
  const test::ScratchDir scratch;
  const std::filesystem::path root = scratch.path() / "cosim";
  EXPECT_EQ(runSimulation(root), root / "sim_001");
  const std::string first = test::readText(root / "sim_001" / "run_log.csv");
  // A new host (a restarted server) numbers its first simulation 1 again.
  EXPECT_EQ(runSimulation(root), root / "sim_002");
  EXPECT_EQ(test::readText(root / "sim_001" / "run_log.csv"), first);
  EXPECT_TRUE(std::filesystem::exists(root / "sim_002" / "checkpoint_final.bin"));
  // Told to overwrite, it writes into sim_001 as servers did before.
  EXPECT_EQ(runSimulation(root, true), root / "sim_001");
  EXPECT_FALSE(std::filesystem::exists(root / "sim_003"));
}

}  // namespace
}  // namespace demlink::server
