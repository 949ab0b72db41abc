/// Constant-twist interval motion with an exact landing (contract in coupled_motion.hpp).
///
/// The rotation from q_now to q_target is r = q_target q_now^-1 (world-frame, left
/// multiplication, as MeshBody::advance applies it). Its axis-angle form uses
/// angle = 2 atan2(|r.vec|, r.w) after flipping r to r.w >= 0, which is accurate for small
/// and large angles alike (acos of r.w loses half the digits near 0).
#include "demlink/core/walls/coupled_motion.hpp"

#include <cmath>

#include "demlink/core/walls/mesh_body.hpp"

namespace demlink::core {

RigidPose advancePose(const RigidPose& sample, const RigidTwist& twist, double seconds) {
  RigidPose out;
  out.position = sample.position + twist.linear * seconds;
  const double rate = twist.angular.norm();
  if (rate > 0.0) {
    const Quat turn(Eigen::AngleAxisd(rate * seconds, twist.angular / rate));
    out.orientation = (turn * sample.orientation).normalized();
  } else {
    out.orientation = sample.orientation.normalized();
  }
  return out;
}

RigidPose targetPose(MotionMode mode, const RigidPose& sample, const RigidTwist& twist, double seconds) {
  if (mode == MotionMode::Lagged) return {sample.position, sample.orientation.normalized()};
  return advancePose(sample, twist, seconds);
}

RigidTwist twistBetween(const RigidPose& from, const RigidPose& to, double seconds) {
  RigidTwist out;
  out.linear = (to.position - from.position) / seconds;
  Quat turn = to.orientation.normalized() * from.orientation.normalized().conjugate();
  if (turn.w() < 0.0) turn.coeffs() = -turn.coeffs();
  const double sinHalf = turn.vec().norm();
  if (sinHalf > 0.0) {
    const double angle = 2.0 * std::atan2(sinHalf, turn.w());
    out.angular = turn.vec() / sinHalf * (angle / seconds);
  }
  return out;
}

void CoupledMotion::beginInterval(MeshBody& mesh, double timeStep, const RigidPose& sample, const RigidTwist& twist,
                                  std::uint64_t steps) {
  const double seconds = static_cast<double>(steps) * timeStep;
  target_ = targetPose(mode_, sample, twist, seconds);
  has_target_ = true;
  const RigidTwist motion = twistBetween({mesh.position(), mesh.orientation()}, target_, seconds);
  mesh.setVelocity(motion.linear, motion.angular);
  impulse_.setZero();
  angular_impulse_.setZero();
  steps_ = 0;
}

void CoupledMotion::hold(MeshBody& mesh) {
  mesh.setVelocity(Vec3::Zero(), Vec3::Zero());
  has_target_ = false;
}

void CoupledMotion::afterStep(const MeshBody& mesh, double timeStep) {
  impulse_ += mesh.force() * timeStep;
  angular_impulse_ += mesh.torque() * timeStep;
  ++steps_;
}

IntervalWrench CoupledMotion::endInterval(MeshBody& mesh, double timeStep) {
  if (has_target_) {
    snap_distance_ = (mesh.position() - target_.position).norm();
    snap_angle_ = mesh.orientation().angularDistance(target_.orientation);
    mesh.setPose(target_.position, target_.orientation);
  }
  IntervalWrench out;
  if (steps_ > 0) {
    const double seconds = static_cast<double>(steps_) * timeStep;
    out.mean_force = impulse_ / seconds;
    out.mean_torque = angular_impulse_ / seconds;
  }
  out.force = mesh.force();
  out.torque = mesh.torque();
  impulse_.setZero();
  angular_impulse_.setZero();
  steps_ = 0;
  return out;
}

}  // namespace demlink::core
