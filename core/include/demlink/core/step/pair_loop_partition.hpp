#pragma once
/// Cuts the half neighbour list's rows into chunks for the threaded pair loop and
/// runs them in two phases. A pair (i, j) has j > i, so chunk c (rows [rowBegin(c),
/// rowEnd(c))) touches only slots in [rowBegin(c), reach(c)), reach(c) being one past
/// its largest partner. plan() makes every chunk reach no further than the end of the
/// next chunk's rows, so chunk c touches only its own rows and chunk c + 1's:
///   - phase 0 runs the even chunks, which touch pairwise disjoint slots; each first
///     clears its own rows and the next chunk's (nothing else writes them before), unless
///     the step's first kick cleared them already (ForcesAfterKick);
///   - phase 1 runs the odd chunks, again pairwise disjoint.
/// Every chunk adds straight into the particle columns: no atomics, no per-chunk
/// buffers to clear and add up afterwards. Each slot's force is summed in an order the
/// plan fixes (its even chunk's pairs, then its odd chunk's), and the plan depends only
/// on the list, so forces are bit-identical whichever thread ran which chunk and for any
/// thread count from 2 on.
///
/// Why not per-chunk spill buffers for the slots beyond a chunk's rows, added up in
/// chunk order afterwards (the previous design): slots are in cell order
/// (CellGrid::spatialOrder), so a chunk reaches one to three cell layers past its rows, and clearing and
/// adding those spills cost as much memory traffic as the pair loop saved by sharing it:
/// two threads ran a 5,000-particle bed's force stage slower than one
/// (docs/benchmarks.md).
///
/// One thread gets one chunk. Its forces are the same sums in row order, so a 1-thread
/// run differs from a threaded one by round-off.
#include <cstdint>
#include <span>
#include <vector>

#include "demlink/core/math_types.hpp"

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

  /// Cuts rows into chunks (one when `threads` is 1).
  void plan(std::span<const std::uint32_t> offsets, std::span<const std::uint32_t> partners, std::uint32_t threads);

  [[nodiscard]] std::uint32_t chunks() const { return static_cast<std::uint32_t>(row_begin_.size() - 1); }
  [[nodiscard]] std::size_t rowBegin(std::uint32_t chunk) const { return row_begin_[chunk]; }
  [[nodiscard]] std::size_t rowEnd(std::uint32_t chunk) const { return row_begin_[chunk + 1]; }
  /// One past the largest slot chunk `chunk` touches (at most rowEnd(chunk + 1)).
  [[nodiscard]] std::size_t reach(std::uint32_t chunk) const { return reach_[chunk]; }

  /// Chunks of phase `phase` (0: the even ones, 1: the odd ones).
  [[nodiscard]] std::uint32_t phaseChunks(std::uint32_t phase) const { return (chunks() + 1 - phase) / 2; }
  /// The k-th chunk of phase `phase`.
  [[nodiscard]] static std::uint32_t chunkOfPhase(std::uint32_t phase, std::uint32_t k) { return 2 * k + phase; }

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

  std::vector<std::size_t> row_begin_{0};
  std::vector<std::size_t> reach_;
};

}  // namespace demlink::core
