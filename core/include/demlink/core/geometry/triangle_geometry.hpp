#pragma once
/// Closest point on a triangle, with the feature (face, edge or vertex) on which it lies.
///
/// Why: sphere-vs-mesh contact needs the closest surface point to the sphere centre, and the
/// contact de-duplication at shared edges and vertices needs to know *which* feature of the
/// triangle that point belongs to.
///
/// Math: the plane of triangle (a, b, c) is split into seven Voronoi regions (three vertex
/// regions, three edge regions, one face region). The region containing the query point p is
/// found with dot products of p - vertex against the edge vectors (the classic region tests
/// described in Ericson, "Real-Time Collision Detection", ch. 5.1.5), and the closest point is
/// then the vertex, the projection onto the edge line, or the projection onto the plane.
/// Only exact arithmetic on the inputs is used (no tolerances), so the result is continuous in p.
#include <cstdint>

#include "demlink/core/base/math_types.hpp"

namespace demlink::core {

/// Feature of a triangle (a, b, c) = (vertex 0, vertex 1, vertex 2).
/// Edge k joins vertex k and vertex (k + 1) mod 3: Edge0 = ab, Edge1 = bc, Edge2 = ca.
enum class TriangleFeature : std::uint8_t { Face, Edge0, Edge1, Edge2, Vertex0, Vertex1, Vertex2 };

/// True for Edge0, Edge1 and Edge2.
[[nodiscard]] constexpr bool isEdge(TriangleFeature f) {
  return f == TriangleFeature::Edge0 || f == TriangleFeature::Edge1 || f == TriangleFeature::Edge2;
}
/// True for Vertex0, Vertex1 and Vertex2.
[[nodiscard]] constexpr bool isVertex(TriangleFeature f) {
  return f == TriangleFeature::Vertex0 || f == TriangleFeature::Vertex1 ||
         f == TriangleFeature::Vertex2;
}

/// Closest point of a triangle to a query point and the feature it lies on.
/// For Vertex features `point` is bit-identical to that vertex.
struct ClosestPoint {
  Vec3 point;
  TriangleFeature feature;
};

/// Returns the point of triangle (a, b, c) closest to p (Euclidean distance) and its feature.
/// Points exactly on a region boundary are given the lower-dimensional feature (vertex before
/// edge before face). A degenerate (zero-area) triangle is treated as the union of its three
/// edges, so the result is always finite for finite inputs.
[[nodiscard]] ClosestPoint closestPointOnTriangle(const Vec3& p, const Vec3& a, const Vec3& b,
                                                  const Vec3& c);

}  // namespace demlink::core
