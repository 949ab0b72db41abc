/// Region shapes and placements (contract in region_shape.hpp).
///
/// An attached region's world pose is the body's pose composed with the region's
/// body-frame pose: c = p_body + R_body c_local, R = R_body R_local. A region moving
/// with constant velocity v is at c(t) = c0 + v t (orientation fixed).
#include "demlink/core/regions/region_shape.hpp"

#include <cmath>
#include <numbers>

#include "demlink/core/base/input_bounds.hpp"
#include "demlink/core/base/input_error.hpp"
#include "demlink/core/particles/sphere.hpp"
#include "demlink/core/base/unit_quaternion.hpp"
#include "demlink/core/walls/mesh_body.hpp"

namespace demlink::core {
namespace {

std::string formatVector(const Vec3& v) {
  return "(" + formatValue(v.x()) + ", " + formatValue(v.y()) + ", " + formatValue(v.z()) + ")";
}

}  // namespace

void RegionPlacement::validate(const std::string& fieldPrefix) {
  requireFiniteVector(fieldPrefix + ".centre", centre);
  requireFiniteVector(fieldPrefix + ".velocity", velocity);
  orientation = requireUnitQuaternion(fieldPrefix + ".orientation", orientation);
  if (attached_mesh && !velocity.isZero(0.0)) {
    throw InputError(fieldPrefix + ".velocity", formatVector(velocity),
                     "a region attached to a mesh body moves with it; give no velocity");
  }
}

void RegionPlacement::resolve(std::size_t meshCount, const std::string& fieldPrefix) const {
  if (attached_mesh && *attached_mesh >= meshCount) {
    throw InputError(fieldPrefix + ".attached_to", std::to_string(*attached_mesh),
                     "no such mesh body (the scene has " + std::to_string(meshCount) + ")");
  }
}

RegionPose RegionPlacement::poseAt(const std::vector<MeshBody>& meshes, double time) const {
  RegionPose pose;
  if (attached_mesh) {
    const MeshBody& body = meshes[*attached_mesh];
    const Mat3 bodyRotation = body.orientation().toRotationMatrix();
    pose.centre = body.position() + bodyRotation * centre;
    pose.rotation = bodyRotation * orientation.toRotationMatrix();
  } else {
    pose.centre = centre + time * velocity;
    pose.rotation = orientation.toRotationMatrix();
  }
  return pose;
}

double RegionPlacement::speedBound(const std::vector<MeshBody>& meshes, double time, double extent) const {
  if (!attached_mesh) return velocity.norm();
  const MeshBody& body = meshes[*attached_mesh];
  const double arm = (poseAt(meshes, time).centre - body.position()).norm() + extent;  // [m]
  return body.linearVelocity().norm() + body.angularVelocity().norm() * arm;
}

void applyRegionChange(const RegionChange& change, double time, VolumeShape& shape, RegionPlacement& placement,
                       const std::string& fieldPrefix) {
  VolumeShape newShape = shape;
  if (change.size) {
    if (shape.kind() != VolumeShape::Kind::Box) {
      throw InputError(fieldPrefix + ".size", formatVector(*change.size), "the region is a sphere; give a radius");
    }
    newShape = VolumeShape::box(*change.size, fieldPrefix);
  }
  if (change.radius) {
    if (shape.kind() != VolumeShape::Kind::Sphere) {
      throw InputError(fieldPrefix + ".radius", formatValue(*change.radius), "the region is a box; give a size");
    }
    newShape = VolumeShape::sphere(*change.radius, fieldPrefix);
  }
  RegionPlacement newPlacement = placement;
  // A region moving at a constant velocity is placed by its centre at t = 0.
  if (change.centre) newPlacement.centre = *change.centre - time * placement.velocity;
  if (change.orientation) newPlacement.orientation = *change.orientation;
  newPlacement.validate(fieldPrefix);
  shape = newShape;
  placement = newPlacement;
}

VolumeShape VolumeShape::box(const Vec3& sides, const std::string& fieldPrefix) {
  static constexpr const char* kAxes[3] = {"x", "y", "z"};
  for (int k = 0; k < 3; ++k) requirePositive(fieldPrefix + ".size." + kAxes[k], sides[k]);
  VolumeShape shape;
  shape.kind_ = Kind::Box;
  shape.half_sides_ = 0.5 * sides;
  return shape;
}

VolumeShape VolumeShape::sphere(double radius, const std::string& fieldPrefix) {
  requirePositive(fieldPrefix + ".radius", radius);
  VolumeShape shape;
  shape.kind_ = Kind::Sphere;
  shape.radius_ = radius;
  return shape;
}

double VolumeShape::volume() const {
  if (kind_ == Kind::Sphere) return sphereVolume(radius_);
  return 8.0 * half_sides_.prod();
}

SurfaceShape SurfaceShape::rectangle(double length, double width, const std::string& fieldPrefix) {
  requirePositive(fieldPrefix + ".length", length);
  requirePositive(fieldPrefix + ".width", width);
  SurfaceShape shape;
  shape.kind_ = Kind::Rectangle;
  shape.half_length_ = 0.5 * length;
  shape.half_width_ = 0.5 * width;
  return shape;
}

SurfaceShape SurfaceShape::disc(double radius, const std::string& fieldPrefix) {
  requirePositive(fieldPrefix + ".radius", radius);
  SurfaceShape shape;
  shape.kind_ = Kind::Disc;
  shape.radius_ = radius;
  return shape;
}

double SurfaceShape::boundingRadius() const {
  return kind_ == Kind::Disc ? radius_ : std::hypot(half_length_, half_width_);
}

double SurfaceShape::area() const {
  return kind_ == Kind::Disc ? std::numbers::pi * radius_ * radius_ : 4.0 * half_length_ * half_width_;
}

Quat surfaceOrientation(const Vec3& normal, const Vec3& lengthAxis, const std::string& fieldPrefix) {
  requireFiniteVector(fieldPrefix + ".normal", normal);
  requireFiniteVector(fieldPrefix + ".length_axis", lengthAxis);
  const double length = normal.norm();
  if (!(length > 0.0)) throw InputError(fieldPrefix + ".normal", formatVector(normal), "must be a non-zero vector");
  const Vec3 n = normal / length;
  Vec3 u = n.unitOrthogonal();
  if (!lengthAxis.isZero(0.0)) {
    const Vec3 inPlane = lengthAxis - lengthAxis.dot(n) * n;
    if (!(inPlane.norm() > 1.0e-9 * lengthAxis.norm())) {
      throw InputError(fieldPrefix + ".length_axis", formatVector(lengthAxis),
                       "must not be parallel to the normal " + formatVector(normal));
    }
    u = inPlane.normalized();
  }
  Mat3 rotation;
  rotation.col(0) = u;
  rotation.col(1) = n.cross(u);
  rotation.col(2) = n;
  return Quat(rotation).normalized();
}

}  // namespace demlink::core
