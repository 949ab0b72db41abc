/// RigidBody: declaration setters, the persistent pose/twist input and the wrench outputs.
#include "demlink/client/rigid_body.hpp"

#include <utility>

#include "demlink/v1/protocol.pb.h"

namespace demlink::client {

RigidBody::RigidBody(std::string name) : Component(std::move(name)), input_(new v1::RigidBodyInput()) {
  declaration().mutable_rigid_body();
}

RigidBody& RigidBody::setStlFile(const std::string& pathOnServer) {
  message().set_stl_file(pathOnServer);
  return *this;
}
RigidBody& RigidBody::setStlData(const std::string& stlBytes) {
  message().set_stl_data(stlBytes);
  return *this;
}
RigidBody& RigidBody::setBox(const Vec3& size, bool openTop) {
  auto* box = message().mutable_box();
  *box->mutable_size() = toProto(size);
  box->set_open_top(openTop);
  return *this;
}
RigidBody& RigidBody::setMaterial(const std::string& material) {
  message().set_material(material);
  return *this;
}
RigidBody& RigidBody::setReferencePoint(const Vec3& point) {
  *message().mutable_reference_point() = toProto(point);
  return *this;
}
RigidBody& RigidBody::setInitialPose(const Vec3& position, const Quat& orientation) {
  *message().mutable_position() = toProto(position);
  *message().mutable_orientation() = toProto(orientation);
  return *this;
}
RigidBody& RigidBody::setInitialVelocity(const Vec3& linear, const Vec3& angular) {
  *message().mutable_linear_velocity() = toProto(linear);
  *message().mutable_angular_velocity() = toProto(angular);
  return *this;
}
RigidBody& RigidBody::setMotion(RigidBodyMotion motion) {
  return setMotion(motion == RigidBodyMotion::kLagged ? v1::RigidBody::LAGGED : v1::RigidBody::PREDICTED);
}
RigidBody& RigidBody::setMotion(v1::RigidBody_Motion motion) {
  message().set_motion(motion);
  return *this;
}

void RigidBody::setPose(const Vec3& position, const Quat& orientation) {
  *input_->mutable_position() = toProto(position);
  *input_->mutable_orientation() = toProto(orientation);
  pose_set_ = true;
}

void RigidBody::setVelocity(const Vec3& linear, const Vec3& angular) {
  *input_->mutable_linear_velocity() = toProto(linear);
  *input_->mutable_angular_velocity() = toProto(angular);
  velocity_set_ = true;
}

void RigidBody::writeInputs(v1::DataPackage& package) const {
  auto* in = package.mutable_rigid_body_input();
  const auto& declared = declaration().rigid_body();
  if (pose_set_) {
    *in->mutable_position() = input_->position();
    *in->mutable_orientation() = input_->orientation();
  } else {
    // The declared initial pose, with the schema's defaults for omitted fields.
    *in->mutable_position() = declared.has_position() ? declared.position() : declared.reference_point();
    *in->mutable_orientation() = toProto(fromProto(declared.orientation(), declared.has_orientation()));
  }
  if (velocity_set_) {
    *in->mutable_linear_velocity() = input_->linear_velocity();
    *in->mutable_angular_velocity() = input_->angular_velocity();
  } else {
    *in->mutable_linear_velocity() = declared.linear_velocity();
    *in->mutable_angular_velocity() = declared.angular_velocity();
  }
}

Vec3 RigidBody::meanForce() const { return fromProto(outputs().rigid_body().mean_force()); }
Vec3 RigidBody::meanTorque() const { return fromProto(outputs().rigid_body().mean_torque()); }
Vec3 RigidBody::force() const { return fromProto(outputs().rigid_body().force()); }
Vec3 RigidBody::torque() const { return fromProto(outputs().rigid_body().torque()); }
Vec3 RigidBody::position() const { return fromProto(outputs().rigid_body().position()); }
Quat RigidBody::orientation() const {
  return fromProto(outputs().rigid_body().orientation(), outputs().rigid_body().has_orientation());
}

v1::RigidBody& RigidBody::message() { return *declaration().mutable_rigid_body(); }

}  // namespace demlink::client
