// Checkpoints: a run continued from a checkpoint in a new World equals the run
// that never stopped, bit for bit (every particle column, neighbour histories,
// plane and mesh near lists and wrenches, tallies, component state), for 1 and 2
// threads, and from 2 threads to 1. Bad files (truncated, wrong magic or version,
// corrupt lengths, another scene) give an InputError naming the file and section and leave the world as it was.
#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <stdexcept>
#include <sstream>

#include <gtest/gtest.h>

#include "demlink/core/checkpoint_file.hpp"
#include "demlink/core/base/input_error.hpp"
#include "demlink/core/state/state_stream.hpp"
#include "checkpoint_test_support.hpp"
#include "test_scenes.hpp"

namespace demlink::core {
namespace {

/// Counts the steps it observed: a component with state of its own.
class StepCounter final : public WorldComponent {
 public:
  StepCounter() : WorldComponent("counter") {}
  [[nodiscard]] std::string_view kind() const override { return "step_counter"; }
  [[nodiscard]] StageSet stages() const override { return stageBit(Stage::kObserve); }
  void observe(const ComponentWorld& /*world*/) override { ++count_; }
  void saveState(StateWriter& out) const override { out.write(count_); }
  void loadState(StateReader& in) override { count_ = in.read<std::uint64_t>(); }
  [[nodiscard]] std::uint64_t count() const { return count_; }

 private:
  std::uint64_t count_ = 0;
};

struct SceneVariant {
  std::uint32_t threads = 1;
  double time_step = 2e-5;     ///< [s]
  bool extra_material = false;
  std::uint32_t mesh_cells = 4;
};

/// Boxed lattice falling onto a plane floor and a sliding mesh strip, with the
/// top layer outside the bounds (removed at the first step) and frequent re-sorts.
std::unique_ptr<World> buildScene(const SceneVariant& v = {}) {
  SimulationSettings s;
  s.time_step = v.time_step;
  s.threads = v.threads;
  s.sort_every_builds = 3;
  s.restitution_tolerance = 0.2;  // round trips, not restitution, are tested
  s.bounds = DomainBounds{Vec3::Constant(-0.1), Vec3(0.1, 0.1, 0.024)};
  auto world = std::make_unique<World>(s);
  const auto grains = test::addBoxedLattice(*world);
  if (v.extra_material) {
    Material extra = test::testMaterial(0.5);
    extra.name = "extra";
    world->addMaterial(extra);
  }
  world->addPlane({"floor", Vec3::Zero(), Vec3::UnitZ(), grains});
  const TriangleMesh strip = rectangleMesh(Vec3(0.008, 0.015, 0.0006), 0.008, 0.015, v.mesh_cells, v.mesh_cells);
  MeshBody mesh("strip", strip.vertices, strip.triangles, grains);
  mesh.setVelocity(Vec3(0.05, 0.0, 0.0), Vec3::Zero());
  world->addMesh(std::move(mesh));
  ParticleArrays& p = world->particles();
  for (std::size_t i = 0; i < p.size(); ++i) p.velocity[i] = Vec3(0.1 * std::sin(double(i)), 0.05, -0.4);
  world->addComponent(std::make_unique<StepCounter>());
  world->initialize();
  return world;
}

const StepCounter& counter(const World& world) { return static_cast<const StepCounter&>(*world.components()[0]); }

using test::bitEqual;

std::string save(const World& world) { return test::saveToBytes(world); }

void expectBitIdentical(const World& a, const World& b) {
  EXPECT_EQ(a.stepCount(), b.stepCount());
  const std::vector<std::string> differing = test::differingColumns(a, b);
  EXPECT_TRUE(differing.empty()) << "first differing column: " << (differing.empty() ? "" : differing.front());
  EXPECT_TRUE(std::ranges::equal(a.neighbourList().partners(), b.neighbourList().partners()));
  EXPECT_TRUE(std::ranges::equal(a.neighbourList().rows(), b.neighbourList().rows()));
  EXPECT_EQ(std::memcmp(a.neighbourList().history().data(), b.neighbourList().history().data(),
                        a.neighbourList().history().size_bytes()),
            0);
  EXPECT_EQ(a.neighbourList().buildCount(), b.neighbourList().buildCount());
  for (std::size_t k = 0; k < a.planes().size(); ++k) {
    EXPECT_TRUE(a.planes()[k].force == b.planes()[k].force) << a.planes()[k].spec.name;
    EXPECT_TRUE(bitEqual(a.planes()[k].near_history, b.planes()[k].near_history)) << a.planes()[k].spec.name;
  }
  EXPECT_TRUE(a.meshes()[0].force() == b.meshes()[0].force());
  EXPECT_TRUE(a.meshes()[0].position() == b.meshes()[0].position());
  EXPECT_EQ(a.removedAtBounds().count, b.removedAtBounds().count);
  EXPECT_EQ(a.removedAtBounds().mass, b.removedAtBounds().mass);
  EXPECT_EQ(counter(a).count(), counter(b).count());
}

bool anyNonZero(std::span<const Vec3> values) {
  return std::any_of(values.begin(), values.end(), [](const Vec3& v) { return !v.isZero(0.0); });
}

TEST(Checkpoint, ContinuedRunIsBitIdenticalToUninterrupted) {
  for (std::uint32_t threads : {1u, 2u}) {
    SceneVariant v;
    v.threads = threads;
    const auto a = buildScene(v);
    for (int n = 0; n < 450; ++n) a->step();
    // The checkpoint must carry live contact state, or this test proves little.
    ASSERT_TRUE(anyNonZero(a->neighbourList().history())) << "no particle contact histories yet";
    ASSERT_TRUE(anyNonZero(a->planes()[4].near_history)) << "no floor contact histories yet";
    ASSERT_GT(a->removedAtBounds().count, 0u);
    ASSERT_GT(a->neighbourList().buildCount(), 3u) << "slots were never re-sorted";
    const std::string file = save(*a);
    for (int n = 0; n < 150; ++n) a->step();

    const auto b = buildScene(v);
    b->restoreCheckpoint(std::string_view(file), "a.bin");
    EXPECT_EQ(b->stepCount(), 450u);
    EXPECT_TRUE(save(*b) == file) << "restoring and saving again reproduces the file";
    for (int n = 0; n < 150; ++n) b->step();
    SCOPED_TRACE(std::to_string(threads) + " threads");
    expectBitIdentical(*a, *b);
  }
}

TEST(Checkpoint, ARunWrittenOnTwoThreadsContinuesOnOneBitIdentically) {
  // Every loop's chunks depend on the scene alone, one thread included, so the thread
  // count is no part of a run's result: a checkpoint of a 2-thread run continued on
  // 1 thread ends in the bits of the 2-thread run that never stopped.
  SceneVariant two;
  two.threads = 2;
  const auto a = buildScene(two);
  for (int n = 0; n < 450; ++n) a->step();
  ASSERT_GT(a->pairLoopPartition().chunks(), 2u) << "one chunk: the thread counts would not differ";
  const std::string file = save(*a);
  for (int n = 0; n < 150; ++n) a->step();
  const auto b = buildScene();  // one thread
  b->restoreCheckpoint(std::string_view(file), "a.bin");
  for (int n = 0; n < 150; ++n) b->step();
  expectBitIdentical(*a, *b);
}

TEST(Checkpoint, MeshNearListHistoriesSurviveTheRoundTrip) {
  const auto a = buildScene();
  for (int n = 0; n < 450; ++n) a->step();
  const std::string file = save(*a);
  const auto b = buildScene();
  b->restoreCheckpoint(std::string_view(file), "a.bin");
  // The mesh strip under the bed carries the bed's contacts: its wrench is live.
  ASSERT_GT(a->meshes()[0].force().norm(), 0.0);
  for (int n = 0; n < 50; ++n) {
    a->step();
    b->step();
  }
  EXPECT_TRUE(a->meshes()[0].force() == b->meshes()[0].force());
  EXPECT_TRUE(a->meshes()[0].torque() == b->meshes()[0].torque());
}

/// Restoring `bytes` into a fresh scene must throw an InputError naming the
/// file and mentioning `section`; the world keeps its state.
void expectRejected(const std::string& bytes, const std::string& section, const SceneVariant& v = {}) {
  const auto world = buildScene(v);
  world->step();
  const std::string before = save(*world);
  try {
    world->restoreCheckpoint(std::string_view(bytes), "bad.bin");
    ADD_FAILURE() << "accepted a bad checkpoint (" << section << ")";
  } catch (const InputError& e) {
    EXPECT_EQ(e.field().rfind("bad.bin:", 0), 0u) << e.what();
    EXPECT_NE(std::string(e.what()).find(section), std::string::npos) << e.what();
  }
  EXPECT_TRUE(save(*world) == before) << "a failed restore changed the world";
}

std::string goodFile() {
  const auto world = buildScene();
  for (int n = 0; n < 20; ++n) world->step();
  return save(*world);
}

TEST(Checkpoint, RejectsTruncatedFiles) {
  const std::string file = goodFile();
  for (std::size_t cut : {std::size_t{0}, std::size_t{5}, std::size_t{20}, file.size() / 7, file.size() / 3,
                          file.size() / 2, file.size() - 13, file.size() - 1}) {
    SCOPED_TRACE(cut);
    expectRejected(file.substr(0, cut), "truncated");
  }
}

TEST(Checkpoint, RejectsWrongMagicAndVersion) {
  std::string file = goodFile();
  std::string magic = file;
  magic[0] = 'X';
  expectRejected(magic, "not a DEMLink checkpoint");
  std::string version = file;
  const std::uint32_t future = kCheckpointVersion + 1;
  std::memcpy(version.data() + 8, &future, sizeof future);
  expectRejected(version, "version");
  std::string order = file;
  std::swap(order[12], order[15]);
  expectRejected(order, "byte order");
}

TEST(Checkpoint, TheWriterRefusesNaNNamingTheSections) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  for (int kind = 0; kind < 3; ++kind) {
    StateWriter out;
    std::string message;
    try {
      out.section("OUTR", [&] {
        out.section("INNR", [&] {
          out.write(1.5);
          if (kind == 0) out.write(nan);
          if (kind == 1) out.write(Vec3(0.0, nan, 0.0));
          if (kind == 2) out.write(Quat(nan, 0.0, 0.0, 1.0));
        });
      });
    } catch (const std::logic_error& error) {
      message = error.what();
    }
    EXPECT_NE(message.find("NaN value in section OUTR/INNR"), std::string::npos) << kind << ": " << message;
  }
  StateWriter finite;
  finite.write(std::numeric_limits<double>::infinity());  // "no limit" is a value, not a missing one
  EXPECT_EQ(finite.bytes().size(), sizeof(double));
}

TEST(Checkpoint, MissingValuesTravelAsFlags) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  StateWriter out;
  writeWithMissing(out, {1.0, nan, -2.5, nan});
  EXPECT_EQ(out.bytes().find(std::string("\x7f\xf8", 2)), std::string::npos);
  StateReader in(out.bytes(), "row.bin", "SMPL");
  const std::vector<double> back = readWithMissing(in, "latest sample");
  ASSERT_EQ(back.size(), 4u);
  EXPECT_EQ(back[0], 1.0);
  EXPECT_TRUE(std::isnan(back[1]));
  EXPECT_EQ(back[2], -2.5);
  EXPECT_TRUE(std::isnan(back[3]));
  // A flag other than 0 or 1, and a NaN not flagged missing, are refused.
  std::string bad = out.bytes();
  bad[bad.size() - 1] = 2;
  StateReader badFlag(bad, "row.bin", "SMPL");
  EXPECT_THROW((void)readWithMissing(badFlag, "latest sample"), InputError);
  StateWriter raw;
  raw.writeVector(std::vector<double>{1.0});
  std::string unflagged = raw.bytes();
  std::memcpy(unflagged.data() + sizeof(std::uint64_t), &nan, sizeof nan);
  unflagged += std::string(sizeof(std::uint64_t), '\0');
  unflagged[unflagged.size() - sizeof(std::uint64_t)] = 1;  // one flag
  unflagged += '\0';
  StateReader hidden(unflagged, "row.bin", "SMPL");
  EXPECT_THROW((void)readWithMissing(hidden, "latest sample"), InputError);
}

TEST(Checkpoint, RejectsCorruptLengthsWithoutHugeAllocations) {
  const std::string file = goodFile();
  // The first section's length field sits right after the 28-byte header and its tag.
  std::string section = file;
  const std::uint64_t huge = std::uint64_t{1} << 60;
  std::memcpy(section.data() + 28 + 4, &huge, sizeof huge);
  expectRejected(section, "exceeds");
  // The element count of the first particle column ("position"): after PART's
  // header, the row count, the column count, COL's header and its name.
  const std::size_t part = file.find("PART");
  ASSERT_NE(part, std::string::npos);
  const std::size_t count = part + 12 + 8 + 4 + 12 + 8 + std::strlen("position") + 4;
  std::uint64_t rows = 0;
  std::memcpy(&rows, file.data() + count, sizeof rows);
  ASSERT_EQ(rows, 245u) << "offset of the column length";
  std::string column = file;
  std::memcpy(column.data() + count, &huge, sizeof huge);
  expectRejected(column, "array length");
  std::string shorter = file;
  const std::uint64_t fewer = rows - 1;
  std::memcpy(shorter.data() + count, &fewer, sizeof fewer);
  expectRejected(shorter, "particles");
}

TEST(Checkpoint, RejectsAnotherScene) {
  const std::string file = goodFile();
  SceneVariant materials;
  materials.extra_material = true;
  expectRejected(file, "material count", materials);
  SceneVariant mesh;
  mesh.mesh_cells = 2;
  expectRejected(file, "triangle count", mesh);
  SceneVariant dt;
  dt.time_step = 1e-5;
  expectRejected(file, "time_step", dt);
}

TEST(Checkpoint, SurvivesRandomByteFlips) {
  // Any corruption either restores (the bytes hit a value) or is an InputError;
  // never a crash or an unchecked allocation (the ASan build checks both).
  const std::string file = goodFile();
  std::uint64_t state = 12345;
  int rejected = 0;
  const auto world = buildScene();
  for (int trial = 0; trial < 200; ++trial) {
    state = state * 6364136223846793005ull + 1442695040888963407ull;
    std::string bad = file;
    const std::size_t at = static_cast<std::size_t>((state >> 33) % bad.size());
    bad[at] = static_cast<char>(bad[at] ^ static_cast<char>(0x5a));
    try {
      world->restoreCheckpoint(std::string_view(bad), "flip.bin");
    } catch (const InputError&) {
      ++rejected;
    }
  }
  EXPECT_GT(rejected, 0);
}

}  // namespace
}  // namespace demlink::core
