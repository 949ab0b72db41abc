// The sparse multi-level cell grid: under extreme particle extents (found by fuzzing the
// co-simulation host: a lattice spacing of 1e175 m overflowed a dense grid's cell count)
// every particle stays listed exactly once, and near queries find every particle in
// reach whatever the extents.
#include <gtest/gtest.h>

#include <limits>
#include <vector>

#include "demlink/core/particles/cell_grid.hpp"

namespace demlink::core {
namespace {

/// Every slot is listed exactly once by a box query covering everything, and each
/// particle finds itself among its near cells.
void expectConsistent(const CellGrid& grid, const std::vector<Vec3>& positions) {
  const double inf = std::numeric_limits<double>::infinity();
  std::vector<int> seen(positions.size(), 0);
  grid.forEachInBox(Vec3::Constant(-inf), Vec3::Constant(inf), [&](std::uint32_t slot) { ++seen[slot]; });
  for (int s : seen) EXPECT_EQ(s, 1);
  for (std::uint32_t i = 0; i < positions.size(); ++i) {
    int self = 0;
    grid.forEachNear(grid.levelOfSlot(i), positions[i], [&](std::uint32_t j) { self += j == i ? 1 : 0; });
    EXPECT_EQ(self, 1) << "slot " << i;
  }
}

TEST(CellGrid, HugeExtentKeepsCellsSmallAndSparse) {
  const std::vector<Vec3> positions{{0.0, 0.0, 0.0}, {1e175, 0.0, 0.0}, {0.0, 1e175, 1e175}, {1e-3, 0.0, 0.0}};
  const std::vector<double> radii(positions.size(), 4e-4);
  CellGrid grid;
  grid.build(positions, radii, 2e-4);
  ASSERT_EQ(grid.levelCount(), 1u);
  EXPECT_DOUBLE_EQ(grid.cellSize(0), 1e-3);
  EXPECT_LE(grid.cellCount(0), positions.size());
  expectConsistent(grid, positions);
  // The two close particles see each other.
  int found = 0;
  grid.forEachNear(0, positions[0], [&](std::uint32_t j) { found += j == 3 ? 1 : 0; });
  EXPECT_EQ(found, 1);
}

TEST(CellGrid, ExtentBeyondDoubleRangeStaysExact) {
  const double big = std::numeric_limits<double>::max();
  const std::vector<Vec3> positions{{-big, 0.0, 0.0}, {big, 0.0, 0.0}, {0.0, 0.0, 0.0}};
  CellGrid grid;
  grid.build(positions, std::vector<double>(3, 0.25), 0.5);
  expectConsistent(grid, positions);
}

TEST(CellGrid, RadiusClassesAFactorTwoApart) {
  // Radii 1, 1.9 (class 0), 2.5 (class 1), 10 (class 3): three levels, cells 2 r_max + skin.
  const std::vector<Vec3> positions{{0, 0, 0}, {5, 0, 0}, {0, 5, 0}, {0, 0, 30}};
  CellGrid grid;
  grid.build(positions, std::vector<double>{1.0, 1.9, 2.5, 10.0}, 0.1);
  ASSERT_EQ(grid.levelCount(), 3u);
  EXPECT_DOUBLE_EQ(grid.cellSize(0), 3.9);
  EXPECT_DOUBLE_EQ(grid.cellSize(1), 5.1);
  EXPECT_DOUBLE_EQ(grid.cellSize(2), 20.1);
  EXPECT_EQ(grid.levelOfSlot(1), 0u);
  EXPECT_EQ(grid.levelOfSlot(3), 2u);
  expectConsistent(grid, positions);
}

}  // namespace
}  // namespace demlink::core
