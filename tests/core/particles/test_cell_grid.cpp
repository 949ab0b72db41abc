// The sparse multi-level cell grid: under extreme particle extents (found by fuzzing the
// co-simulation host: a lattice spacing of 1e175 m overflowed a dense grid's cell count)
// every particle stays listed exactly once, and near queries find every particle in
// reach whatever the extents.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <random>
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

TEST(CellGrid, PartnerBlockHoldsEveryLargePartnerOfASmallParticleInFewerCells) {
  // 1:10 radii: small spheres of 0.5 mm (level 0) and large ones of 5 mm (a higher
  // level, cells of 10.25 mm). Every large partner of a small sphere (within r_i + r_j +
  // skin) must lie in a cell of its partnerBlock; the blocks hold far fewer than the 27
  // cells around (the saving the block exists for).
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> u(0.0, 0.1);
  std::vector<Vec3> positions;
  std::vector<double> radii;
  for (int i = 0; i < 2000; ++i) {
    positions.emplace_back(u(rng), u(rng), u(rng));
    radii.push_back(i % 20 == 0 ? 5e-3 : 5e-4);
  }
  const double skin = 2.5e-4;
  CellGrid grid;
  grid.build(positions, radii, skin);
  ASSERT_EQ(grid.levelCount(), 2u);
  double blockCells = 0.0;
  std::size_t partners = 0;
  std::size_t smalls = 0;
  for (std::size_t i = 0; i < positions.size(); ++i) {
    if (grid.levelOfSlot(i) != 0) continue;
    ++smalls;
    const CellGrid::CellBlock b = grid.partnerBlock(1, positions[i], radii[i]);
    double cells = 1.0;
    for (int d = 0; d < 3; ++d) cells *= static_cast<double>(b.hi[d] - b.lo[d] + 1);
    blockCells += cells;
    for (std::size_t j = 0; j < positions.size(); ++j) {
      const double cutoff = radii[i] + radii[j] + skin;
      if (grid.levelOfSlot(j) != 1 || (positions[j] - positions[i]).squaredNorm() >= cutoff * cutoff) continue;
      ++partners;
      const CellGrid::CellCoords c = grid.cellOf(1, positions[j]);
      for (int d = 0; d < 3; ++d) {
        EXPECT_TRUE(c[d] >= b.lo[d] && c[d] <= b.hi[d]) << "small " << i << ", large " << j << ", axis " << d;
      }
    }
  }
  EXPECT_GT(partners, 100u) << "the test needs small spheres near large ones";
  // Reach 5.75 mm of cells 10.25 mm: 1 + 11.5 / 10.25 = 2.12 cells per axis on average.
  EXPECT_LT(blockCells / static_cast<double>(smalls), 12.0);
}


/// Particles of radius 0.5 at cell centres (cells of 1 m with no skin): `perCell` in each
/// cell of an nx x ny x nz block (binary fractions: the cells the grid finds are exact).
std::vector<Vec3> block(int nx, int ny, int nz, int perCell = 1) {
  std::vector<Vec3> positions;
  for (int z = 0; z < nz; ++z) {
    for (int y = 0; y < ny; ++y) {
      for (int x = 0; x < nx; ++x) {
        for (int k = 0; k < perCell; ++k) positions.emplace_back(x + 0.5, y + 0.5, z + 0.25 + 0.5 * k / perCell);
      }
    }
  }
  return positions;
}

/// spatialOrder of `positions` (radius 0.5, skin 0: cells of 1 m), checked to be a
/// permutation; returns the positions in that order.
std::vector<Vec3> inSpatialOrder(const std::vector<Vec3>& positions) {
  CellGrid grid;
  grid.build(positions, std::vector<double>(positions.size(), 0.5), 0.0);
  const std::vector<std::uint32_t> order = grid.spatialOrder(positions);
  std::vector<std::uint32_t> sorted = order;
  std::sort(sorted.begin(), sorted.end());
  for (std::uint32_t k = 0; k < sorted.size(); ++k) EXPECT_EQ(sorted[k], k);
  std::vector<Vec3> ordered;
  for (const std::uint32_t slot : order) ordered.push_back(positions[slot]);
  return ordered;
}

/// Whether the cells along `ordered` never go back along `slow`, and, within one cell
/// layer of `slow`, never back along `middle`.
bool runsAlong(const std::vector<Vec3>& ordered, int slow, int middle) {
  for (std::size_t k = 1; k < ordered.size(); ++k) {
    const double a = std::floor(ordered[k - 1][slow]);
    const double b = std::floor(ordered[k][slow]);
    if (b < a) return false;
    if (b == a && std::floor(ordered[k][middle]) < std::floor(ordered[k - 1][middle])) return false;
  }
  return true;
}

TEST(CellGrid, SpatialOrderRunsAlongTheAxisWithTheThinnestLayers) {
  // A bed 20 cells long in x, 10 in y, 4 high: an x layer holds 40 particles, a y layer
  // 80, a z layer 200. The pair loop's chunks are at least one layer of the slowest
  // axis: x gives twenty of them, z (the order before) four.
  EXPECT_TRUE(runsAlong(inSpatialOrder(block(20, 10, 4)), 0, 1));
  // A tall column: z.
  EXPECT_TRUE(runsAlong(inSpatialOrder(block(3, 4, 30)), 2, 1));
  // Equal layers everywhere keep z, then y, slowest.
  EXPECT_TRUE(runsAlong(inSpatialOrder(block(5, 5, 5)), 2, 1));
}

TEST(CellGrid, SpatialOrderWeighsLayersByTheirParticlesNotTheirCount) {
  // A settling column: a dense bed 10 x 8 cells, 8 particles a cell, one layer high,
  // and one particle in each of 40 cells above it. z has 41 layers and x only 10, but the
  // bottom z layer holds 640 of the 680 particles: one chunk would hold nearly all the
  // work. The fullest x layer holds 104 (y: 120).
  std::vector<Vec3> positions = block(10, 8, 1, 8);
  for (int z = 1; z <= 40; ++z) positions.emplace_back(4.5, 4.5, z + 0.5);
  EXPECT_TRUE(runsAlong(inSpatialOrder(positions), 0, 1));
}

TEST(CellGrid, SpatialOrderIgnoresAFarParticle) {
  // A bed long in y; one particle a million cells away along x (the layer count along x
  // is then a sparse range: the rule counts particles per layer without a dense
  // histogram) leaves y the slowest axis.
  std::vector<Vec3> positions = block(4, 16, 3);
  positions.emplace_back(1e6, 0.5, 0.5);
  const std::vector<Vec3> ordered = inSpatialOrder(positions);
  std::vector<Vec3> bed(ordered.begin(), ordered.end());
  bed.erase(std::remove_if(bed.begin(), bed.end(), [](const Vec3& x) { return x[0] > 100.0; }), bed.end());
  EXPECT_TRUE(runsAlong(bed, 1, 0));
}

}  // namespace
}  // namespace demlink::core
