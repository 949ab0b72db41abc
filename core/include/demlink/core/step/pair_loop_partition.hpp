#pragma once
/// Cuts the half neighbour list's rows into chunks of about the same number of
/// pairs for the threaded pair loop. The cut depends only on the list, never on the
/// thread count. A pair (i, j) has j > i, so chunk c (rows [rowBegin(c), rowEnd(c)))
/// only touches slots in [rowBegin(c), reach(c)), reach(c) being one past its
/// largest partner. No other chunk touches the particle columns of c's own rows
/// while the pairs run (earlier chunks reach them only through their spill), so c
/// adds straight into them and keeps only what lands beyond its rows, in
/// [rowEnd(c), reach(c)), in its own spill buffer. gather() then adds, for every
/// slot, the spill of every earlier chunk reaching it, in chunk order, before the
/// slot's own chunk's sum. No atomics, and forces that are bit-identical whichever
/// thread ran which chunk and for any thread count from 2 on.
///
/// One thread gets one chunk: no spill to clear and gather, 7 % of a settled
/// 5,000-particle step (docs/benchmarks.md). Its forces are the same sums added in
/// another order, so a 1-thread run differs from a threaded one by round-off.
///
/// Slots are kept in cell order (World re-sorts them), so a window reaches about one
/// layer of cells beyond its rows; plan() grows the chunks when the windows together
/// would exceed a few times the particle count (slots out of order).
#include <cstdint>
#include <span>
#include <vector>

#include "demlink/core/math_types.hpp"

namespace demlink::core {

/// Where one chunk's pair loop adds its forces and torques [N, N m]: slots below
/// own_end (its own rows) into the particle columns, the others into its spill.
struct ChunkForces {
  Vec3* force;         ///< particle column, index slot
  Vec3* torque;
  Vec3* spill_force;   ///< index slot - own_end
  Vec3* spill_torque;
  std::size_t own_end;

  [[nodiscard]] Vec3& forceOf(std::size_t slot) const {
    return slot < own_end ? force[slot] : spill_force[slot - own_end];
  }
  [[nodiscard]] Vec3& torqueOf(std::size_t slot) const {
    return slot < own_end ? torque[slot] : spill_torque[slot - own_end];
  }
};

class PairLoopPartition {
 public:
  /// Pairs per chunk before growing [-].
  static constexpr std::uint64_t kPairsPerChunk = 512;

  /// Cuts rows into chunks (one when `threads` is 1) and sizes their spill buffers.
  void plan(std::span<const std::uint32_t> offsets, std::span<const std::uint32_t> partners, std::uint32_t threads);

  [[nodiscard]] std::uint32_t chunks() const { return static_cast<std::uint32_t>(row_begin_.size() - 1); }
  [[nodiscard]] std::size_t rowBegin(std::uint32_t chunk) const { return row_begin_[chunk]; }
  [[nodiscard]] std::size_t rowEnd(std::uint32_t chunk) const { return row_begin_[chunk + 1]; }
  /// One past the largest slot chunk `chunk` touches.
  [[nodiscard]] std::size_t reach(std::uint32_t chunk) const { return reach_[chunk]; }
  /// Zeroes chunk `chunk`'s own rows of force and torque and its spill (before its
  /// pairs run) and says where its pairs add.
  ChunkForces start(std::uint32_t chunk, std::span<Vec3> force, std::span<Vec3> torque);
  /// Completes force[s] and torque[s] for the slots s of chunk `chunk`'s rows: the
  /// spills of the earlier chunks reaching s, in chunk order, then the chunk's own sum.
  void gather(std::uint32_t chunk, std::span<Vec3> force, std::span<Vec3> torque) const;
  /// Bytes held by the buffers and the plan.
  [[nodiscard]] std::size_t bytes() const;

 private:
  std::vector<std::size_t> row_begin_{0};
  std::vector<std::size_t> reach_;
  std::vector<std::size_t> spill_start_{0};
  std::vector<std::uint32_t> first_covering_;  ///< lowest chunk whose window reaches rowBegin(c)
  std::vector<std::size_t> covered_end_;       ///< one past chunk c's last row an earlier window reaches
  std::vector<Vec3> force_;
  std::vector<Vec3> torque_;
};

}  // namespace demlink::core
