// The pair loop's plan: chunks of one parity never touch the same slot, every
// row belongs to exactly one chunk, the cut depends on the list alone, and a row is
// done (no chunk touches it again) where rowsDoneAfter says.
#include <gtest/gtest.h>

#include <algorithm>
#include <atomic>
#include <cstdint>
#include <memory>
#include <random>
#include <thread>
#include <vector>

#include "demlink/core/step/pair_loop_partition.hpp"
#include "demlink/core/parallel/thread_pool.hpp"

namespace demlink::core {
namespace {

/// A half list (offsets, partners) of `rows` rows, each with partners j > i at most
/// `span` slots ahead (a cell layer in a cell-ordered list), `perRow` on average; with
/// `farRow0`, row 0 also pairs with the last slot.
struct HalfList {
  std::vector<std::uint32_t> offsets{0};
  std::vector<std::uint32_t> partners;
};

HalfList randomHalfList(std::uint32_t rows, std::uint32_t span, std::uint32_t perRow, std::uint64_t seed,
                        bool farRow0 = false) {
  std::mt19937_64 rng(seed);
  HalfList list;
  if (farRow0) list.partners.push_back(rows - 1);
  for (std::uint32_t i = 0; i < rows; ++i) {
    const std::uint32_t count = static_cast<std::uint32_t>(rng() % (2 * perRow + 1));
    for (std::uint32_t k = 0; k < count && i + 1 < rows; ++k) {
      const std::uint32_t ahead = 1 + static_cast<std::uint32_t>(rng() % span);
      list.partners.push_back(std::min(rows - 1, i + ahead));
    }
    list.offsets.push_back(static_cast<std::uint32_t>(list.partners.size()));
  }
  return list;
}

/// The plan of `list`.
PairLoopPartition planOf(const HalfList& list) {
  PairLoopPartition plan;
  plan.plan(list.offsets, list.partners);
  return plan;
}

/// Every slot chunk c touches, from the list itself: its rows and their partners.
void expectParitiesDisjoint(const PairLoopPartition& plan, const HalfList& list) {
  const std::size_t rows = list.offsets.size() - 1;
  ASSERT_GE(plan.chunks(), 1u);
  EXPECT_EQ(plan.rowBegin(0), 0u);
  EXPECT_EQ(plan.rowEnd(plan.chunks() - 1), rows);
  for (std::uint32_t parity = 0; parity < 2; ++parity) {
    std::vector<int> toucher(rows, -1);
    for (std::uint32_t k = 0; k < plan.parityChunks(parity); ++k) {
      const std::uint32_t c = PairLoopPartition::chunkOfParity(parity, k);
      ASSERT_LT(c, plan.chunks());
      EXPECT_LT(plan.rowBegin(c), plan.rowEnd(c)) << "chunk " << c << " has no rows";
      std::vector<bool> mine(rows, false);
      for (std::size_t i = plan.rowBegin(c); i < plan.rowEnd(c); ++i) {
        mine[i] = true;
        for (std::uint32_t m = list.offsets[i]; m < list.offsets[i + 1]; ++m) {
          mine[list.partners[m]] = true;
          EXPECT_LT(list.partners[m], plan.reach(c)) << "chunk " << c;
        }
      }
      for (std::size_t s = 0; s < rows; ++s) {
        if (!mine[s]) continue;
        EXPECT_EQ(toucher[s], -1) << "parity " << parity << ": slot " << s << " touched by chunks " << toucher[s]
                                  << " and " << c;
        toucher[s] = static_cast<int>(c);
      }
    }
  }
  // Phases together run every chunk once.
  EXPECT_EQ(plan.parityChunks(0) + plan.parityChunks(1), plan.chunks());
}

TEST(PairLoopPartition, ChunksOfOnePhaseTouchDisjointSlots) {
  for (const std::uint32_t span : {8u, 300u, 2000u}) {
    const HalfList list = randomHalfList(20000, span, 3, span);
    const PairLoopPartition plan = planOf(list);
    EXPECT_GE(plan.chunks(), 4u) << "span " << span;
    if (plan.chunks() >= 4) {
      EXPECT_EQ(plan.chunks() % 4, 0u) << "span " << span;
    }
    for (std::uint32_t c = 0; c + 1 < plan.chunks(); ++c) EXPECT_LE(plan.reach(c), plan.rowEnd(c + 1));
    expectParitiesDisjoint(plan, list);
  }
}

TEST(PairLoopPartition, ARowReachingFarMergesChunks) {
  // Row 0 pairs with the last slot: nothing may run beside the chunk holding row 0
  // unless the next chunk ends at the list's end, so the cut has at most two chunks.
  const HalfList list = randomHalfList(5000, 50, 3, 7, true);
  const PairLoopPartition plan = planOf(list);
  EXPECT_LE(plan.chunks(), 2u);
  expectParitiesDisjoint(plan, list);
}

TEST(PairLoopPartition, ChunksStretchedByTheReachShareThePairsEvenly) {
  // Every row pairs with the next slot and with the slot one "cell layer" (`layer` slots)
  // ahead, as in a settled bed in cell order. A chunk then spans at least a layer, more
  // than the wanted 5000 / 16 rows: the cut once stretched every chunk to its
  // predecessor's reach and left the last one a remainder (a settled 5,000-sphere bed:
  // 12 full chunks, then 300, 3 and 1 rows; two threads' home ranges held 59 % and 41 %
  // of the pairs).
  for (const std::uint32_t layer : {330u, 369u, 400u}) {
    HalfList list;
    const std::uint32_t rows = 5000;
    for (std::uint32_t i = 0; i < rows; ++i) {
      if (i + 1 < rows) list.partners.push_back(i + 1);
      if (i + layer < rows) list.partners.push_back(i + layer);
      list.offsets.push_back(static_cast<std::uint32_t>(list.partners.size()));
    }
    const PairLoopPartition plan = planOf(list);
    ASSERT_GE(plan.chunks(), 4u) << "layer " << layer;
    const double mean = static_cast<double>(list.partners.size()) / plan.chunks();
    for (std::uint32_t c = 0; c < plan.chunks(); ++c) {
      const double pairs = list.offsets[plan.rowEnd(c)] - list.offsets[plan.rowBegin(c)];
      EXPECT_GT(pairs, 0.5 * mean) << "layer " << layer << ", chunk " << c << " of " << plan.chunks();
    }
    expectParitiesDisjoint(plan, list);
  }
}

TEST(PairLoopPartition, ThePlanDependsOnTheListOnly) {
  // The plan takes no thread count; one object planned for another list in between
  // plans a list as a fresh one does (nothing of an earlier plan is carried over).
  const HalfList list = randomHalfList(30000, 700, 4, 3);
  const HalfList other = randomHalfList(9000, 300, 6, 8);
  const PairLoopPartition fresh = planOf(list);
  ASSERT_GE(fresh.chunks(), 4u);
  PairLoopPartition reused = planOf(other);
  ASSERT_NE(reused.chunks(), fresh.chunks());
  reused.plan(list.offsets, list.partners);
  ASSERT_EQ(reused.chunks(), fresh.chunks());
  for (std::uint32_t c = 0; c < fresh.chunks(); ++c) {
    EXPECT_EQ(reused.rowBegin(c), fresh.rowBegin(c));
    EXPECT_EQ(reused.reach(c), fresh.reach(c));
  }
  expectParitiesDisjoint(reused, list);
}

TEST(PairLoopPartition, EvenChunksClearTheirRowsAndTheNextChunks) {
  const HalfList list = randomHalfList(4000, 100, 3, 11);
  const PairLoopPartition plan = planOf(list);
  ASSERT_GE(plan.chunks(), 3u);
  std::vector<Vec3> force(4000, Vec3::Ones());
  std::vector<Vec3> torque(4000, Vec3::Ones());
  for (std::uint32_t k = 0; k < plan.parityChunks(0); ++k) {
    (void)plan.start(PairLoopPartition::chunkOfParity(0, k), force, torque);
  }
  for (std::size_t s = 0; s < force.size(); ++s) {
    ASSERT_EQ(force[s], Vec3::Zero()) << "slot " << s;
    ASSERT_EQ(torque[s], Vec3::Zero()) << "slot " << s;
  }
  // Odd chunks clear nothing: the even chunks' additions are already in their rows.
  force.assign(4000, Vec3::Ones());
  for (std::uint32_t k = 0; k < plan.parityChunks(1); ++k) {
    (void)plan.start(PairLoopPartition::chunkOfParity(1, k), force, torque);
  }
  for (const Vec3& f : force) ASSERT_EQ(f, Vec3::Ones());
}

TEST(PairLoopPartition, RunGivesEveryChunkOnceAndNeverTwoThatTouchOneSlot) {
  // Every chunk marks the slots it touches while it runs; a slot marked twice is two
  // chunks running at once on one slot (an odd chunk started before an even neighbour
  // finished). Chunks yield while they hold their marks, so the threads interleave.
  const HalfList list = randomHalfList(6000, 120, 3, 5);
  const PairLoopPartition plan = planOf(list);
  ASSERT_GE(plan.chunks(), 8u);
  const std::size_t rows = list.offsets.size() - 1;
  for (const std::uint32_t threads : {1u, 2u, 3u, 4u}) {
    ThreadPool pool(threads);
    PairLoopPartition run = plan;
    for (int repeat = 0; repeat < 20; ++repeat) {
      const auto marks = std::make_unique<std::atomic<int>[]>(rows);
      const auto ran = std::make_unique<std::atomic<int>[]>(plan.chunks());
      std::atomic<int> overlaps{0};
      run.run(&pool, [&](std::uint32_t c) {
        ran[c].fetch_add(1);
        std::vector<std::size_t> touched;
        for (std::size_t i = plan.rowBegin(c); i < plan.rowEnd(c); ++i) {
          touched.push_back(i);
          for (std::uint32_t m = list.offsets[i]; m < list.offsets[i + 1]; ++m) touched.push_back(list.partners[m]);
        }
        std::sort(touched.begin(), touched.end());
        touched.erase(std::unique(touched.begin(), touched.end()), touched.end());
        for (const std::size_t s : touched) {
          if (marks[s].fetch_add(1) != 0) overlaps.fetch_add(1);
        }
        std::this_thread::yield();
        for (const std::size_t s : touched) marks[s].fetch_sub(1);
      });
      for (std::uint32_t c = 0; c < plan.chunks(); ++c) ASSERT_EQ(ran[c].load(), 1) << "chunk " << c;
      ASSERT_EQ(overlaps.load(), 0) << threads << " threads, repeat " << repeat;
    }
  }
}

TEST(PairLoopPartition, RowsDoneAfterAChunkAreTouchedByNoLaterChunk) {
  // The pair loop kicks and drifts rowsDoneAfter(c) as soon as chunk c has run
  // (World::computeForces): no chunk may touch such a row afterwards, and every row must
  // be kicked exactly once. Each chunk checks the slots it touches against the rows
  // done so far, then marks its own done rows, as the pair loop does.
  for (const std::uint32_t span : {60u, 120u}) {
    const HalfList list = randomHalfList(6000, span, 3, 21 + span);
    const PairLoopPartition plan = planOf(list);
    ASSERT_GE(plan.chunks(), 8u);
    const std::size_t rows = list.offsets.size() - 1;
    for (const std::uint32_t threads : {1u, 2u, 3u}) {
      ThreadPool pool(threads);
      PairLoopPartition run = plan;
      for (int repeat = 0; repeat < 10; ++repeat) {
        const auto done = std::make_unique<std::atomic<int>[]>(rows);
        std::atomic<int> late{0};
        run.run(&pool, [&](std::uint32_t c) {
          for (std::size_t i = plan.rowBegin(c); i < plan.rowEnd(c); ++i) {
            if (done[i].load() != 0) late.fetch_add(1);
            for (std::uint32_t m = list.offsets[i]; m < list.offsets[i + 1]; ++m) {
              if (done[list.partners[m]].load() != 0) late.fetch_add(1);
            }
          }
          std::this_thread::yield();
          const auto [begin, end] = plan.rowsDoneAfter(c);
          for (std::size_t i = begin; i < end; ++i) done[i].fetch_add(1);
        });
        ASSERT_EQ(late.load(), 0) << threads << " threads, repeat " << repeat;
        for (std::size_t i = 0; i < rows; ++i) ASSERT_EQ(done[i].load(), 1) << "row " << i;
      }
    }
  }
}

}  // namespace
}  // namespace demlink::core
