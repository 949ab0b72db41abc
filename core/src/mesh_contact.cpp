/// Sphere-vs-mesh contact collection; see mesh_contact.hpp for the de-duplication rule.
///
/// Implementation notes: the raw contacts are appended to `out` directly and filtered in place
/// (no scratch allocation in this hot path). A contact marked for removal gets a negated
/// overlap; the marks are applied by a stable compaction after each de-duplication stage, so
/// every decision of a stage is taken against the complete set of that stage's input.
/// The number of contacts of one sphere is small (a handful), so the pairwise O(k^2) checks
/// are cheaper than building any adjacency structure.
#include "demlink/core/mesh_contact.hpp"

#include <algorithm>
#include <cassert>
#include <cmath>
#include <cstddef>

namespace demlink::core {
namespace {

using Triangle = std::array<std::uint32_t, 3>;

/// Removes the contacts in out[base, end) whose overlap is negative, preserving order.
void compactMarked(std::vector<MeshContactPoint>& out, std::size_t base) {
  const auto first = out.begin() + static_cast<std::ptrdiff_t>(base);
  out.erase(
      std::remove_if(first, out.end(), [](const MeshContactPoint& c) { return c.overlap < 0.0; }),
      out.end());
}

double distanceToTriangle(const Vec3& p, const Triangle& tri, std::span<const Vec3> vertices) {
  const ClosestPoint cp =
      closestPointOnTriangle(p, vertices[tri[0]], vertices[tri[1]], vertices[tri[2]]);
  return (cp.point - p).norm();
}

}  // namespace

void collectSphereMeshContacts(const Vec3& centre, double radius,
                               std::span<const std::uint32_t> candidateTriangles,
                               std::span<const Vec3> worldVertices,
                               std::span<const std::array<std::uint32_t, 3>> triangles,
                               std::vector<MeshContactPoint>& out) {
  assert(radius > 0.0);
  const std::size_t base = out.size();
  const double radius2 = radius * radius;
  const double tol = kMeshContactRelTolerance * radius;

  // Stage 0: raw contacts, one per distinct candidate triangle within reach.
  for (const std::uint32_t index : candidateTriangles) {
    assert(index < triangles.size());
    const Triangle& tri = triangles[index];
    assert(tri[0] < worldVertices.size() && tri[1] < worldVertices.size() &&
           tri[2] < worldVertices.size());
    const Vec3& a = worldVertices[tri[0]];
    const Vec3& b = worldVertices[tri[1]];
    const Vec3& c = worldVertices[tri[2]];
    const ClosestPoint cp = closestPointOnTriangle(centre, a, b, c);
    const Vec3 toCentre = centre - cp.point;
    const double dist2 = toCentre.squaredNorm();
    if (!(dist2 < radius2)) continue;
    const bool duplicate =
        std::any_of(out.begin() + static_cast<std::ptrdiff_t>(base), out.end(),
                    [index](const MeshContactPoint& m) { return m.triangle == index; });
    if (duplicate) continue;
    const double dist = std::sqrt(dist2);
    Vec3 normal;
    if (dist > 0.0) {
      normal = toCentre / dist;
    } else {
      // Centre exactly on the triangle: the only meaningful direction is the face normal.
      const Vec3 n = (b - a).cross(c - a);
      const double nNorm = n.norm();
      if (!(nNorm > 0.0)) continue;
      normal = n / nNorm;
    }
    out.push_back({index, cp.point, normal, radius - dist, cp.feature});
  }
  const std::size_t count = out.size() - base;
  if (count < 2) return;

  // Stage 1: drop edge/vertex contacts whose point lies on another contacting triangle that
  // has a face contact or a strictly closer closest point.
  for (std::size_t i = base; i < out.size(); ++i) {
    MeshContactPoint& ci = out[i];
    if (ci.feature == TriangleFeature::Face) continue;
    const double distI = (centre - ci.point).norm();
    for (std::size_t j = base; j < out.size(); ++j) {
      if (j == i) continue;
      const MeshContactPoint& cj = out[j];
      const double distJ = (centre - cj.point).norm();
      const bool betterThere = cj.feature == TriangleFeature::Face || distJ < distI - tol;
      if (!betterThere) continue;
      if (distanceToTriangle(ci.point, triangles[cj.triangle], worldVertices) < tol) {
        ci.overlap = -std::abs(ci.overlap);  // mark; decided against the unmarked geometry
        break;
      }
    }
  }
  compactMarked(out, base);

  // Stage 2: merge coincident contacts, keeping the lowest triangle index.
  for (std::size_t i = base; i < out.size(); ++i) {
    for (std::size_t j = base; j < out.size(); ++j) {
      if (j == i || out[j].triangle > out[i].triangle) continue;
      if ((out[j].point - out[i].point).norm() < tol) {
        out[i].overlap = -std::abs(out[i].overlap);
        break;
      }
    }
  }
  compactMarked(out, base);
}

}  // namespace demlink::core
