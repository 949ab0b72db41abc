#pragma once
/// A tetrahedral mesh for the FEM body: nodes, linear (4-node) or quadratic (10-node)
/// tetrahedra, and the boundary as triangles.
///
/// Node order inside an element is VTK's (VTK_TETRA, VTK_QUADRATIC_TETRA): corners 0..3, then
/// the mid-edge nodes of edges (0,1), (1,2), (0,2), (0,3), (1,3), (2,3). Gmsh orders the last
/// two the other way round ((2,3), (1,3)); gmsh_reader.cpp swaps them. Corners are ordered
/// so that the volume det(x1 - x0, x2 - x0, x3 - x0)/6 is positive.
///
/// The contact surface is made of linear triangles: a quadratic boundary face (3 corners,
/// 3 mid-edge nodes) is split into 4 triangles through its mid-edge nodes, so every boundary
/// node carries surface and the surface follows the quadratic element's edges.
#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "demlink/core/base/math_types.hpp"

namespace demlink::core {

struct TetMesh {
  std::vector<Vec3> nodes;          ///< [m]
  int order = 1;                    ///< 1: 4-node, 2: 10-node tetrahedra
  std::vector<std::uint32_t> tets;  ///< nodesPerTet() indices per element (VTK order)
  /// Boundary faces given by the file (3 or 6 nodes each, corners then mid-edge nodes
  /// (0,1), (1,2), (2,0)); empty when the file has none.
  std::vector<std::uint32_t> faces;
  /// Gmsh node tag of each node (empty for generated meshes).
  std::vector<std::uint64_t> tags;

  [[nodiscard]] std::size_t nodesPerTet() const { return order == 2 ? 10 : 4; }
  [[nodiscard]] std::size_t nodesPerFace() const { return order == 2 ? 6 : 3; }
  [[nodiscard]] std::size_t tetCount() const { return tets.size() / nodesPerTet(); }
};

/// Faces that belong to one tetrahedron only, oriented outward (counter-clockwise seen from
/// outside), nodesPerFace() indices each, in a deterministic order.
[[nodiscard]] std::vector<std::uint32_t> boundaryFaces(const TetMesh& mesh);

/// The contact triangles: mesh.faces when present (each turned outward when it matches a
/// boundary face), otherwise boundaryFaces(); quadratic faces split into 4 triangles.
[[nodiscard]] std::vector<std::array<std::uint32_t, 3>> surfaceTriangles(const TetMesh& mesh);

/// A box [lo, hi] cut into nx * ny * nz cells, each split into 6 tetrahedra around its
/// main diagonal (conforming between cells); order 2 adds the mid-edge nodes. For tests
/// and benchmarks.
[[nodiscard]] TetMesh boxTetMesh(const Vec3& lo, const Vec3& hi, int nx, int ny, int nz, int order);

/// Writes an ASCII Gmsh file, format "2.2" or "4.1" (tetrahedra and, if present, the faces).
void writeGmsh(const std::string& path, const TetMesh& mesh, const std::string& version);

}  // namespace demlink::core
