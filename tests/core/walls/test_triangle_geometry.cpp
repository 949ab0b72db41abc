/// Tests for closestPointOnTriangle: every Voronoi region against hand-computed answers, and
/// random triangles/points against brute-force minimisation over a fine barycentric grid.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <random>
#include <utility>

#include "demlink/core/geometry/triangle_geometry.hpp"

namespace demlink::core {
namespace {

using F = TriangleFeature;

struct RegionCase {
  Vec3 p;
  Vec3 expected;
  F feature;
};

// Right triangle a=(0,0,0), b=(1,0,0), c=(0,1,0); expected points worked out by hand.
TEST(TriangleGeometry, EveryVoronoiRegionOfRightTriangle) {
  const Vec3 a(0, 0, 0), b(1, 0, 0), c(0, 1, 0);
  const RegionCase cases[] = {
      {Vec3(0.2, 0.3, 0.5), Vec3(0.2, 0.3, 0.0), F::Face},
      {Vec3(0.2, 0.3, -0.7), Vec3(0.2, 0.3, 0.0), F::Face},
      {Vec3(0.5, -0.3, 0.4), Vec3(0.5, 0.0, 0.0), F::Edge0},  // below ab
      {Vec3(0.8, 0.8, -0.2), Vec3(0.5, 0.5, 0.0), F::Edge1},  // beyond bc: projection (0.5,0.5)
      {Vec3(0.9, 0.3, 0.0), Vec3(0.8, 0.2, 0.0), F::Edge1},   // t = (p-b).(c-b)/|c-b|^2 = 0.2
      {Vec3(-0.3, 0.5, 0.1), Vec3(0.0, 0.5, 0.0), F::Edge2},  // left of ca
      {Vec3(-0.5, -0.5, 0.3), a, F::Vertex0},
      {Vec3(-0.1, -0.0, 2.0), a, F::Vertex0},
      {Vec3(1.5, -0.2, 0.0), b, F::Vertex1},
      {Vec3(2.0, 0.5, 0.0), b, F::Vertex1},  // (c-b).(p-b) = -1+0.5 < 0
      {Vec3(-0.1, 1.5, 1.0), c, F::Vertex2},
  };
  for (const auto& tc : cases) {
    const ClosestPoint cp = closestPointOnTriangle(tc.p, a, b, c);
    EXPECT_EQ(cp.feature, tc.feature) << "p = " << tc.p.transpose();
    EXPECT_NEAR((cp.point - tc.expected).norm(), 0.0, 1e-15) << "p = " << tc.p.transpose();
  }
}

TEST(TriangleGeometry, VertexFeatureReturnsTheVertexExactly) {
  const Vec3 a(0.1, 0.2, 0.3), b(1.7, 0.1, -0.2), c(0.3, 1.9, 0.4);
  const Vec3 out = a + 0.5 * ((a - b).normalized() + (a - c).normalized());
  const ClosestPoint cp = closestPointOnTriangle(out, a, b, c);
  ASSERT_EQ(cp.feature, F::Vertex0);
  EXPECT_EQ(cp.point, a);
}

TEST(TriangleGeometry, PointOnRegionBoundaryGetsLowerDimensionalFeature) {
  const Vec3 a(0, 0, 0), b(1, 0, 0), c(0, 1, 0);
  // Exactly above edge ab (boundary between face and edge region).
  EXPECT_EQ(closestPointOnTriangle(Vec3(0.5, 0.0, 1.0), a, b, c).feature, F::Edge0);
  // Exactly above vertex a.
  EXPECT_EQ(closestPointOnTriangle(Vec3(0.0, 0.0, 1.0), a, b, c).feature, F::Vertex0);
}

/// Barycentric coordinates (u, v, w) of q with respect to (a, b, c), least squares.
Vec3 barycentric(const Vec3& q, const Vec3& a, const Vec3& b, const Vec3& c) {
  Eigen::Matrix<double, 3, 2> m;
  m.col(0) = b - a;
  m.col(1) = c - a;
  const Eigen::Vector2d vw = m.colPivHouseholderQr().solve(q - a);
  return {1.0 - vw.x() - vw.y(), vw.x(), vw.y()};
}

/// Minimum distance from p to the grid points a + (i/n) ab + (j/n) ac, i + j <= n.
double bruteForceDistance(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c, int n) {
  const Vec3 ab = b - a, ac = c - a, ap = p - a;
  double best2 = std::numeric_limits<double>::infinity();
  for (int i = 0; i <= n; ++i) {
    const double s = static_cast<double>(i) / n;
    for (int j = 0; i + j <= n; ++j) {
      const double t = static_cast<double>(j) / n;
      const double dx = ap.x() - s * ab.x() - t * ac.x();
      const double dy = ap.y() - s * ab.y() - t * ac.y();
      const double dz = ap.z() - s * ab.z() - t * ac.z();
      best2 = std::min(best2, dx * dx + dy * dy + dz * dz);
    }
  }
  return std::sqrt(best2);
}

/// Independent exact reference: projection onto the plane if it falls inside (barycentric
/// test), otherwise the best of the three clamped segment projections.
Vec3 referenceClosestPoint(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c) {
  const Vec3 n = (b - a).cross(c - a).normalized();
  const Vec3 proj = p - n * n.dot(p - a);
  if (barycentric(proj, a, b, c).minCoeff() >= 0.0) return proj;
  Vec3 best = a;
  for (const auto& [s, e] : {std::pair{a, b}, std::pair{b, c}, std::pair{c, a}}) {
    const double t = std::clamp((p - s).dot(e - s) / (e - s).squaredNorm(), 0.0, 1.0);
    const Vec3 q = s + t * (e - s);
    if ((p - q).norm() < (p - best).norm()) best = q;
  }
  return best;
}

TEST(TriangleGeometry, RandomPointsMatchBruteForceAndFeatureIsConsistent) {
  std::mt19937_64 rng(12345);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  const auto randVec = [&](double scale) -> Vec3 {
    return Vec3(unit(rng), unit(rng), unit(rng)) * scale;
  };
  constexpr int kGrid = 120;
  std::array<int, 7> seen{};
  for (int trial = 0; trial < 400; ++trial) {
    const Vec3 a = randVec(1.0), b = randVec(1.0), c = randVec(1.0);
    const Vec3 n = (b - a).cross(c - a);
    if (n.norm() < 0.05) continue;  // keep the grid-based tolerance meaningful
    const Vec3 p = randVec(2.0);
    const ClosestPoint cp = closestPointOnTriangle(p, a, b, c);
    const double ours = (p - cp.point).norm();
    const double maxEdge = std::max({(b - a).norm(), (c - b).norm(), (a - c).norm()});
    const double gridError = 2.0 * maxEdge / kGrid;  // bound on the distance to the nearest node
    const double brute = bruteForceDistance(p, a, b, c, kGrid);
    // The returned point is on the triangle, so it cannot beat the true minimum; it must be at
    // least as good as every grid node, and no grid node can be much closer than the optimum.
    EXPECT_LE(ours, brute + 1e-12);
    EXPECT_GE(ours, brute - gridError);
    const Vec3 ref = referenceClosestPoint(p, a, b, c);
    EXPECT_NEAR((cp.point - ref).norm(), 0.0, 1e-9) << "p = " << p.transpose();

    const Vec3 bc = barycentric(cp.point, a, b, c);
    const double eps = 1e-9;
    EXPECT_GE(bc.minCoeff(), -eps) << "closest point must lie on the triangle";
    // Feature consistency: which barycentric coordinates vanish, and orthogonality of p - q.
    const Vec3 d = p - cp.point;
    switch (cp.feature) {
      case F::Face:
        EXPECT_GT(bc.minCoeff(), -eps);
        EXPECT_NEAR(d.cross(n.normalized()).norm(), 0.0, 1e-9);
        break;
      case F::Edge0:
        EXPECT_NEAR(bc[2], 0.0, eps);
        EXPECT_NEAR(d.dot((b - a).normalized()), 0.0, 1e-9);
        break;
      case F::Edge1:
        EXPECT_NEAR(bc[0], 0.0, eps);
        EXPECT_NEAR(d.dot((c - b).normalized()), 0.0, 1e-9);
        break;
      case F::Edge2:
        EXPECT_NEAR(bc[1], 0.0, eps);
        EXPECT_NEAR(d.dot((a - c).normalized()), 0.0, 1e-9);
        break;
      case F::Vertex0:
        EXPECT_EQ(cp.point, a);
        break;
      case F::Vertex1:
        EXPECT_EQ(cp.point, b);
        break;
      case F::Vertex2:
        EXPECT_EQ(cp.point, c);
        break;
    }
    ++seen[static_cast<std::size_t>(cp.feature)];
  }
  for (std::size_t k = 0; k < seen.size(); ++k) EXPECT_GT(seen[k], 0) << "feature " << k;
}

TEST(TriangleGeometry, DegenerateTriangleGivesFiniteClosestPoint) {
  // Collinear vertices: the closest point must be the closest point of segment [a, b].
  const Vec3 a(0, 0, 0), b(2, 0, 0), c(1, 0, 0);
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> unit(-3.0, 3.0);
  for (int k = 0; k < 200; ++k) {
    const Vec3 p(unit(rng), unit(rng), unit(rng));
    const ClosestPoint cp = closestPointOnTriangle(p, a, b, c);
    ASSERT_TRUE(cp.point.allFinite());
    const double t = std::clamp(p.x() / 2.0, 0.0, 1.0);
    EXPECT_NEAR((cp.point - Vec3(2.0 * t, 0, 0)).norm(), 0.0, 1e-12);
  }
  // All three vertices equal.
  const ClosestPoint cp = closestPointOnTriangle(Vec3(1, 2, 3), a, a, a);
  EXPECT_EQ(cp.point, a);
}

}  // namespace
}  // namespace demlink::core
