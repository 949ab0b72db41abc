#pragma once
/// A rigid triangle mesh (wall, drum, tool) whose motion is prescribed, not integrated from
/// forces. The particles push on it; the accumulated wrench is reported, not applied.
///
/// Why: boundaries in DEM are usually kinematic (a rotating drum, a moving plate). The engine
/// needs the current world-frame triangles for contact detection, the wall velocity at a
/// contact point for the tangential contact law, the reaction force/torque for output, and a
/// cheap bound on how far any vertex moved to decide when neighbour lists must be rebuilt.
///
/// Math: world vertex x_i = p + R(q) r_i, with r_i the body-frame vertex (relative to the
/// reference point) and p the reference point's world position. With constant linear velocity
/// v and world-frame angular velocity w over a step dt the motion is exact:
///   p(t+dt) = p + v dt,   q(t+dt) = dq * q,   dq = (cos(|w|dt/2), sin(|w|dt/2) w/|w|),
/// i.e. a rotation by angle |w|dt about the fixed world axis w/|w| (about the reference point).
/// Rigid-body velocity field: v(x) = v + w x (x - p). Torque about the reference point:
/// T = sum (x_k - p) x F_k.
/// Displacement bound since a mark (p0, q0): every vertex moved by at most
///   |p - p0| + 2 r_max sin(theta/2),   theta = rotation angle of q q0^-1,
/// since a rotation by theta moves a point at distance r from the axis point by 2 r sin(theta/2).
#include <array>
#include <cstdint>
#include <limits>
#include <string>
#include <vector>

#include "demlink/core/math_types.hpp"

namespace demlink::core {

/// Plain triangle mesh: vertices plus index triples (counter-clockwise = outward normal).
struct TriangleMesh {
  std::vector<Vec3> vertices;
  std::vector<std::array<std::uint32_t, 3>> triangles;
};

/// Closed box [lo, hi] as 8 vertices and 12 triangles with outward normals.
/// Throws InputError (field "box.hi") unless lo < hi component-wise and both are finite.
[[nodiscard]] TriangleMesh axisAlignedBoxMesh(const Vec3& lo, const Vec3& hi);

/// Flat rectangle in the plane z = centre.z, spanning centre +- (halfX, halfY), split into
/// nx * ny cells of two triangles each (all diagonals parallel, so every interior vertex is
/// shared by six triangles). Normals are +z. Vertex (i, j) has index j * (nx + 1) + i.
/// Throws InputError for non-positive half extents or nx, ny < 1.
[[nodiscard]] TriangleMesh rectangleMesh(const Vec3& centre, double halfX, double halfY,
                                         std::uint32_t nx, std::uint32_t ny);

/// Rigid triangle mesh under prescribed motion. Forces are world-frame, "on the mesh by the
/// particles"; torque is about the reference point. Not thread-safe: accumulate per thread
/// (force and torque about position()) and add the per-thread totals with addWrench().
class MeshBody {
 public:
  /// `localVertices` are relative to the body's reference point. The initial pose is the
  /// identity at the origin, so world == local until setPose/advance is called.
  /// Throws InputError for no triangles, an index out of range or a non-finite vertex.
  MeshBody(std::string name, std::vector<Vec3> localVertices,
           std::vector<std::array<std::uint32_t, 3>> triangles, std::uint32_t materialIndex = 0);

  /// Loads an STL file; vertices are stored relative to `referencePointInFile` (file
  /// coordinates). The pose is then set so that the mesh sits where the file put it
  /// (position = referencePointInFile, identity orientation). STL warnings are kept.
  [[nodiscard]] static MeshBody fromStl(std::string name, const std::string& path,
                                        const Vec3& referencePointInFile,
                                        std::uint32_t materialIndex = 0);

  /// Sets the pose and updates the world geometry. The quaternion is normalised.
  /// Throws InputError: "pose.position" if not finite, "pose.orientation" if not finite or
  /// (near) zero norm.
  void setPose(const Vec3& position, const Quat& orientation);
  /// Sets the velocities (linear [m/s], angular [rad/s], world frame). Throws InputError
  /// ("velocity.linear" / "velocity.angular") if not finite.
  void setVelocity(const Vec3& linear, const Vec3& angular);
  /// Advances the pose exactly over dt for constant velocities, then updates the world
  /// geometry. Throws InputError ("dt") if dt is not finite.
  void advance(double dt);
  /// Recomputes the world-frame vertices and triangle normals from the pose.
  void updateWorldGeometry();

  /// Velocity of the material point of the body currently at worldPoint: v + w x (x - p).
  [[nodiscard]] Vec3 velocityAt(const Vec3& worldPoint) const;
  /// Accumulates a force on the mesh applied at worldPoint, and its torque about the
  /// reference point.
  void addContactForce(const Vec3& forceOnMesh, const Vec3& worldPoint);
  /// Adds an already reduced force and torque (about the reference point) to the wrench.
  void addWrench(const Vec3& force, const Vec3& torqueAboutReference);
  /// Resets the accumulated force and torque to zero.
  void clearWrench();

  /// Collision window [s]: the body takes part in contacts at force evaluations at
  /// times t with from <= t < until; otherwise it is only a region in space (its
  /// pose still moves) and costs nothing in the contact stage. Default: always.
  /// from == until: never (a non-colliding body). Throws InputError ("active_from"
  /// / "active_until") for NaN or until < from.
  void setCollisionWindow(double from, double until);
  [[nodiscard]] bool collidesAt(double time) const { return time >= collideFrom_ && time < collideUntil_; }
  [[nodiscard]] bool everCollides() const { return collideFrom_ < collideUntil_; }
  [[nodiscard]] double collideFrom() const { return collideFrom_; }
  [[nodiscard]] double collideUntil() const { return collideUntil_; }

  /// Remembers the current pose as the reference for maxDisplacementSinceMark().
  void markNeighbourBuild();
  /// Upper bound on the displacement of any vertex since the last markNeighbourBuild()
  /// (or construction) [m].
  [[nodiscard]] double maxDisplacementSinceMark() const;

  [[nodiscard]] const std::string& name() const { return name_; }
  [[nodiscard]] const std::vector<Vec3>& localVertices() const { return localVertices_; }
  [[nodiscard]] const std::vector<std::array<std::uint32_t, 3>>& triangles() const {
    return triangles_;
  }
  [[nodiscard]] const Vec3& position() const { return position_; }
  [[nodiscard]] const Quat& orientation() const { return orientation_; }
  [[nodiscard]] const Vec3& linearVelocity() const { return linearVelocity_; }
  [[nodiscard]] const Vec3& angularVelocity() const { return angularVelocity_; }
  /// World-frame vertices, valid after the last setPose/advance/updateWorldGeometry.
  [[nodiscard]] const std::vector<Vec3>& worldVertices() const { return worldVertices_; }
  /// World-frame unit normals (b-a)x(c-a)/|...| per triangle (zero for a zero-area triangle).
  [[nodiscard]] const std::vector<Vec3>& triangleNormals() const { return worldNormals_; }
  [[nodiscard]] const Vec3& force() const { return force_; }
  [[nodiscard]] const Vec3& torque() const { return torque_; }
  [[nodiscard]] std::uint32_t materialIndex() const { return materialIndex_; }
  void setMaterialIndex(std::uint32_t index) { materialIndex_ = index; }
  /// Largest distance of a vertex from the reference point [m].
  [[nodiscard]] double boundingRadius() const { return boundingRadius_; }
  /// Warnings from loading (e.g. degenerate STL triangles dropped); empty otherwise.
  [[nodiscard]] const std::vector<std::string>& loadWarnings() const { return loadWarnings_; }

 private:
  friend class World;  // checkpoint.cpp saves and restores the private state
  std::string name_;
  std::vector<Vec3> localVertices_;
  std::vector<std::array<std::uint32_t, 3>> triangles_;
  std::vector<Vec3> localNormals_;
  std::vector<Vec3> worldVertices_;
  std::vector<Vec3> worldNormals_;
  std::vector<std::string> loadWarnings_;
  Vec3 position_ = Vec3::Zero();
  Quat orientation_ = Quat::Identity();
  Vec3 linearVelocity_ = Vec3::Zero();
  Vec3 angularVelocity_ = Vec3::Zero();
  Vec3 force_ = Vec3::Zero();
  Vec3 torque_ = Vec3::Zero();
  Vec3 markPosition_ = Vec3::Zero();
  Quat markOrientation_ = Quat::Identity();
  double boundingRadius_ = 0.0;
  double collideFrom_ = -std::numeric_limits<double>::infinity();  ///< [s]
  double collideUntil_ = std::numeric_limits<double>::infinity();  ///< [s]
  std::uint32_t materialIndex_ = 0;
};

}  // namespace demlink::core
