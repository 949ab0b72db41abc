#pragma once
/// The bucket's surface: an open shell (back plate, bottom, two side plates) in the bucket
/// frame of excavator_model.hpp (origin at the bucket pivot, x towards the teeth, y
/// lateral, z towards the shell), plus the region the fill sensor watches.
///
/// Why a profile polygon: a real bucket's back curves into its bottom and ends at the
/// teeth; three straight plates along a four-point profile keep that shape with 10
/// triangles, and the side plates are the same polygon. Facet contacts are two-sided, so
/// the plates need no thickness.
#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include <Eigen/Core>

namespace demlink::examples::excavator {

struct BucketMesh {
  std::vector<Eigen::Vector3d> vertices;                 ///< bucket frame [m]
  std::vector<std::array<std::uint32_t, 3>> triangles;   ///< indices into vertices
};

/// Profile corners (x, z) from the pivot to the teeth [m] and the width [m].
inline constexpr std::array<std::array<double, 2>, 4> kBucketProfile{{{0.0, 0.0}, {0.15, 0.55}, {0.6, 0.65}, {1.05, 0.1}}};
inline constexpr double kBucketWidth = 1.2;

/// The fill sensor's box in the bucket frame: the profile's bounding box over the full
/// width, plus up to 0.15 m of heap beyond the mouth [m]. Why the bounding box and not a
/// box inside the shell: the profile is a skewed quadrilateral, and an inner box missed the
/// corner at the teeth and the deep corner — it reported 211 kg carried when 389 kg reached
/// the truck. The price: while the bucket is buried, the two slivers of the box outside the
/// plates (behind the back plate, below the bottom plate) also count pit gravel; once the
/// bucket is lifted they are empty, so the mass carried to the truck is exact.
inline const Eigen::Vector3d kFillBoxCentre{0.525, 0.0, 0.25};
inline const Eigen::Vector3d kFillBoxSize{1.05, 1.2, 0.8};

/// The shell's triangles.
[[nodiscard]] BucketMesh makeBucketMesh();

/// Writes the mesh as binary STL with core's writer and returns the file's bytes (the
/// RigidBody's stl_data).
[[nodiscard]] std::string writeBucketStl(const BucketMesh& mesh, const std::string& path);

/// Volume enclosed by the profile and the mouth times the width [m^3] (struck capacity).
[[nodiscard]] double bucketCapacity();

}  // namespace demlink::examples::excavator
