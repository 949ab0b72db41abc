#pragma once
/// Uniform cell grid over the particles' bounding box (the solver paper's
/// cell-linked list), stored as cells sorted by a counting sort: cell_start[c] ..
/// cell_start[c+1] index into sorted_slots. Building is O(N + cells) and the
/// number of cells is capped at ~4N (the cell edge grows if a stray particle
/// stretches the box), so memory and time stay linear in N.
#include <array>
#include <cstdint>
#include <span>
#include <vector>

#include "demlink/core/math_types.hpp"

namespace demlink::core {

class CellGrid {
 public:
  /// Bins positions into cells of edge >= minCellSize [m].
  void build(std::span<const Vec3> positions, double minCellSize);

  [[nodiscard]] std::array<std::int64_t, 3> cellCoords(const Vec3& x) const;
  [[nodiscard]] std::size_t cellIndex(std::int64_t ix, std::int64_t iy, std::int64_t iz) const {
    return static_cast<std::size_t>((iz * dims_[1] + iy) * dims_[0] + ix);
  }
  [[nodiscard]] const std::array<std::int64_t, 3>& dims() const { return dims_; }
  [[nodiscard]] std::span<const std::uint32_t> cell(std::size_t c) const {
    return {sorted_slots_.data() + cell_start_[c], sorted_slots_.data() + cell_start_[c + 1]};
  }
  /// Slots in cell order: a locality-friendly permutation of the particles.
  [[nodiscard]] const std::vector<std::uint32_t>& sortedSlots() const { return sorted_slots_; }
  [[nodiscard]] double cellSize() const { return cell_size_; }

 private:
  Vec3 origin_ = Vec3::Zero();
  double cell_size_ = 1.0;
  std::array<std::int64_t, 3> dims_{1, 1, 1};
  std::vector<std::uint32_t> cell_start_;
  std::vector<std::uint32_t> sorted_slots_;
  std::vector<std::uint32_t> cell_of_slot_;
};

}  // namespace demlink::core
