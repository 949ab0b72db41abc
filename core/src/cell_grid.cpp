#include "demlink/core/cell_grid.hpp"

#include <algorithm>
#include <cmath>

namespace demlink::core {

void CellGrid::build(std::span<const Vec3> positions, double minCellSize) {
  const std::size_t n = positions.size();
  Vec3 lo = Vec3::Constant(0.0);
  Vec3 hi = Vec3::Constant(0.0);
  if (n > 0) {
    lo = hi = positions[0];
    for (const Vec3& x : positions) {
      lo = lo.cwiseMin(x);
      hi = hi.cwiseMax(x);
    }
  }
  origin_ = lo;
  cell_size_ = minCellSize;
  const double maxCells = 4.0 * static_cast<double>(n) + 64.0;
  for (;;) {
    for (int d = 0; d < 3; ++d) {
      dims_[d] = static_cast<std::int64_t>(std::floor((hi[d] - lo[d]) / cell_size_)) + 1;
    }
    if (static_cast<double>(dims_[0]) * static_cast<double>(dims_[1]) * static_cast<double>(dims_[2]) <= maxCells) {
      break;
    }
    cell_size_ *= 1.5;
  }
  const std::size_t cells = static_cast<std::size_t>(dims_[0] * dims_[1] * dims_[2]);
  cell_start_.assign(cells + 1, 0);
  cell_of_slot_.resize(n);
  for (std::size_t i = 0; i < n; ++i) {
    const auto c = cellCoords(positions[i]);
    cell_of_slot_[i] = static_cast<std::uint32_t>(cellIndex(c[0], c[1], c[2]));
    ++cell_start_[cell_of_slot_[i] + 1];
  }
  for (std::size_t c = 0; c < cells; ++c) cell_start_[c + 1] += cell_start_[c];
  sorted_slots_.resize(n);
  std::vector<std::uint32_t> fill(cell_start_.begin(), cell_start_.end() - 1);
  for (std::size_t i = 0; i < n; ++i) sorted_slots_[fill[cell_of_slot_[i]]++] = static_cast<std::uint32_t>(i);
}

std::array<std::int64_t, 3> CellGrid::cellCoords(const Vec3& x) const {
  std::array<std::int64_t, 3> c{};
  for (int d = 0; d < 3; ++d) {
    const auto k = static_cast<std::int64_t>(std::floor((x[d] - origin_[d]) / cell_size_));
    c[d] = std::clamp<std::int64_t>(k, 0, dims_[d] - 1);
  }
  return c;
}

}  // namespace demlink::core
