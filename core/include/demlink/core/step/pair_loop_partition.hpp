#pragma once
/// Cuts the half neighbour list's rows into chunks for the threaded pair loop and
/// schedules them. A pair (i, j) has j > i, so chunk c (rows [rowBegin(c), rowEnd(c)))
/// touches only slots in [rowBegin(c), reach(c)), reach(c) being one past its largest
/// partner. plan() makes every chunk reach no further than the end of the next chunk's
/// rows, so chunk c touches only its own rows and chunk c + 1's. Two chunks touch a
/// common slot only when they are neighbours, so:
///   - the even chunks are pairwise disjoint, and so are the odd ones;
///   - an even chunk first clears its own rows and the next chunk's (nothing else
///     writes them before), unless the step's first kick cleared them already
///     (ForcesAfterKick);
///   - odd chunk c runs after both its even neighbours c - 1 and c + 1 (run()).
/// Every chunk adds straight into the particle columns: no atomics, no per-chunk
/// buffers to clear and add up afterwards. Each slot's force is summed in an order the
/// plan fixes (its even chunk's pairs, then its odd chunk's), and the plan depends only
/// on the list, so forces are bit-identical whichever thread ran which chunk and for any
/// thread count, one included (one thread runs the chunks in run()'s order: each odd
/// chunk right after its later even neighbour).
///
/// Why run() is a dataflow, not two phases (all even chunks, a join, all odd ones):
/// each join waits for the slower thread, and on machines whose cores run at unequal
/// speeds the faster thread would idle twice per step or steal whole chunks whose rows
/// then sit in the wrong cache for the next kick. The threads claim even chunks, and
/// the thread that finishes the second even neighbour of an odd chunk runs that odd
/// chunk at once, while both chunks' rows are in its cache: one join per force
/// evaluation, no waiting for a dependency, and the same sums in the same order as two
/// phases would make.
///
/// Why no per-chunk spill buffers for the slots beyond a chunk's rows, added up in
/// chunk order afterwards: slots are in cell order (CellGrid::spatialOrder), so a chunk
/// reaches one to three cell layers past its rows, and clearing and adding those spills
/// costs as much memory traffic as sharing the pair loop saves.
///
/// Why one thread runs the same chunks, not one chunk over all rows: a run then sums
/// every force in the same order whatever the thread count, so one thread gives the
/// threaded runs' bits (docs/benchmarks.md has the cost, measured).
#include <algorithm>
#include <atomic>
#include <cstdint>
#include <span>
#include <utility>
#include <vector>

#include "demlink/core/base/math_types.hpp"
#include "demlink/core/parallel/parallel_loops.hpp"

namespace demlink::core {

/// Where a chunk's pair loop adds its forces and torques [N, N m]: the particle columns,
/// indexed by slot.
struct ChunkForces {
  Vec3* force;
  Vec3* torque;
};

class PairLoopPartition {
 public:
  /// Pairs per chunk wanted before the reach stretches the chunks [-].
  static constexpr std::uint64_t kPairsPerChunk = 512;

  /// Cuts rows into chunks: from the list alone, the same for any thread count.
  void plan(std::span<const std::uint32_t> offsets, std::span<const std::uint32_t> partners);

  [[nodiscard]] std::uint32_t chunks() const { return static_cast<std::uint32_t>(row_begin_.size() - 1); }
  [[nodiscard]] std::size_t rowBegin(std::uint32_t chunk) const { return row_begin_[chunk]; }
  [[nodiscard]] std::size_t rowEnd(std::uint32_t chunk) const { return row_begin_[chunk + 1]; }
  /// One past the largest slot chunk `chunk` touches (at most rowEnd(chunk + 1)).
  [[nodiscard]] std::size_t reach(std::uint32_t chunk) const { return reach_[chunk]; }

  /// Chunks of parity `parity` (0: the even ones, 1: the odd ones), which touch pairwise
  /// disjoint slots.
  [[nodiscard]] std::uint32_t parityChunks(std::uint32_t parity) const { return (chunks() + 1 - parity) / 2; }
  /// The k-th chunk of parity `parity`.
  [[nodiscard]] static std::uint32_t chunkOfParity(std::uint32_t parity, std::uint32_t k) { return 2 * k + parity; }

  /// Calls body(chunk) once for every chunk, spread over `pool` (serially without one):
  /// the even chunks as the pool's parts, and each odd chunk right after the later of its
  /// even neighbours, by the thread that ran that one. Not reentrant.
  template <class Body>
  void run(ThreadPool* pool, const Body& body);

  /// Rows [first, second) that no chunk touches any more once chunk `chunk` has run in
  /// run(), so their forces are final: chunk c's rows are touched by chunks c - 1 and c
  /// only, so chunk 0's rows are done after chunk 0, and an odd chunk's rows and the next
  /// chunk's after the odd chunk (which runs after both its even neighbours). Empty for
  /// the other even chunks. Every row is in exactly one chunk's range.
  [[nodiscard]] std::pair<std::size_t, std::size_t> rowsDoneAfter(std::uint32_t chunk) const {
    if (chunk == 0) return {rowBegin(0), rowEnd(0)};
    if (chunk % 2 == 0) return {rowBegin(chunk), rowBegin(chunk)};
    return {rowBegin(chunk), rowEnd(std::min(chunk + 1, chunks() - 1))};
  }

  /// Before chunk `chunk`'s pairs run: with `clear`, an even chunk zeroes force and torque
  /// of its own rows and of the next chunk's (without, they are zero already). Says where
  /// its pairs add.
  ChunkForces start(std::uint32_t chunk, std::span<Vec3> force, std::span<Vec3> torque, bool clear = true) const;
  /// Bytes held by the plan.
  [[nodiscard]] std::size_t bytes() const;

 private:
  /// One cut for `wanted` chunks of about equal pairs, each stretched to the reach of the
  /// one before it; may give fewer chunks.
  void cut(std::span<const std::uint32_t> offsets, std::span<const std::uint32_t> partners, std::size_t wanted);

  /// Before run() marks odd chunk c ready: its even neighbours not yet finished.
  void resetWaits();

  std::vector<std::size_t> row_begin_{0};
  std::vector<std::size_t> reach_;
  /// Per chunk, during run(): an odd chunk's even neighbours still running or unclaimed
  /// (decremented through std::atomic_ref; unused for even chunks).
  std::vector<std::uint32_t> waits_;
};

template <class Body>
void PairLoopPartition::run(ThreadPool* pool, const Body& body) {
  const std::uint32_t n = chunks();
  resetWaits();
  parallelParts(pool, (n + 1) / 2, [&](std::uint32_t k) {
    const std::uint32_t even = 2 * k;
    body(even);
    // Release: the odd chunk's runner sees this chunk's forces; acquire: and the other
    // neighbour's, when this thread finishes the later one.
    const auto evenDone = [&](std::uint32_t odd) {
      if (odd < n && std::atomic_ref<std::uint32_t>(waits_[odd]).fetch_sub(1, std::memory_order_acq_rel) == 1) {
        body(odd);
      }
    };
    if (even > 0) evenDone(even - 1);
    evenDone(even + 1);
  });
}

}  // namespace demlink::core
