#pragma once
/// The dump body's surface: an open box with walls and a floor of finite thickness, as one
/// closed (watertight) triangle surface, written as binary STL for the RigidBody.
///
/// Why a thick, closed surface instead of an open box of single facets: contacts with
/// facets are two-sided, so a particle that falls onto a zero-thickness wall top could end
/// up on either side; a rim of finite width gives it something to rest on and keeps the
/// inside and outside apart, as a real body does.
#include <array>
#include <string>
#include <vector>

namespace demlink::examples::truck {

using Point = std::array<double, 3>;
using Triangle = std::array<Point, 3>;

/// Inner size and wall/floor thickness [m]. Frame: origin at the centre of the floor's top
/// (inner) surface, x along the length, z up; the cavity is x in [-L/2, L/2],
/// y in [-W/2, W/2], z in [0, wall_height].
struct DumpBodyShape {
  double length = 3.0;          ///< inner, along x [m]
  double width = 2.0;           ///< inner, along y [m]
  double wall_height = 0.6;     ///< above the floor's top [m]
  double wall_thickness = 0.08;  ///< [m]
  double floor_thickness = 0.1;  ///< [m]
};

/// 28 triangles with outward normals (counter-clockwise seen from outside).
[[nodiscard]] std::vector<Triangle> dumpBodyTriangles(const DumpBodyShape& shape);

/// Writes the triangles as binary STL; throws std::runtime_error naming the path on failure.
void writeBinaryStl(const std::string& path, const std::vector<Triangle>& triangles);

}  // namespace demlink::examples::truck
