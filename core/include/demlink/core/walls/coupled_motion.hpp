#pragma once
/// Motion coupling of a rigid body whose pose a co-simulation client prescribes at sample
/// steps (docs/cosim.md, "Motion coupling").
///
/// Why a constant twist per interval and a snap at its end: the client knows the body's
/// pose only at its sample times. Jumping the mesh to each sent pose would push particles
/// through it in one step (an energy injection); interpolating only the client's twist
/// would drift. Instead, at sample k the body has a target pose for the end of the
/// interval (PREDICTED: the sent pose advanced by the sent twist over T; LAGGED: the sent
/// pose itself), and the mesh moves at the ONE constant twist that carries it from where it
/// is now to that target in T:
///   u     = (P_target - P_now) / T
///   omega = axis * angle / T,  (axis, angle) of q_target q_now^-1, the shorter way round.
/// MeshBody::advance integrates a constant twist exactly (translation plus rotation about a
/// fixed world axis through the reference point), so after the interval's steps the pose
/// equals the target up to rounding; it is then set to the target exactly. The mesh moves
/// continuously, lands on every target, and prediction errors are removed in the next
/// interval instead of accumulating.
///
/// Wrench: the impulse sum(F dt) and angular impulse sum(T dt) of the force ON the body BY
/// the particles (world frame, torque about the reference point) are accumulated after every
/// step; their mean over the interval is impulse / T.
#include <cstddef>
#include <cstdint>

#include "demlink/core/base/math_types.hpp"

namespace demlink::core {

class MeshBody;

/// How the target pose of an interval follows from the sample sent at its start.
enum class MotionMode : std::uint8_t {
  Predicted,  ///< target = sent pose advanced by the sent twist over the interval
  Lagged,     ///< target = sent pose (the body follows one interval late)
};

struct RigidPose {
  Vec3 position = Vec3::Zero();          ///< reference point, world frame [m]
  Quat orientation = Quat::Identity();   ///< body frame -> world [-]
};

struct RigidTwist {
  Vec3 linear = Vec3::Zero();   ///< velocity of the reference point [m/s]
  Vec3 angular = Vec3::Zero();  ///< world frame [rad/s]
};

/// Wrench ON the body BY the particles over one interval (world frame, about the reference point).
struct IntervalWrench {
  Vec3 mean_force = Vec3::Zero();   ///< impulse / interval [N]
  Vec3 mean_torque = Vec3::Zero();  ///< angular impulse / interval [N m]
  Vec3 force = Vec3::Zero();        ///< at the end of the interval [N]
  Vec3 torque = Vec3::Zero();       ///< at the end of the interval [N m]
};

/// The pose `sample` advanced by a constant twist over `seconds`: translation by
/// linear * seconds, rotation by |angular| * seconds about the world axis angular / |angular|.
[[nodiscard]] RigidPose advancePose(const RigidPose& sample, const RigidTwist& twist, double seconds);

/// The target at the end of an interval of `seconds` for a sample sent at its start.
[[nodiscard]] RigidPose targetPose(MotionMode mode, const RigidPose& sample, const RigidTwist& twist,
                                   double seconds);

/// The constant twist that carries `from` to `to` in `seconds` (> 0), rotating the shorter way.
[[nodiscard]] RigidTwist twistBetween(const RigidPose& from, const RigidPose& to, double seconds);

/// Drives one mesh of a world through successive sample intervals. The caller passes the
/// mesh (World::mesh(meshIndex())) and the world's time step [s] to each call.
class CoupledMotion {
 public:
  CoupledMotion(std::size_t meshIndex, MotionMode mode) : mesh_(meshIndex), mode_(mode) {}

  /// Starts an interval of `steps` (>= 1) world steps at the world's current step: the
  /// target follows from the sample (mode), the mesh gets the constant twist that reaches
  /// it. Resets the wrench accumulators.
  void beginInterval(MeshBody& mesh, double timeStep, const RigidPose& sample, const RigidTwist& twist,
                     std::uint64_t steps);
  /// Stops the mesh where it is (no target): for a body whose client has left.
  void hold(MeshBody& mesh);
  /// Adds the last step's force and torque times dt to the impulses. Call after every step.
  void afterStep(const MeshBody& mesh, double timeStep);
  /// Ends the interval: sets the pose exactly to the target (if an interval was begun) and
  /// returns the wrench over the steps since beginInterval (or since the last endInterval).
  IntervalWrench endInterval(MeshBody& mesh, double timeStep);

  [[nodiscard]] std::size_t meshIndex() const { return mesh_; }
  [[nodiscard]] MotionMode mode() const { return mode_; }
  [[nodiscard]] const RigidPose& target() const { return target_; }
  /// Distance between the integrated and the target position at the last snap [m].
  [[nodiscard]] double lastSnapDistance() const { return snap_distance_; }
  /// Angle between the integrated and the target orientation at the last snap [rad].
  [[nodiscard]] double lastSnapAngle() const { return snap_angle_; }

 private:
  std::size_t mesh_;
  MotionMode mode_;
  bool has_target_ = false;
  RigidPose target_;
  Vec3 impulse_ = Vec3::Zero();          ///< [N s]
  Vec3 angular_impulse_ = Vec3::Zero();  ///< [N m s]
  std::uint64_t steps_ = 0;              ///< steps accumulated [-]
  double snap_distance_ = 0.0;
  double snap_angle_ = 0.0;
};

}  // namespace demlink::core
