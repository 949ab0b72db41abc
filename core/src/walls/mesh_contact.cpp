/// Sphere-vs-mesh contact collection; see mesh_contact.hpp for the de-duplication rule.
///
/// Implementation notes: the raw contacts are appended to `out` directly and filtered in place
/// (no scratch allocation in this hot path). A contact marked for removal gets a negated
/// overlap; the marks are applied by a stable compaction after each de-duplication stage, so
/// every decision of a stage is taken against the complete set of that stage's input.
/// The number of contacts of one sphere is small (a handful), so the pairwise O(k^2) checks
/// are cheaper than building any adjacency structure.
#include "demlink/core/walls/mesh_contact.hpp"

#include <algorithm>
#include <cassert>
#include <cmath>
#include <cstddef>
#include <limits>

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

/// Squared distance from p to the bounding box of triangle (a, b, c): a cheap lower bound of
/// its distance to the triangle, whose closest point lies in that box. Each component is one
/// subtraction (relative error eps/2), so a bound above a reach that includes the rounding
/// of computed distances (distSlack) never rejects what the exact test would accept.
double squaredDistanceToBox(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c) {
  return (a.cwiseMin(b).cwiseMin(c) - p).cwiseMax(p - a.cwiseMax(b).cwiseMax(c)).cwiseMax(0.0).squaredNorm();
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
  // Point tolerance: relative to the radius, plus a few ulps of the coordinate magnitude,
  // because closest points of far-from-origin meshes carry rounding of about eps * |x|.
  // Computed distances carry the same absolute rounding (distSlack).
  const double coordScale = centre.cwiseAbs().maxCoeff() + radius;
  const double distSlack =
      kMeshContactUlpFactor * std::numeric_limits<double>::epsilon() * coordScale;
  const double tol = kMeshContactRelTolerance * radius + distSlack;
  const double tolDiff = 0.25 * tol;
  const double reject = (radius + distSlack) * (1.0 + 1e-12);
  const double reject2 = reject * reject;
  const double rejectPoint = (tol + distSlack) * (1.0 + 1e-12);
  const double rejectPoint2 = rejectPoint * rejectPoint;

  // Stage 0: raw contacts, one per distinct candidate triangle within reach.
  for (const std::uint32_t index : candidateTriangles) {
    assert(index < triangles.size());
    const Triangle& tri = triangles[index];
    assert(tri[0] < worldVertices.size() && tri[1] < worldVertices.size() &&
           tri[2] < worldVertices.size());
    const Vec3& a = worldVertices[tri[0]];
    const Vec3& b = worldVertices[tri[1]];
    const Vec3& c = worldVertices[tri[2]];
    // Cheap rejection before the exact test: a bounding box farther than the radius (plus
    // the rounding of computed distances, distSlack) from the centre cannot give a contact.
    if (squaredDistanceToBox(centre, a, b, c) > reject2) continue;
    const ClosestPoint cp = closestPointOnTriangle(centre, a, b, c);
    const Vec3 toCentre = centre - cp.point;
    const double dist2 = toCentre.squaredNorm();
    if (!(dist2 < radius2)) continue;
    const bool duplicate =
        std::any_of(out.begin() + static_cast<std::ptrdiff_t>(base), out.end(),
                    [index](const MeshContactPoint& m) { return m.triangle == index; });
    if (duplicate) continue;
    double dist = std::sqrt(dist2);
    Vec3 normal;
    if (cp.feature == TriangleFeature::Face || !(dist > 0.0)) {
      // Face region: the direction to the centre is +-(unit face normal) exactly; using the
      // face normal avoids the rounding of (centre - point)/dist for small distances and makes
      // the contact identical to an infinite-plane contact. This also covers a centre lying
      // exactly on the triangle (dist == 0), where no other direction is defined.
      const Vec3 n = (b - a).cross(c - a);
      const double nNorm = n.norm();
      if (!(nNorm > 0.0)) {
        if (!(dist > 0.0)) continue;  // zero-area triangle and centre on it: no direction
        normal = toCentre / dist;
      } else {
        const Vec3 unit = n / nNorm;
        const double height = (centre - a).dot(unit);
        normal = height < 0.0 ? Vec3(-unit) : unit;
        if (cp.feature == TriangleFeature::Face) dist = std::abs(height);
      }
    } else {
      normal = toCentre / dist;
    }
    if (!(dist < radius)) continue;
    out.push_back({index, cp.point, normal, radius - dist, cp.feature});
  }
  const std::size_t count = out.size() - base;
  if (count < 2) return;

  // Stage 1: drop edge/vertex contacts whose point lies on another contacting triangle that
  // has a face contact or a closer closest point (see the header for the rule).
  bool anyKept = false;
  for (std::size_t i = base; i < out.size(); ++i) {
    MeshContactPoint& ci = out[i];
    if (ci.feature == TriangleFeature::Face) {
      anyKept = true;
      continue;
    }
    const double distI = (centre - ci.point).norm();
    bool drop = false;
    for (std::size_t j = base; j < out.size() && !drop; ++j) {
      if (j == i) continue;
      const MeshContactPoint& cj = out[j];
      const double distJ = (centre - cj.point).norm();
      const bool closer = cj.feature == TriangleFeature::Face || distJ < distI ||
                          (distJ <= distI + distSlack && (cj.point - ci.point).norm() > tolDiff);
      if (!closer) continue;
      // Only triangles that reach ci's point within tol can hold it; the box test rejects
      // the others (most of a sphere's contacts on a fine mesh) without the exact one.
      const Triangle& tj = triangles[cj.triangle];
      if (squaredDistanceToBox(ci.point, worldVertices[tj[0]], worldVertices[tj[1]], worldVertices[tj[2]]) >
          rejectPoint2) {
        continue;
      }
      drop = distanceToTriangle(ci.point, tj, worldVertices) < tol;
    }
    if (drop) {
      ci.overlap = -ci.overlap;  // mark; later decisions still see the full geometry
    } else {
      anyKept = true;
    }
  }
  if (!anyKept) {
    // Only reachable through rounding in near-degenerate ties: keep the closest contact.
    auto best = out.begin() + static_cast<std::ptrdiff_t>(base);
    for (auto it = best; it != out.end(); ++it) {
      if (-it->overlap > -best->overlap) best = it;  // marked overlaps are negated
    }
    best->overlap = -best->overlap;
  }
  compactMarked(out, base);

  // Stage 2: merge coincident contacts, keeping the lowest triangle index.
  for (std::size_t i = base; i < out.size(); ++i) {
    for (std::size_t j = base; j < out.size(); ++j) {
      if (j == i || out[j].triangle > out[i].triangle) continue;
      if ((out[j].point - out[i].point).norm() < tol) {
        out[i].overlap = -out[i].overlap;
        break;
      }
    }
  }
  compactMarked(out, base);
}

}  // namespace demlink::core
