#pragma once
/// The inside of a closed triangle mesh sampled on a regular grid: which sample points lie
/// inside, and roughly how deep.
///
/// Inside test: one vertical ray per grid column. Each triangle whose projection covers the
/// column adds its crossing height with the sign of its normal's z component; walking down
/// from above, a point is inside when the signed crossings above it sum to more than zero.
/// The projected edge tests are evaluated with each edge's end points in one fixed order
/// (lower vertex index first), so the two triangles sharing an edge see exactly opposite
/// values and a ray near the edge is counted by exactly one of them (a watertight test).
/// The grid is shifted by a small generic fraction of a cell so rays do not pass exactly
/// through the vertices of meshes with round coordinates.
///
/// Depth: the Euclidean distance from each inside sample to the nearest outside sample
/// (the grid padded with outside samples), by the separable exact distance transform of
/// Felzenszwalb and Huttenlocher, "Distance Transforms of Sampled Functions", Theory of
/// Computing 8 (2012), DOI 10.4086/toc.2012.v008a019. It differs from the distance to the
/// surface by less than one grid spacing; distanceToSurface() gives the exact value.
#include <array>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "demlink/core/base/math_types.hpp"
#include "demlink/core/geometry/stl_reader.hpp"

namespace demlink::core {

struct SolidSamples {
  Vec3 origin = Vec3::Zero();         ///< sample (0, 0, 0) [m]
  double spacing = 0.0;               ///< between neighbouring samples [m]
  std::array<std::size_t, 3> counts{};  ///< samples along x, y, z
  std::vector<std::uint8_t> inside;   ///< 1 inside, 0 outside; index = i + nx (j + ny k)
  std::vector<double> depth;          ///< distance to the nearest outside sample [m]; 0 outside

  [[nodiscard]] std::size_t size() const { return inside.size(); }
  [[nodiscard]] Vec3 point(std::size_t i, std::size_t j, std::size_t k) const {
    return origin + spacing * Vec3(static_cast<double>(i), static_cast<double>(j), static_cast<double>(k));
  }
  [[nodiscard]] Vec3 point(std::size_t index) const {
    return point(index % counts[0], (index / counts[0]) % counts[1], index / (counts[0] * counts[1]));
  }
};

/// Samples the solid bounded by `mesh` (closed and outward-oriented: requireClosedSurface)
/// with `cellsAlongLongest` samples along the bounding box's longest side (>= 2).
[[nodiscard]] SolidSamples sampleSolid(const StlMesh& mesh, std::size_t cellsAlongLongest);

/// Distance from `p` to the nearest point of the mesh's triangles [m] (O(triangles)).
[[nodiscard]] double distanceToSurface(const StlMesh& mesh, const Vec3& p);

}  // namespace demlink::core
