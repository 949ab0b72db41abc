// Checkpoints of scene components: a world with a source inserting during the run, a
// sink, a flow sensor, a region sensor and a tracker, saved and restored into a freshly
// built world, continues bit for bit (every particle column and every component
// reading); the CSV rows a restored world writes continue the uninterrupted file; a
// corrupt component section is an InputError naming the component and section, and a
// failed restore leaves every component as it was.
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "checkpoint_test_support.hpp"
#include "component_scene.hpp"
#include "demlink/core/base/input_error.hpp"

namespace demlink::core {
namespace {

constexpr int kBefore = 1200;  // steps before the checkpoint (a multiple of every sample period)
constexpr int kAfter = 800;    // steps after it

using test::bitEqual;
using test::differingColumns;

std::string save(const World& world) { return test::saveToBytes(world); }

void expectSameReadings(const test::ComponentScene& a, const test::ComponentScene& b) {
  const SourceReport& ra = a.source->report();
  const SourceReport& rb = b.source->report();
  EXPECT_EQ(ra.inserted_count, rb.inserted_count);
  EXPECT_EQ(ra.inserted_mass, rb.inserted_mass);
  EXPECT_EQ(ra.shortfall_count, rb.shortfall_count);
  EXPECT_EQ(ra.requested_count, rb.requested_count);
  EXPECT_EQ(a.sink->total().count, b.sink->total().count);
  EXPECT_EQ(a.sink->total().mass, b.sink->total().mass);
  EXPECT_EQ(a.sink->lastInterval().count, b.sink->lastInterval().count);
  EXPECT_EQ(a.flow->total().negative_count, b.flow->total().negative_count);
  EXPECT_EQ(a.flow->total().negative_mass, b.flow->total().negative_mass);
  EXPECT_EQ(a.flow->total().positive_count, b.flow->total().positive_count);
  EXPECT_EQ(a.flow->trackedCount(), b.flow->trackedCount());
  EXPECT_EQ(a.flow->band(), b.flow->band());
  EXPECT_EQ(a.region->latest().count, b.region->latest().count);
  EXPECT_EQ(a.region->latest().mass, b.region->latest().mass);
  const std::vector<const SampledComponent*> sa{a.sink, a.flow, a.region, a.tracker};
  const std::vector<const SampledComponent*> sb{b.sink, b.flow, b.region, b.tracker};
  for (std::size_t k = 0; k < sa.size(); ++k) {
    SCOPED_TRACE(sa[k]->name());
    EXPECT_EQ(sa[k]->sampleCount(), sb[k]->sampleCount());
    // Bitwise, so that NaN entries (empty region, absent tracked particle) compare too.
    EXPECT_TRUE(bitEqual(sa[k]->latestRow(), sb[k]->latestRow()));
  }
  for (std::size_t k = 0; k < a.tracker->particles().size(); ++k) {
    EXPECT_EQ(a.tracker->particles()[k].status, b.tracker->particles()[k].status);
  }
}

std::vector<std::string> readLines(const std::filesystem::path& path) {
  std::ifstream in(path);
  std::vector<std::string> lines;
  for (std::string line; std::getline(in, line);) lines.push_back(line);
  return lines;
}

/// A fresh directory under the system temp directory, removed at the end.
class TempDir {
 public:
  explicit TempDir(const std::string& name)
      : path_(std::filesystem::temp_directory_path() / (name + "_" + std::to_string(::testing::UnitTest::GetInstance()->random_seed()) + "_" + std::to_string(reinterpret_cast<std::uintptr_t>(this)))) {
    std::filesystem::remove_all(path_);
    std::filesystem::create_directories(path_);
  }
  ~TempDir() {
    std::error_code ec;
    std::filesystem::remove_all(path_, ec);
  }
  TempDir(const TempDir&) = delete;
  TempDir& operator=(const TempDir&) = delete;
  [[nodiscard]] const std::filesystem::path& path() const { return path_; }

 private:
  std::filesystem::path path_;
};

TEST(CheckpointComponents, RestoredWorldWithComponentsContinuesBitIdentically) {
  const TempDir dir("demlink_ckpt_components");
  std::filesystem::create_directories(dir.path() / "a");
  std::filesystem::create_directories(dir.path() / "b");
  test::ComponentScene a = test::buildComponentScene();
  const std::vector<std::filesystem::path> csvA = writeSamplesToCsv(a.world->components(), dir.path() / "a");
  for (int n = 0; n < kBefore; ++n) a.world->step();
  // Every component must have state worth saving at the checkpoint.
  ASSERT_GT(a.source->report().inserted_count, 0u);
  ASSERT_GT(a.sink->total().count, 0u) << "the sink has not removed anything yet";
  ASSERT_GT(a.flow->total().negative_count, 0u) << "nothing crossed the flow sensor yet";
  ASSERT_GT(a.flow->trackedCount(), 0u) << "no particle near the flow sensor";
  ASSERT_GT(a.region->latest().count, 0u);
  const std::string file = save(*a.world);
  for (int n = 0; n < kAfter; ++n) a.world->step();
  ASSERT_GT(a.world->removedAtBounds().count, 0u) << "nothing left over the bounds";

  test::ComponentScene b = test::buildComponentScene();
  b.world->restoreCheckpoint(std::string_view(file), "a.bin");
  EXPECT_TRUE(save(*b.world) == file) << "restoring and saving again reproduces the file";
  const std::vector<std::filesystem::path> csvB = writeSamplesToCsv(b.world->components(), dir.path() / "b");
  for (int n = 0; n < kAfter; ++n) b.world->step();

  ASSERT_EQ(a.world->particles().size(), b.world->particles().size());
  const std::vector<std::string> differing = differingColumns(*a.world, *b.world);
  EXPECT_TRUE(differing.empty()) << "first differing column: " << (differing.empty() ? "" : differing.front());
  EXPECT_EQ(a.world->removedAtBounds().count, b.world->removedAtBounds().count);
  EXPECT_EQ(a.world->removedAtBounds().mass, b.world->removedAtBounds().mass);
  expectSameReadings(a, b);
  EXPECT_TRUE(save(*a.world) == save(*b.world)) << "final checkpoints differ";

  // CSV: the restored world's file is the header, the sample at the checkpoint and
  // every later one, i.e. exactly the uninterrupted file's header and its tail.
  ASSERT_EQ(csvA.size(), csvB.size());
  for (std::size_t k = 0; k < csvA.size(); ++k) {
    SCOPED_TRACE(csvA[k].filename().string());
    const std::vector<std::string> full = readLines(csvA[k]);
    const std::vector<std::string> continued = readLines(csvB[k]);
    ASSERT_GE(continued.size(), 3u);
    ASSERT_LE(continued.size(), full.size());
    EXPECT_EQ(continued.front(), full.front());
    const std::size_t offset = full.size() - continued.size();
    for (std::size_t row = 1; row < continued.size(); ++row) EXPECT_EQ(continued[row], full[offset + row]) << row;
    // The first continued row is the sample taken at the checkpoint's step.
    EXPECT_EQ(continued[1].substr(0, continued[1].find(',')),
              full[offset + 1].substr(0, full[offset + 1].find(',')));
  }
}

/// Offset of the first byte after section tag `tag` and its u64 length.
std::size_t payloadOf(const std::string& file, const char* tag) {
  const std::size_t at = file.find(tag);
  EXPECT_NE(at, std::string::npos) << tag;
  return at + 4 + sizeof(std::uint64_t);
}

/// Restores `file` into a fresh scene and returns the error's field ("" if none).
std::string restoreError(const std::string& file, test::ComponentScene& scene) {
  try {
    scene.world->restoreCheckpoint(std::string_view(file), "a.bin");
  } catch (const InputError& e) {
    return e.field() + " | " + e.what();
  }
  return "";
}

TEST(CheckpointComponents, CorruptComponentDataIsRejectedAndRolledBack) {
  test::ComponentScene a = test::buildComponentScene();
  for (int n = 0; n < 700; ++n) a.world->step();
  ASSERT_GT(a.flow->trackedCount(), 0u);
  ASSERT_GT(a.sink->total().count, 0u);
  const std::string file = save(*a.world);

  struct Case {
    const char* tag;
    std::size_t offset;  // from the payload start
    std::vector<unsigned char> bytes;
    const char* field;   // expected in the error's field
  };
  const std::uint64_t huge = ~std::uint64_t{0} / 4;
  std::vector<unsigned char> hugeBytes(sizeof huge);
  std::memcpy(hugeBytes.data(), &huge, sizeof huge);
  const std::vector<Case> cases{
      // Remembered-particle count of the flow sensor: far more than the bytes left.
      {"FLOW", 8 + 3 * 32, hugeBytes, "a.bin:components.gate.crossings"},
      // All-zero generator state of the source.
      {"SRCE", 0, std::vector<unsigned char>(32, 0), "a.bin:components.src.source"},
      // A tracked particle's status outside {-1, 0, 1}: the tracker is the last
      // component, so the others were loaded before it failed and must be rolled back.
      {"TRAK", 8 + 8, {7, 0, 0, 0}, "a.bin:components.follow.tracked"},
      // Latest-row length of the sink's schedule: longer than the section.
      {"SMPL", 16, hugeBytes, "a.bin:components.drain.schedule"},
      // Negative removed mass of the sink.
      {"SINK", 8, {0, 0, 0, 0, 0, 0, 0xf0, 0xbf}, "a.bin:components.drain.tallies"},
  };
  for (const Case& c : cases) {
    SCOPED_TRACE(c.tag);
    std::string bad = file;
    std::memcpy(bad.data() + payloadOf(file, c.tag) + c.offset, c.bytes.data(), c.bytes.size());
    test::ComponentScene b = test::buildComponentScene();
    const std::string error = restoreError(bad, b);
    EXPECT_NE(error.find(c.field), std::string::npos) << error;
    // Nothing changed: the fresh world and its components are as built.
    EXPECT_EQ(b.world->stepCount(), 0u);
    EXPECT_EQ(b.source->report().inserted_count, 0u);
    EXPECT_EQ(b.sink->total().count, 0u);
    EXPECT_EQ(b.sink->sampleCount(), 1u);
    EXPECT_EQ(b.flow->total().negative_count, 0u);
    // ... and the intact file still restores into it and continues like the original.
    ASSERT_EQ(restoreError(file, b), "");
    EXPECT_EQ(b.sink->total().count, a.sink->total().count);
    EXPECT_TRUE(save(*b.world) == file);
  }
}

TEST(CheckpointComponents, ComponentSectionLongerThanItsDataIsRejected) {
  test::ComponentScene a = test::buildComponentScene();
  for (int n = 0; n < 300; ++n) a.world->step();
  const std::string file = save(*a.world);
  // The source's section claims one byte more than its component's data holds.
  std::string bad = file;
  const std::size_t lengthAt = file.find("SRCE") + 4;
  std::uint64_t length = 0;
  std::memcpy(&length, bad.data() + lengthAt, sizeof length);
  ++length;
  std::memcpy(bad.data() + lengthAt, &length, sizeof length);
  test::ComponentScene b = test::buildComponentScene();
  const std::string error = restoreError(bad, b);
  EXPECT_NE(error.find("a.bin:components.src"), std::string::npos) << error;
  EXPECT_NE(error.find("SRCE"), std::string::npos) << error;
  EXPECT_EQ(b.source->report().inserted_count, 0u);
}

// Run-time inputs in checkpoints: a client halves the source's rate, switches it off and
// on, moves and shrinks the sink and resizes the sensor's box mid-run. The checkpoint after
// that holds them (section INPT), and a world built from the scene and restored from it
// continues bit for bit (insertions, removals, readings). Without the inputs the restored
// world would insert at the scene's rate and remove in the scene's sink.
TEST(CheckpointComponents, RunTimeInputsAreSavedAndRestored) {
  test::ComponentScene a = test::buildComponentScene();
  for (int n = 0; n < kBefore / 2; ++n) a.world->step();
  a.source->setRate(*a.world, 1500.0, "rate");
  a.sink->changeRegion(*a.world, RegionChange{.centre = a.sink->placement().centre + Vec3(0.002, 0.0, 0.0),
                                              .orientation = std::nullopt, .size = std::nullopt, .radius = 0.016},
                       "sink");
  a.region->changeRegion(*a.world, RegionChange{.centre = std::nullopt, .orientation = std::nullopt,
                                                .size = Vec3(0.1, 0.1, 0.05), .radius = std::nullopt},
                         "region");
  for (int n = 0; n < kBefore / 4; ++n) a.world->step();
  a.source->setEnabled(*a.world, false);
  for (int n = 0; n < kBefore / 8; ++n) a.world->step();
  a.source->setEnabled(*a.world, true);
  for (int n = 0; n < kBefore / 8; ++n) a.world->step();
  ASSERT_GT(a.sink->total().count, 0u);
  const std::string file = save(*a.world);
  EXPECT_NE(file.find("INPT"), std::string::npos);
  EXPECT_EQ(save(*test::buildComponentScene().world).find("INPT"), std::string::npos)
      << "a world without inputs writes no INPT section";
  for (int n = 0; n < kAfter; ++n) a.world->step();

  test::ComponentScene b = test::buildComponentScene();
  b.world->restoreCheckpoint(std::string_view(file), "inputs.bin");
  EXPECT_TRUE(save(*b.world) == file) << "restoring and saving again reproduces the file";
  EXPECT_EQ(b.source->rate(), 1500.0);
  EXPECT_EQ(b.sink->shape().radius(), 0.016);
  EXPECT_EQ(b.region->shape().halfSides().z(), 0.025);
  for (int n = 0; n < kAfter; ++n) b.world->step();
  ASSERT_EQ(a.world->particles().size(), b.world->particles().size());
  const std::vector<std::string> differing = differingColumns(*a.world, *b.world);
  EXPECT_TRUE(differing.empty()) << "first differing column: " << (differing.empty() ? "" : differing.front());
  expectSameReadings(a, b);
  EXPECT_TRUE(save(*a.world) == save(*b.world)) << "final checkpoints differ";
}

}  // namespace
}  // namespace demlink::core
