#pragma once
/// Shapes and placements of measurement and removal regions: volumes (oriented box,
/// sphere) for sinks and region sensors, surfaces (oriented rectangle, disc) for flow
/// sensors, and where they are (fixed, moving with a constant velocity, or carried by a
/// mesh body).
///
/// Why a separate shape and placement: the same membership test serves a fixed sink and a
/// sensor riding in an excavator bucket; only the pose differs. Every test is done in the
/// region's local frame: x_local = R^T (x - c), with c the centre and R the rotation
/// (local -> world). A box contains x_local when |x_local,k| <= l_k / 2 for k = x, y, z;
/// a sphere when |x_local| <= r (true sphere membership, not the circumscribed cube the
/// coupling paper's eq. 4 tests). A surface lies in its local z = 0 plane with normal
/// local +z; a rectangle spans |x| <= length/2, |y| <= width/2, a disc x^2 + y^2 <= r^2.
/// Boundary points count as inside.
#include <cmath>
#include <cstddef>
#include <optional>
#include <string>
#include <vector>

#include "demlink/core/base/math_types.hpp"

namespace demlink::core {

class MeshBody;

/// A region's current pose: centre [m] and rotation local -> world.
struct RegionPose {
  Vec3 centre = Vec3::Zero();
  Mat3 rotation = Mat3::Identity();

  /// Coordinates of the world point x in the region's frame [m].
  [[nodiscard]] Vec3 toLocal(const Vec3& x) const { return rotation.transpose() * (x - centre); }
};

/// Where a region is. With `attached_mesh` set, `centre` and `orientation` are given in
/// that mesh body's frame (relative to its reference point) and the region follows the
/// body; otherwise they are world-frame values at t = 0 and the region moves with the
/// constant `velocity`.
struct RegionPlacement {
  Vec3 centre = Vec3::Zero();             ///< [m]
  Quat orientation = Quat::Identity();    ///< local -> world (or -> body) [-]; normalised by validate()
  Vec3 velocity = Vec3::Zero();           ///< constant world velocity of the region [m/s]
  std::optional<std::size_t> attached_mesh;  ///< index into World::meshes()

  /// Checks finiteness, a non-zero quaternion (then normalises it) and that a region is
  /// not both attached and moving. Throws InputError naming fieldPrefix + ".centre",
  /// ".orientation" or ".velocity".
  void validate(const std::string& fieldPrefix);
  /// Checks that the attached mesh exists among the world's `meshCount` mesh bodies; throws
  /// InputError naming fieldPrefix + ".attached_to" otherwise.
  void resolve(std::size_t meshCount, const std::string& fieldPrefix) const;
  /// The pose at `time` [s], the world's mesh bodies `meshes` in their current poses.
  [[nodiscard]] RegionPose poseAt(const std::vector<MeshBody>& meshes, double time) const;
  /// Upper bound on the speed of any point of the region within `extent` [m] of its
  /// centre [m/s], at `time` [s].
  [[nodiscard]] double speedBound(const std::vector<MeshBody>& meshes, double time, double extent) const;
};

/// A closed volume: an oriented box or a sphere, in its local frame.
class VolumeShape {
 public:
  enum class Kind { Box, Sphere };

  /// A box with side lengths `sides` [m] along the local axes. Throws InputError naming
  /// fieldPrefix + ".size" unless all three are finite and > 0.
  [[nodiscard]] static VolumeShape box(const Vec3& sides, const std::string& fieldPrefix);
  /// A sphere of radius [m]. Throws InputError naming fieldPrefix + ".radius" unless > 0.
  [[nodiscard]] static VolumeShape sphere(double radius, const std::string& fieldPrefix);

  /// True when the local point lies inside or on the boundary.
  [[nodiscard]] bool containsLocal(const Vec3& local) const {
    if (kind_ == Kind::Sphere) return local.squaredNorm() <= radius_ * radius_;
    return (local.cwiseAbs().array() <= half_sides_.array()).all();
  }
  /// True when the world point x lies inside the region at `pose`.
  [[nodiscard]] bool contains(const RegionPose& pose, const Vec3& x) const { return containsLocal(pose.toLocal(x)); }

  [[nodiscard]] Kind kind() const { return kind_; }
  [[nodiscard]] const Vec3& halfSides() const { return half_sides_; }  ///< box only [m]
  [[nodiscard]] double radius() const { return radius_; }             ///< sphere only [m]
  /// Largest distance of a point of the shape from its centre [m].
  [[nodiscard]] double boundingRadius() const { return kind_ == Kind::Sphere ? radius_ : half_sides_.norm(); }
  /// Volume [m^3].
  [[nodiscard]] double volume() const;

 private:
  Kind kind_ = Kind::Sphere;
  Vec3 half_sides_ = Vec3::Zero();
  double radius_ = 0.0;
};

/// A run-time change of a volume region (a co-simulation client's RegionInput); each given
/// value replaces the current one. Centre and orientation are in the placement's frame
/// (world, or the attached body's).
struct RegionChange {
  std::optional<Vec3> centre;       ///< [m]; a region moving at a constant velocity: its centre now
  std::optional<Quat> orientation;  ///< [-], unit within 1e-6
  std::optional<Vec3> size;         ///< box side lengths [m]
  std::optional<double> radius;     ///< sphere radius [m]
};

/// Applies `change` at world time `time` [s] to `shape` and `placement`, all or nothing.
/// Throws InputError naming fieldPrefix + ".centre", ".orientation", ".size" or ".radius"
/// (a size for a sphere or a radius for a box is refused too).
void applyRegionChange(const RegionChange& change, double time, VolumeShape& shape, RegionPlacement& placement,
                       const std::string& fieldPrefix);

/// A flat surface in the local z = 0 plane (normal +z): a rectangle or a disc.
class SurfaceShape {
 public:
  enum class Kind { Rectangle, Disc };

  /// A rectangle length x width [m] (length along local x). Throws InputError naming
  /// fieldPrefix + ".length" / ".width" unless finite and > 0.
  [[nodiscard]] static SurfaceShape rectangle(double length, double width, const std::string& fieldPrefix);
  /// A disc of radius [m]. Throws InputError naming fieldPrefix + ".radius" unless > 0.
  [[nodiscard]] static SurfaceShape disc(double radius, const std::string& fieldPrefix);

  /// True when the in-plane local point (x, y) lies on the surface (boundary included).
  [[nodiscard]] bool containsInPlane(double x, double y) const {
    if (kind_ == Kind::Disc) return x * x + y * y <= radius_ * radius_;
    return std::abs(x) <= half_length_ && std::abs(y) <= half_width_;
  }

  [[nodiscard]] Kind kind() const { return kind_; }
  [[nodiscard]] double halfLength() const { return half_length_; }  ///< rectangle only [m]
  [[nodiscard]] double halfWidth() const { return half_width_; }    ///< rectangle only [m]
  [[nodiscard]] double radius() const { return radius_; }           ///< disc only [m]
  /// Largest distance of a point of the surface from its centre [m].
  [[nodiscard]] double boundingRadius() const;
  /// Area [m^2].
  [[nodiscard]] double area() const;

 private:
  Kind kind_ = Kind::Disc;
  double half_length_ = 0.0;
  double half_width_ = 0.0;
  double radius_ = 0.0;
};

/// The rotation (local -> world) of a surface with unit normal along `normal` and local x
/// along the part of `lengthAxis` perpendicular to the normal (any perpendicular axis when
/// lengthAxis is zero). Throws InputError naming fieldPrefix + ".normal" for a zero or
/// non-finite normal and fieldPrefix + ".length_axis" for an axis parallel to the normal.
[[nodiscard]] Quat surfaceOrientation(const Vec3& normal, const Vec3& lengthAxis, const std::string& fieldPrefix);

}  // namespace demlink::core
