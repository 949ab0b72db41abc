#pragma once
/// Splits the half neighbour list's rows into `parts` contiguous ranges holding
/// about the same number of pairs, for the threaded pair loop. A pair (i, j) has
/// j > i, so part t (rows from row_begin[t]) only ever touches slots >=
/// row_begin[t]: part 0 accumulates straight into the particle arrays, every other
/// part into its own buffers covering [row_begin[t], N), which a reduction then
/// adds in fixed order. No atomics, and bit-identical results for a fixed count.
#include <cstdint>
#include <span>
#include <vector>

#include "demlink/core/math_types.hpp"

namespace demlink::core {

class PairLoopPartition {
 public:
  /// Balances rows by pair count; sizes the buffers of parts 1..parts-1.
  void plan(std::span<const std::uint32_t> offsets, std::uint32_t parts);

  [[nodiscard]] std::uint32_t parts() const { return static_cast<std::uint32_t>(row_begin_.size() - 1); }
  [[nodiscard]] std::size_t rowBegin(std::uint32_t part) const { return row_begin_[part]; }
  [[nodiscard]] std::size_t rowEnd(std::uint32_t part) const { return row_begin_[part + 1]; }
  /// Buffers of part >= 1; index slot - rowBegin(part).
  [[nodiscard]] std::vector<Vec3>& force(std::uint32_t part) { return force_[part]; }
  [[nodiscard]] std::vector<Vec3>& torque(std::uint32_t part) { return torque_[part]; }

 private:
  std::vector<std::size_t> row_begin_{0, 0};
  std::vector<std::vector<Vec3>> force_;
  std::vector<std::vector<Vec3>> torque_;
};

}  // namespace demlink::core
