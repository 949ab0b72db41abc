#pragma once
/// Cuts the half neighbour list's rows into chunks of about the same number of
/// pairs for the threaded pair loop. The cut depends only on the list, never on the
/// thread count. A pair (i, j) has j > i, so chunk c (rows [rowBegin(c), rowEnd(c)))
/// only touches slots in [rowBegin(c), reach(c)), reach(c) being one past its
/// largest partner: each chunk accumulates into its own buffer over that window,
/// and gather() then sums, for every slot, the buffers covering it in chunk order.
/// No atomics, and forces that are bit-identical whichever thread ran which chunk
/// and for any thread count (1 included).
///
/// Slots are kept in cell order (World re-sorts them), so a window reaches about one
/// layer of cells beyond its rows; plan() grows the chunks when the windows together
/// would exceed a few times the particle count (slots out of order).
#include <cstdint>
#include <span>
#include <vector>

#include "demlink/core/math_types.hpp"

namespace demlink::core {

class PairLoopPartition {
 public:
  /// Pairs per chunk before growing [-].
  static constexpr std::uint64_t kPairsPerChunk = 512;

  /// Cuts rows into chunks and sizes their buffers.
  void plan(std::span<const std::uint32_t> offsets, std::span<const std::uint32_t> partners);

  [[nodiscard]] std::uint32_t chunks() const { return static_cast<std::uint32_t>(row_begin_.size() - 1); }
  [[nodiscard]] std::size_t rowBegin(std::uint32_t chunk) const { return row_begin_[chunk]; }
  [[nodiscard]] std::size_t rowEnd(std::uint32_t chunk) const { return row_begin_[chunk + 1]; }
  /// One past the largest slot chunk `chunk` touches.
  [[nodiscard]] std::size_t reach(std::uint32_t chunk) const { return reach_[chunk]; }
  /// Buffers of chunk `chunk`: index slot - rowBegin(chunk), length reach - rowBegin.
  [[nodiscard]] Vec3* force(std::uint32_t chunk) { return force_.data() + buffer_start_[chunk]; }
  [[nodiscard]] Vec3* torque(std::uint32_t chunk) { return torque_.data() + buffer_start_[chunk]; }
  /// Zeroes chunk `chunk`'s buffers (before its pairs run).
  void clear(std::uint32_t chunk);
  /// Writes force[s] and torque[s] for the slots s of chunk `chunk`'s rows: the sum of
  /// every buffer covering s, in chunk order.
  void gather(std::uint32_t chunk, std::span<Vec3> force, std::span<Vec3> torque) const;
  /// Bytes held by the buffers and the plan.
  [[nodiscard]] std::size_t bytes() const;

 private:
  std::vector<std::size_t> row_begin_{0};
  std::vector<std::size_t> reach_;
  std::vector<std::size_t> buffer_start_{0};
  std::vector<std::uint32_t> first_covering_;  ///< lowest chunk whose window reaches rowBegin(c)
  std::vector<Vec3> force_;
  std::vector<Vec3> torque_;
};

}  // namespace demlink::core
