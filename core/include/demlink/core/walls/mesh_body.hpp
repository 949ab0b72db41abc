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

#include "demlink/core/base/math_types.hpp"

namespace demlink::core {

class StateWriter;
class StateReader;

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
  /// The same two with the triangle of the contact first (a rigid body ignores it), so
  /// one contact loop (contact_stage.hpp) serves meshes and deformable surfaces.
  [[nodiscard]] Vec3 velocityAt(std::uint32_t /*triangle*/, const Vec3& worldPoint) const {
    return velocityAt(worldPoint);
  }
  void addContactForce(std::uint32_t /*triangle*/, const Vec3& worldPoint, const Vec3& forceOnMesh) {
    addContactForce(forceOnMesh, worldPoint);
  }
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
  [[nodiscard]] bool collidesAt(double time) const { return time >= collide_from_ && time < collide_until_; }
  [[nodiscard]] bool everCollides() const { return collide_from_ < collide_until_; }

  /// Remembers the current pose as the reference for maxDisplacementSinceMark().
  void markNeighbourBuild();
  /// Upper bound on the displacement of any vertex since the last markNeighbourBuild()
  /// (or construction) [m].
  [[nodiscard]] double maxDisplacementSinceMark() const;
  /// The pose at the last markNeighbourBuild().
  [[nodiscard]] const Vec3& markPosition() const { return state_.mark_position; }
  [[nodiscard]] const Quat& markOrientation() const { return state_.mark_orientation; }

  [[nodiscard]] const std::string& name() const { return name_; }
  [[nodiscard]] const std::vector<Vec3>& localVertices() const { return local_vertices_; }
  [[nodiscard]] const std::vector<std::array<std::uint32_t, 3>>& triangles() const {
    return triangles_;
  }
  [[nodiscard]] const Vec3& position() const { return state_.position; }
  [[nodiscard]] const Quat& orientation() const { return state_.orientation; }
  [[nodiscard]] const Vec3& linearVelocity() const { return state_.linear_velocity; }
  [[nodiscard]] const Vec3& angularVelocity() const { return state_.angular_velocity; }
  /// World-frame vertices, valid after the last setPose/advance/updateWorldGeometry.
  [[nodiscard]] const std::vector<Vec3>& worldVertices() const { return world_vertices_; }
  /// World-frame unit normals (b-a)x(c-a)/|...| per triangle (zero for a zero-area triangle).
  [[nodiscard]] const std::vector<Vec3>& triangleNormals() const { return world_normals_; }
  [[nodiscard]] const Vec3& force() const { return state_.force; }
  [[nodiscard]] const Vec3& torque() const { return state_.torque; }
  [[nodiscard]] std::uint32_t materialIndex() const { return material_index_; }
  /// Declares the body rigid (World::addMesh then gives it the rigid twin of its
  /// material, Material::rigid).
  void setRigid(bool rigid) { rigid_ = rigid; }
  [[nodiscard]] bool rigid() const { return rigid_; }
  /// Replaces the material (World::addMesh for a rigid body's twin material).
  void setMaterialIndex(std::uint32_t materialIndex) { material_index_ = materialIndex; }
  /// Declared largest speed of any point of the body [m/s] (a client-driven
  /// body's promise; 0: none). The time-step limit is validated against it.
  /// Throws InputError ("max_speed") unless finite and >= 0.
  void setSpeedLimit(double speed);
  [[nodiscard]] double speedLimit() const { return speed_limit_; }
  /// Largest distance of a vertex from the reference point [m].
  [[nodiscard]] double boundingRadius() const { return bounding_radius_; }
  /// Warnings from loading (e.g. degenerate STL triangles dropped); empty otherwise.
  [[nodiscard]] const std::vector<std::string>& loadWarnings() const { return load_warnings_; }

  /// What of a mesh body evolves during a run: pose, twist, wrench and the pose at
  /// the last neighbour build (displacement mark). Geometry, material and collision
  /// window come from the scene.
  struct State {
    Vec3 position = Vec3::Zero();
    Quat orientation = Quat::Identity();
    Vec3 linear_velocity = Vec3::Zero();
    Vec3 angular_velocity = Vec3::Zero();
    Vec3 force = Vec3::Zero();
    Vec3 torque = Vec3::Zero();
    Vec3 mark_position = Vec3::Zero();
    Quat mark_orientation = Quat::Identity();
  };
  /// Checkpoint payload (one mesh of section MESH, before its near list): name,
  /// triangle count, then the State fields in declaration order.
  void save(StateWriter& out) const;
  /// Reads what save() wrote and checks it against this body (same name and
  /// triangle count, unit orientation); throws InputError via in.fail(). Does not
  /// change the body, so a world can read every section before replacing anything
  /// (and without copying the geometry).
  [[nodiscard]] State readState(StateReader& in) const;
  /// Takes over a State from readState() and updates the world geometry.
  void restoreState(const State& state);

 private:
  std::string name_;
  std::vector<Vec3> local_vertices_;
  std::vector<std::array<std::uint32_t, 3>> triangles_;
  std::vector<Vec3> local_normals_;
  std::vector<Vec3> world_vertices_;
  std::vector<Vec3> world_normals_;
  std::vector<std::string> load_warnings_;
  State state_;
  double bounding_radius_ = 0.0;
  double speed_limit_ = 0.0;  ///< [m/s], 0: none declared
  bool rigid_ = false;
  double collide_from_ = -std::numeric_limits<double>::infinity();  ///< [s]
  double collide_until_ = std::numeric_limits<double>::infinity();  ///< [s]
  std::uint32_t material_index_ = 0;
};

}  // namespace demlink::core
