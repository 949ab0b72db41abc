#include "demlink/core/particles/cell_grid.hpp"

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
  // Cell counts are found in double precision first: particles spread over an absurd
  // extent (found by fuzzing: a lattice spacing of 1e175 m) must grow the cells, not
  // overflow the integer conversion. An extent that is not even finite as a double
  // gets one cell along that axis (every particle clamps into it: slow but correct).
  std::array<double, 3> counts{};
  for (;;) {
    for (int d = 0; d < 3; ++d) {
      const double extent = hi[d] - lo[d];
      counts[d] = std::isfinite(extent) ? std::floor(extent / cell_size_) + 1.0 : 1.0;
    }
    if (counts[0] * counts[1] * counts[2] <= maxCells) break;
    cell_size_ *= 1.5;
  }
  for (int d = 0; d < 3; ++d) dims_[d] = static_cast<std::int64_t>(counts[d]);
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
    // Clamped in double before the conversion (an out-of-range double -> int64 is UB).
    const double k = std::floor((x[d] - origin_[d]) / cell_size_);
    const auto last = static_cast<double>(dims_[d] - 1);
    c[d] = !(k > 0.0) ? 0 : static_cast<std::int64_t>(std::min(k, last));
  }
  return c;
}

}  // namespace demlink::core
