#pragma once
/// Closed, outward-oriented triangle meshes with known mass properties, for the tests of
/// solids read from STL and of the clump fit.
#include <array>
#include <cmath>
#include <cstdint>
#include <numbers>
#include <vector>

#include "demlink/core/walls/mesh_body.hpp"
#include "demlink/core/geometry/stl_reader.hpp"

namespace demlink::core::test {

inline StlMesh boxMesh(const Vec3& lo, const Vec3& hi) {
  const TriangleMesh box = axisAlignedBoxMesh(lo, hi);
  return {box.vertices, box.triangles, {}};
}

/// Corners at `origin` and origin + size along each axis.
inline StlMesh cornerTetrahedron(const Vec3& origin, double size) {
  StlMesh mesh;
  mesh.vertices = {origin, origin + Vec3(size, 0, 0), origin + Vec3(0, size, 0), origin + Vec3(0, 0, size)};
  mesh.triangles = {{0, 2, 1}, {0, 1, 3}, {0, 3, 2}, {1, 2, 3}};
  return mesh;
}

/// A convex solid from rings of `segments` points each (bottom to top) closed by a point
/// below the first ring and one above the last; triangles oriented outward (away from
/// `inside`, a point inside the solid).
inline StlMesh ringSolid(const std::vector<std::vector<Vec3>>& rings, const Vec3& bottom, const Vec3& top,
                         const Vec3& inside) {
  StlMesh mesh;
  const auto segments = static_cast<std::uint32_t>(rings.front().size());
  mesh.vertices.push_back(bottom);
  for (const auto& ring : rings) mesh.vertices.insert(mesh.vertices.end(), ring.begin(), ring.end());
  mesh.vertices.push_back(top);
  const auto topIndex = static_cast<std::uint32_t>(mesh.vertices.size() - 1);
  const auto at = [segments](std::size_t ring, std::uint32_t k) {
    return static_cast<std::uint32_t>(1 + ring * segments + k % segments);
  };
  const auto add = [&mesh, &inside](std::uint32_t a, std::uint32_t b, std::uint32_t c) {
    const Vec3& pa = mesh.vertices[a];
    const Vec3 normal = (mesh.vertices[b] - pa).cross(mesh.vertices[c] - pa);
    if (normal.dot(pa - inside) >= 0.0) {
      mesh.triangles.push_back({a, b, c});
    } else {
      mesh.triangles.push_back({a, c, b});
    }
  };
  for (std::uint32_t k = 0; k < segments; ++k) {
    add(0, at(0, k), at(0, k + 1));
    add(topIndex, at(rings.size() - 1, k), at(rings.size() - 1, k + 1));
    for (std::size_t r = 0; r + 1 < rings.size(); ++r) {
      add(at(r, k), at(r, k + 1), at(r + 1, k));
      add(at(r, k + 1), at(r + 1, k + 1), at(r + 1, k));
    }
  }
  return mesh;
}

inline std::vector<Vec3> circle(double radius, double z, std::uint32_t segments) {
  std::vector<Vec3> ring;
  for (std::uint32_t k = 0; k < segments; ++k) {
    const double phi = 2.0 * std::numbers::pi * k / segments;
    ring.emplace_back(radius * std::cos(phi), radius * std::sin(phi), z);
  }
  return ring;
}

/// A sphere of radius R about the origin: `rings` latitude rings of 2 x rings points.
inline StlMesh uvSphere(double radius, std::uint32_t rings) {
  std::vector<std::vector<Vec3>> latitude;
  for (std::uint32_t r = 1; r < rings; ++r) {
    const double theta = std::numbers::pi * (1.0 - static_cast<double>(r) / rings);
    latitude.push_back(circle(radius * std::sin(theta), radius * std::cos(theta), 2 * rings));
  }
  return ringSolid(latitude, Vec3(0, 0, -radius), Vec3(0, 0, radius), Vec3::Zero());
}

/// A regular n-gon prism (circumradius R) from z = 0 to z = height.
inline StlMesh polygonPrism(double radius, double height, std::uint32_t sides) {
  return ringSolid({circle(radius, 0.0, sides), circle(radius, height, sides)}, Vec3::Zero(), Vec3(0, 0, height),
                   Vec3(0, 0, 0.5 * height));
}

/// A capsule along z: a cylinder of radius R and length `length` (centred on the origin)
/// with hemispherical ends; `rings` latitude rings per hemisphere.
inline StlMesh capsule(double radius, double length, std::uint32_t rings) {
  std::vector<std::vector<Vec3>> latitude;
  const std::uint32_t segments = 4 * rings;
  for (std::uint32_t r = 1; r <= rings; ++r) {
    const double theta = 0.5 * std::numbers::pi * (1.0 - static_cast<double>(r) / rings);
    latitude.push_back(circle(radius * std::cos(theta), -0.5 * length - radius * std::sin(theta), segments));
  }
  for (std::uint32_t r = 0; r < rings; ++r) {
    const double theta = 0.5 * std::numbers::pi * static_cast<double>(r) / rings;
    latitude.push_back(circle(radius * std::cos(theta), 0.5 * length + radius * std::sin(theta), segments));
  }
  return ringSolid(latitude, Vec3(0, 0, -0.5 * length - radius), Vec3(0, 0, 0.5 * length + radius), Vec3::Zero());
}

}  // namespace demlink::core::test
