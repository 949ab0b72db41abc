/// The demlink-run tool as a user runs it: exit codes 0 / 2, summary.csv rows,
/// the field named in the error message, no crash on garbage.
#include <gtest/gtest.h>
#include <sys/wait.h>

#include <cstdlib>

#include "test_support.hpp"

namespace demlink::server {
namespace {

using Result = test::ProgramRun;

Result runTool(const std::vector<std::string>& arguments, const std::filesystem::path& dir) {
  return test::runProgram(DEMLINK_RUN_EXE, arguments, dir);
}

std::size_t lineCount(const std::string& text) { return test::countOccurrences(text, "\n"); }

TEST(DemlinkRun, TinySceneExitsZeroAndWritesOneSummaryRowPerFrame) {
  const test::ScratchDir scratch;
  const std::filesystem::path& dir = scratch.path();
  test::writeText(dir / "tiny.json", test::tinySceneJson(0.01, 0.0025));
  const Result result = runTool({(dir / "tiny.json").string(), "--output", (dir / "out").string()}, dir);
  ASSERT_EQ(result.exit_code, 0) << result.output;
  // Frames at 0, 0.0025, 0.005, 0.0075, 0.01 s, plus the header.
  EXPECT_EQ(lineCount(test::readText(dir / "out" / "summary.csv")), 6u);
  EXPECT_NE(result.output.find("critical time step"), std::string::npos) << "compile report first";
  EXPECT_NE(result.output.find("finished"), std::string::npos) << result.output;
}

TEST(DemlinkRun, EndTimeOverrideAndQuiet) {
  const test::ScratchDir scratch;
  const std::filesystem::path& dir = scratch.path();
  test::writeText(dir / "tiny.json", test::tinySceneJson(0.01, 0.0025));
  const Result result = runTool(
      {(dir / "tiny.json").string(), "--quiet", "--end-time", "0.005", "--output=" + (dir / "out").string()}, dir);
  ASSERT_EQ(result.exit_code, 0) << result.output;
  EXPECT_EQ(lineCount(test::readText(dir / "out" / "summary.csv")), 4u);
  EXPECT_EQ(result.output.find("finished"), std::string::npos) << "--quiet prints no info lines";
}

TEST(DemlinkRun, BadSceneExitsTwoNamingTheField) {
  const test::ScratchDir scratch;
  const std::filesystem::path& dir = scratch.path();
  std::string json = test::tinySceneJson(0.01, 0.0025);
  json.replace(json.find("\"density\": 2500"), 15, "\"density\": -1");
  test::writeText(dir / "bad.json", json);
  const Result result = runTool({(dir / "bad.json").string(), "--output", (dir / "out").string()}, dir);
  EXPECT_EQ(result.exit_code, 2) << result.output;
  EXPECT_NE(result.output.find("error: components[1].material.density = -1: must be > 0"), std::string::npos)
      << result.output;
  EXPECT_FALSE(std::filesystem::exists(dir / "out" / "summary.csv"));
}

/// --check validates without running: nothing is written; a bad value, or a time step
/// above the critical one (found only when the world initialises), exits 2 naming the field.
TEST(DemlinkRun, CheckValidatesWithoutRunning) {
  const test::ScratchDir scratch;
  const std::filesystem::path& dir = scratch.path();
  const std::string good = test::tinySceneJson(0.01, 0.0025);
  test::writeText(dir / "good.json", good);
  const Result valid = runTool({"--check", (dir / "good.json").string(), "--output", (dir / "out").string()}, dir);
  EXPECT_EQ(valid.exit_code, 0) << valid.output;
  EXPECT_NE(valid.output.find("good.json: valid"), std::string::npos) << valid.output;
  EXPECT_FALSE(std::filesystem::exists(dir / "out")) << "--check writes nothing";

  std::string bad = good;
  bad.replace(bad.find("\"density\": 2500"), 15, "\"density\": -1");
  test::writeText(dir / "bad.json", bad);
  const Result invalid = runTool({"--check", (dir / "bad.json").string()}, dir);
  EXPECT_EQ(invalid.exit_code, 2) << invalid.output;
  EXPECT_NE(invalid.output.find("components[1].material.density = -1"), std::string::npos) << invalid.output;

  std::string unsafe = good;
  const std::size_t at = unsafe.find("\"time_step\"");
  ASSERT_NE(at, std::string::npos) << unsafe;
  unsafe.replace(at, unsafe.find_first_of(",}", at) - at, "\"time_step\": 0.01");
  test::writeText(dir / "unsafe.json", unsafe);
  const Result tooLarge = runTool({"--check", (dir / "unsafe.json").string()}, dir);
  EXPECT_EQ(tooLarge.exit_code, 2) << tooLarge.output;
  EXPECT_NE(tooLarge.output.find("time_step = 0.01"), std::string::npos) << tooLarge.output;
}

TEST(DemlinkRun, BadInputNeverCrashes) {
  const test::ScratchDir scratch;
  const std::filesystem::path& dir = scratch.path();
  test::writeText(dir / "garbage.json", std::string("\x7f\x45\x4c\x46\x00\xff{[\"", 9));
  test::writeText(dir / "typo.json", R"({"components": [{"name": "b", "simulation_box": {"end_tme": 1}}]})");
  const std::string typoScene = (dir / "typo.json").string();
  EXPECT_EQ(runTool({(dir / "garbage.json").string()}, dir).exit_code, 2);
  const Result typo = runTool({typoScene}, dir);
  EXPECT_EQ(typo.exit_code, 2);
  EXPECT_NE(typo.output.find("end_tme"), std::string::npos) << typo.output;
  EXPECT_EQ(runTool({(dir / "missing.json").string()}, dir).exit_code, 2);
  EXPECT_EQ(runTool({}, dir).exit_code, 2) << "no scene";
  EXPECT_EQ(runTool({typoScene, "--frobnicate"}, dir).exit_code, 2);
  EXPECT_EQ(runTool({typoScene, "--end-time", "-1"}, dir).exit_code, 2);
  EXPECT_EQ(runTool({typoScene, "--end-time"}, dir).exit_code, 2);
  EXPECT_EQ(runTool({typoScene, "second.json"}, dir).exit_code, 2);
  EXPECT_EQ(runTool({"--help"}, dir).exit_code, 0);
}

TEST(DemlinkRun, BadViewCapsExitTwoNamingTheOption) {
  const test::ScratchDir scratch;
  const std::filesystem::path& dir = scratch.path();
  test::writeText(dir / "tiny.json", test::tinySceneJson(1e-4, 1e-4));
  const std::string scene = (dir / "tiny.json").string();
  const std::vector<std::pair<std::vector<std::string>, std::string>> cases = {
      {{"--view-max-connections", "0"}, "--view-max-connections = 0: not a whole number in 1..1024"},
      {{"--view-max-connections", "2.5"}, "--view-max-connections = 2.5"},
      {{"--view-max-rate", "0"}, "--view-max-rate = 0: frames per second must be > 0 and <= 120"},
      {{"--view-max-rate", "500"}, "--view-max-rate = 500"},
      {{"--view-max-bytes-per-second", "10"}, "--view-max-bytes-per-second = 10: must be >= 1000"},
      {{"--view-max-bytes-per-second", "inf"}, "--view-max-bytes-per-second = inf: not a number"},
  };
  for (const auto& [option, expected] : cases) {
    std::vector<std::string> arguments{scene, "--view", "0"};
    arguments.insert(arguments.end(), option.begin(), option.end());
    const Result result = runTool(arguments, dir);
    EXPECT_EQ(result.exit_code, 2) << option.front() << "\n" << result.output;
    EXPECT_NE(result.output.find("error: " + expected), std::string::npos) << result.output;
  }
  // A cap without --view is a mistake, not a silent no-op.
  const Result alone = runTool({scene, "--view-max-connections", "4"}, dir);
  EXPECT_EQ(alone.exit_code, 2);
  EXPECT_NE(alone.output.find("--view-max-connections requires --view"), std::string::npos) << alone.output;
}

}  // namespace
}  // namespace demlink::server
