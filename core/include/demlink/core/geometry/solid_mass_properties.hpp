#pragma once
/// Exact volume, centre of mass and inertia of the solid a closed triangle mesh bounds.
///
/// Method (divergence theorem): the solid is the signed sum of the tetrahedra spanned by a
/// reference point and each triangle; a triangle seen counter-clockwise from outside gives
/// a positive tetrahedron. For a tetrahedron with one corner at the reference point and the
/// others at a, b, c (relative to it), with V = a . (b x c) / 6 and s = a + b + c:
///   integral of 1 = V,  integral of x = V s / 4,
///   integral of x x^T = V / 20 (a a^T + b b^T + c c^T + s s^T)
/// (the monomial integrals over a simplex, k! l! m! / (k + l + m + 3)! times 6V). These are
/// exact polynomials, so the result is exact to rounding for any closed polyhedron; the
/// reference point is the bounding-box centre, so far-off shapes lose no digits.
#include <string>

#include "demlink/core/base/math_types.hpp"
#include "demlink/core/geometry/principal_axes.hpp"
#include "demlink/core/geometry/stl_reader.hpp"

namespace demlink::core {

/// Mass properties per unit density, in the mesh's units (m for an STL in metres).
struct SolidMassProperties {
  double volume = 0.0;                ///< [m^3]
  Vec3 centroid = Vec3::Zero();       ///< centre of mass at uniform density [m]
  Mat3 inertia = Mat3::Zero();        ///< inertia tensor about the centroid per unit density [m^5]
  PrincipalAxes principal;            ///< of `inertia` [m^5], ascending
  double bounding_radius = 0.0;       ///< largest distance from the centroid to a vertex [m]
};

/// Integrates the solid bounded by `mesh`, which must be closed and consistently oriented
/// (requireClosedSurface). Throws InputError (field `field`) when the enclosed volume is not
/// positive: negative means the triangles are wound inward (clockwise seen from outside),
/// about zero (below 1e-9 x the bounding-box diagonal cubed) that the surface encloses
/// nothing (e.g. a flat sheet given twice).
[[nodiscard]] SolidMassProperties solidMassProperties(const StlMesh& mesh, const std::string& field);

}  // namespace demlink::core
