// The cell grid under extreme particle extents: found by fuzzing the co-simulation host
// (a lattice spacing of 1e175 m made the cell count overflow a 64-bit integer).
#include <gtest/gtest.h>

#include <limits>
#include <vector>

#include "demlink/core/particles/cell_grid.hpp"

namespace demlink::core {
namespace {

/// Every slot is listed exactly once in the cells, and each sits in the cell of its position.
void expectConsistent(const CellGrid& grid, const std::vector<Vec3>& positions) {
  const auto& d = grid.dims();
  const std::size_t cells = static_cast<std::size_t>(d[0] * d[1] * d[2]);
  std::vector<int> seen(positions.size(), 0);
  for (std::size_t c = 0; c < cells; ++c) {
    for (std::uint32_t slot : grid.cell(c)) {
      ++seen[slot];
      const auto k = grid.cellCoords(positions[slot]);
      EXPECT_EQ(grid.cellIndex(k[0], k[1], k[2]), c);
    }
  }
  for (int s : seen) EXPECT_EQ(s, 1);
}

TEST(CellGrid, HugeExtentGrowsCellsInsteadOfOverflowing) {
  const std::vector<Vec3> positions{{0.0, 0.0, 0.0}, {1e175, 0.0, 0.0}, {0.0, 1e175, 1e175}, {1e-3, 0.0, 0.0}};
  CellGrid grid;
  grid.build(positions, 1e-3);
  const auto& d = grid.dims();
  EXPECT_LE(static_cast<double>(d[0]) * static_cast<double>(d[1]) * static_cast<double>(d[2]),
            4.0 * static_cast<double>(positions.size()) + 64.0);
  EXPECT_GT(grid.cellSize(), 1e170);
  expectConsistent(grid, positions);
}

TEST(CellGrid, ExtentBeyondDoubleRangeUsesOneCellAlongThatAxis) {
  const double big = std::numeric_limits<double>::max();
  const std::vector<Vec3> positions{{-big, 0.0, 0.0}, {big, 0.0, 0.0}, {0.0, 0.0, 0.0}};
  CellGrid grid;
  grid.build(positions, 1.0);
  EXPECT_EQ(grid.dims()[0], 1);
  expectConsistent(grid, positions);
}

}  // namespace
}  // namespace demlink::core
