/// Closest point on a triangle by Voronoi-region classification.
///
/// Notation: ab = b - a, ac = c - a and, for a query point p, the six dot products
///   d1 = ab.(p-a)  d2 = ac.(p-a)  d3 = ab.(p-b)  d4 = ac.(p-b)  d5 = ab.(p-c)  d6 = ac.(p-c).
/// Vertex regions: p is in the region of a when d1 <= 0 and d2 <= 0 (it lies behind both edge
/// planes through a), and similarly for b (d3 >= 0, d4 <= d3) and c (d6 >= 0, d5 <= d6).
/// Edge regions: the scalars vc = d1*d4 - d3*d2, vb = d5*d2 - d1*d6, va = d3*d6 - d5*d4 are the
/// (unnormalised) barycentric coordinates of the projection of p onto the plane, i.e. signed
/// areas times |n|^2. A non-positive coordinate together with p lying between the two vertex
/// planes of that edge means p is in the edge region; the closest point is then the projection
/// onto the edge line. Otherwise p projects inside the face and (va, vb, vc)/(va+vb+vc) are the
/// barycentric coordinates of the closest point.
#include "demlink/core/geometry/triangle_geometry.hpp"

namespace demlink::core {
namespace {

/// Closest point on segment [s, e]; endpoints are reported as the given vertex features.
ClosestPoint closestOnSegment(const Vec3& p, const Vec3& s, const Vec3& e, TriangleFeature edge,
                              TriangleFeature startVertex, TriangleFeature endVertex) {
  const Vec3 se = e - s;
  const double len2 = se.squaredNorm();
  const double t = len2 > 0.0 ? se.dot(p - s) / len2 : 0.0;
  if (!(t > 0.0)) return {s, startVertex};
  if (!(t < 1.0)) return {e, endVertex};
  return {s + t * se, edge};
}

/// Fallback for (numerically) degenerate triangles: the best of the three edges.
ClosestPoint closestOnEdges(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c) {
  using F = TriangleFeature;
  const ClosestPoint candidates[3] = {closestOnSegment(p, a, b, F::Edge0, F::Vertex0, F::Vertex1),
                                      closestOnSegment(p, b, c, F::Edge1, F::Vertex1, F::Vertex2),
                                      closestOnSegment(p, c, a, F::Edge2, F::Vertex2, F::Vertex0)};
  const ClosestPoint* best = &candidates[0];
  double bestDist2 = (p - best->point).squaredNorm();
  for (const ClosestPoint& cand : candidates) {
    const double d2 = (p - cand.point).squaredNorm();
    if (d2 < bestDist2) {
      bestDist2 = d2;
      best = &cand;
    }
  }
  return *best;
}

}  // namespace

ClosestPoint closestPointOnTriangle(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c) {
  using F = TriangleFeature;
  const Vec3 ab = b - a;
  const Vec3 ac = c - a;

  // Vertex a.
  const Vec3 ap = p - a;
  const double d1 = ab.dot(ap);
  const double d2 = ac.dot(ap);
  if (d1 <= 0.0 && d2 <= 0.0) return {a, F::Vertex0};

  // Vertex b.
  const Vec3 bp = p - b;
  const double d3 = ab.dot(bp);
  const double d4 = ac.dot(bp);
  if (d3 >= 0.0 && d4 <= d3) return {b, F::Vertex1};

  // Edge ab: p is between the vertex planes of a and b and on the outer side of ab.
  const double vc = d1 * d4 - d3 * d2;
  if (vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0) {
    const double len2 = d1 - d3;  // = |ab|^2
    if (!(len2 > 0.0)) return closestOnEdges(p, a, b, c);
    const double t = d1 / len2;
    return {a + t * ab, F::Edge0};
  }

  // Vertex c.
  const Vec3 cp = p - c;
  const double d5 = ab.dot(cp);
  const double d6 = ac.dot(cp);
  if (d6 >= 0.0 && d5 <= d6) return {c, F::Vertex2};

  // Edge ca (reported as Edge2, which joins vertex 2 and vertex 0).
  const double vb = d5 * d2 - d1 * d6;
  if (vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0) {
    const double len2 = d2 - d6;  // = |ac|^2
    if (!(len2 > 0.0)) return closestOnEdges(p, a, b, c);
    const double t = d2 / len2;
    return {a + t * ac, F::Edge2};
  }

  // Edge bc.
  const double va = d3 * d6 - d5 * d4;
  const double fromB = d4 - d3;  // (c-b).(p-b)
  const double fromC = d5 - d6;  // (b-c).(p-c)
  if (va <= 0.0 && fromB >= 0.0 && fromC >= 0.0) {
    const double len2 = fromB + fromC;  // = |bc|^2
    if (!(len2 > 0.0)) return closestOnEdges(p, a, b, c);
    const double t = fromB / len2;
    return {b + t * (c - b), F::Edge1};
  }

  // Face interior. In exact arithmetic va, vb, vc > 0 here; rounding on a (nearly) degenerate
  // triangle can break that, in which case the edges give the correct answer.
  if (!(va > 0.0 && vb > 0.0 && vc > 0.0)) return closestOnEdges(p, a, b, c);
  const double inv = 1.0 / (va + vb + vc);
  const double v = vb * inv;
  const double w = vc * inv;
  const Vec3 q = a + v * ab + w * ac;
  if (!q.allFinite()) return closestOnEdges(p, a, b, c);
  return {q, F::Face};
}

}  // namespace demlink::core
