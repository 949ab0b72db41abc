// The checkpoint format is a promise to files already on disk: a checkpoint of the
// golden scene must equal, byte for byte, the one the engine wrote when the golden
// file was made (golden/README.md), the golden file must restore and continue
// exactly like the run that never stopped, and a file of another format version
// must be refused with both version numbers in the message.
#include <cstring>
#include <fstream>
#include <sstream>

#include <gtest/gtest.h>

#include "demlink/core/base/input_error.hpp"
#include "demlink/core/checkpoint_file.hpp"
#include "demlink/core/state/state_stream.hpp"
#include "checkpoint_test_support.hpp"
#include "state/golden_scene.hpp"

namespace demlink::core {
namespace {

const std::string kGoldenPath = std::string(DEMLINK_SOURCE_DIR) + "/tests/core/state/golden/checkpoint_v3.bin";

std::string goldenBytes() {
  std::ifstream in(kGoldenPath, std::ios::binary);
  EXPECT_TRUE(in) << "cannot open " << kGoldenPath;
  std::ostringstream bytes;
  bytes << in.rdbuf();
  return bytes.str();
}

/// "" when equal, else where the first difference is: offset and the top-level
/// section holding it (header bytes come before the first section).
std::string firstDifference(const std::string& actual, const std::string& expected) {
  if (actual == expected) return "";
  std::size_t at = 0;
  while (at < actual.size() && at < expected.size() && actual[at] == expected[at]) ++at;
  std::string section = "header";
  std::size_t start = 8 + 3 * sizeof(std::uint32_t) + sizeof(double);
  while (start + 12 <= expected.size() && start <= at) {
    std::uint64_t length = 0;
    std::memcpy(&length, expected.data() + start + 4, sizeof length);
    if (at < start + 12 + length) {
      section = expected.substr(start, 4);
      break;
    }
    start += 12 + length;
  }
  return "sizes " + std::to_string(actual.size()) + " and " + std::to_string(expected.size()) +
         ", first difference at byte " + std::to_string(at) + " in section \"" + section + "\"";
}

std::unique_ptr<World> goldenWorld() {
  auto world = test::buildGoldenScene();
  for (int n = 0; n < test::kGoldenSteps; ++n) world->step();
  return world;
}

TEST(CheckpointGolden, NewCheckpointEqualsTheGoldenFileByteForByte) {
  const std::string golden = goldenBytes();
  ASSERT_GT(golden.size(), 1000u);
  EXPECT_EQ(firstDifference(test::saveToBytes(*goldenWorld()), golden), "");
}

TEST(CheckpointGolden, GoldenFileRestoresAndContinuesBitIdentically) {
  const std::string golden = goldenBytes();
  const auto uninterrupted = goldenWorld();
  const auto restored = test::buildGoldenScene();
  restored->restoreCheckpoint(std::string_view(golden), "golden.bin");
  EXPECT_EQ(firstDifference(test::saveToBytes(*restored), golden), "");
  for (int n = 0; n < 400; ++n) {
    uninterrupted->step();
    restored->step();
  }
  EXPECT_TRUE(test::differingColumns(*uninterrupted, *restored).empty());
  EXPECT_EQ(firstDifference(test::saveToBytes(*restored), test::saveToBytes(*uninterrupted)), "");
}

TEST(CheckpointGolden, AnotherFormatVersionIsRefusedNamingBoth) {
  const std::string golden = goldenBytes();
  for (const std::uint32_t version : {kCheckpointVersion - 1, kCheckpointVersion + 1, 77u}) {
    SCOPED_TRACE(version);
    std::string file = golden;
    std::memcpy(file.data() + 8, &version, sizeof version);
    const auto world = test::buildGoldenScene();
    const std::string before = test::saveToBytes(*world);
    try {
      world->restoreCheckpoint(std::string_view(file), "old.bin");
      ADD_FAILURE() << "accepted format version " << version;
    } catch (const InputError& e) {
      EXPECT_EQ(e.field(), "old.bin:header");
      EXPECT_EQ(e.value(), std::to_string(version));
      EXPECT_NE(std::string(e.what()).find("reads version " + std::to_string(kCheckpointVersion)), std::string::npos)
          << e.what();
    }
    EXPECT_EQ(test::saveToBytes(*world), before) << "a refused file changed the world";
  }
}

}  // namespace
}  // namespace demlink::core
