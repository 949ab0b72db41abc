#pragma once
/// Sphere-vs-triangle-mesh contact detection with de-duplication at shared edges and vertices.
///
/// Why: a sphere resting on a triangulated surface touches several triangles at once whenever
/// its closest surface point lies on an edge or vertex shared by them. Counting one contact per
/// triangle would double (or sextuple) the force there, and a sphere rolling across a flat,
/// finely meshed plane would feel bumps. The rule below keeps one contact per distinct closest
/// point, so a sphere on a flat mesh behaves exactly like a sphere on an infinite plane.
///
/// Math: for every candidate triangle the closest point q to the centre c is found by
/// Voronoi-region classification (triangle_geometry.hpp). The triangle is in contact when
/// |c - q| < radius; the contact normal is (c - q)/|c - q| and overlap = radius - |c - q|.
/// For face contacts the same quantities are evaluated as +-n and radius - |(c - a).n| with the
/// unit face normal n (mathematically identical, but free of the rounding of q when |c - q|
/// is small), so a face contact equals the infinite-plane contact to machine precision.
/// De-duplication, using only geometry, so no adjacency table is needed. The point tolerance
/// is tol = 1e-9 * radius + 64 * eps * (max|centre_i| + radius) (the second term covers the
/// rounding of coordinates far from the origin):
///  1. face contacts are kept;
///  2. an edge or vertex contact at q of triangle A is dropped if another triangle T in contact
///     contains q (distance from q to T < tol) and T is better placed: T's own contact is a
///     face contact, or T's closest point is strictly closer to c than q, or the two distances
///     are equal to rounding (within 64 eps |c|) while T's closest point differs from q by more
///     than tol/4. In all three cases the surface continues from q into T and gets closer to
///     the centre (the closest point of a triangle is unique, so a *different* closest point
///     of a triangle containing q is closer), i.e. q is not a local minimum of the distance:
///     the centre is in the face region of a triangle sharing that edge or vertex, or further
///     along the surface. No "closer by more than a tolerance" margin is used: near a shared
///     vertex the distance differences are second order (offset^2 / (2 h)), and any margin
///     would keep an extra edge contact next to the face contact for centres within
///     ~sqrt(2 h margin) of the vertex. If rounding in a degenerate tie would drop every
///     contact, the one with the largest overlap is kept;
///  3. remaining contacts whose points coincide (within tol) are merged into one, keeping the
///     contact of the lowest triangle index (deterministic, independent of candidate order).
///     This merges the edge/vertex contacts of all triangles around a shared edge or vertex.
///     It also merges the rare pair of *face* contacts that arises when the centre is exactly
///     above a shared edge and rounding classifies both triangles as Face.
/// For a convex closed mesh and an outside centre this yields exactly one contact; in a
/// concave valley each face the sphere touches gives its own contact.
/// Cost: up to k^2 closest-point evaluations for k triangles within reach; fine when triangles
/// are not much smaller than the sphere (k is then a handful), quadratic for very fine meshes.
///
/// Sidedness: triangles are treated as two-sided. A centre behind a triangle (on the negative
/// side of its normal (b-a)x(c-a)) still gives a contact whose normal points from the contact
/// point towards the centre, i.e. it pushes the sphere further back. Callers that need
/// one-sided walls must filter on the triangle normal themselves.
#include <array>
#include <cstdint>
#include <span>
#include <vector>

#include "demlink/core/base/math_types.hpp"
#include "demlink/core/geometry/triangle_geometry.hpp"

namespace demlink::core {

/// One sphere-vs-mesh contact.
struct MeshContactPoint {
  std::uint32_t triangle;   ///< index into the triangle array
  Vec3 point;               ///< closest point on the triangle (world frame) [m]
  Vec3 normal;              ///< unit vector from `point` towards the sphere centre
  double overlap;           ///< radius - |centre - point| > 0 [m]
  TriangleFeature feature;  ///< feature of `triangle` on which `point` lies
};

/// Relative tolerance (times the radius) of the "same point" / "point on triangle" tests.
inline constexpr double kMeshContactRelTolerance = 1e-9;
/// Multiple of machine epsilon times the coordinate magnitude added to that tolerance.
inline constexpr double kMeshContactUlpFactor = 64.0;

/// Appends to `out` the de-duplicated contacts of the sphere (centre, radius) with the triangles
/// listed in `candidateTriangles` (indices into `triangles`, whose entries index
/// `worldVertices`). Contacts already in `out` are left untouched. Duplicate candidate indices
/// are ignored. The order of the appended contacts follows `candidateTriangles`.
/// If the centre lies exactly on a triangle (|c - q| == 0) the normal is the triangle's unit
/// normal (b-a)x(c-a)/|...|; such a contact on a zero-area triangle is skipped.
/// Preconditions (checked by assert only): radius > 0, all indices in range.
void collectSphereMeshContacts(const Vec3& centre, double radius,
                               std::span<const std::uint32_t> candidateTriangles,
                               std::span<const Vec3> worldVertices,
                               std::span<const std::array<std::uint32_t, 3>> triangles,
                               std::vector<MeshContactPoint>& out);

/// A pair-loop chunk's part of a mesh's contacts (contact_stage.hpp, meshContactSlots):
/// its contacts' scratch and the forces on the surface it leaves, in near-list order.
struct MeshContactChunk {
  struct SurfaceLoad {
    std::uint32_t triangle;
    Vec3 point;   ///< contact point [m]
    Vec3 force;   ///< force on the surface [N]
  };
  std::vector<MeshContactPoint> contacts;
  std::vector<SurfaceLoad> loads;
};

}  // namespace demlink::core
