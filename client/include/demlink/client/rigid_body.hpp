#pragma once
/// A rigid body whose motion the client prescribes (a bucket, a dump body): it sends pose
/// and twist at each sample and reads back the wrench the particles exert on it.
///
/// Why the input persists: the server needs a pose in every package, so the last one set
/// is sent again if the model did not move the body; before the first setPose() the
/// declared initial pose is sent, so a body that never moves needs no input call at all.
#include <string>

#include "demlink/client/component.hpp"

namespace demlink::client {

/// How the server moves the body between two packages (RigidBody.Motion in the schema).
enum class RigidBodyMotion : int {
  kPredicted = 1,  ///< towards the sent pose advanced by the sent twist (zero lag)
  kLagged = 2,     ///< onto the sent pose, one interval late
};

class RigidBody : public Component {
 public:
  explicit RigidBody(std::string name);
  RigidBody& setStlFile(const std::string& pathOnServer);
  RigidBody& setStlData(const std::string& stlBytes);  ///< an ASCII or binary STL's content
  RigidBody& setBox(const Vec3& size, bool openTop = false);  ///< box about its centre [m]
  RigidBody& setMaterial(const std::string& material);
  RigidBody& setReferencePoint(const Vec3& point);  ///< geometry frame [m]
  RigidBody& setInitialPose(const Vec3& position, const Quat& orientation = {});  ///< [m], [-]
  RigidBody& setInitialVelocity(const Vec3& linear, const Vec3& angular = {});   ///< [m/s], [rad/s]
  RigidBody& setMotion(RigidBodyMotion motion);
  RigidBody& setMotion(v1::RigidBody_Motion motion);
  [[nodiscard]] v1::RigidBody& message();

  // Inputs, sent with every package.
  /// World position of the reference point [m] and rotation geometry -> world [-].
  void setPose(const Vec3& position, const Quat& orientation);
  /// Velocity of the reference point [m/s] and angular velocity, world frame [rad/s].
  void setVelocity(const Vec3& linear, const Vec3& angular);

  // Outputs: wrench ON the body BY the particles, world frame, about the reference point.
  [[nodiscard]] Vec3 meanForce() const;   ///< impulse / interval [N]
  [[nodiscard]] Vec3 meanTorque() const;  ///< [N m]
  [[nodiscard]] Vec3 force() const;       ///< at the end of the interval [N]
  [[nodiscard]] Vec3 torque() const;      ///< [N m]
  [[nodiscard]] Vec3 position() const;    ///< server's pose at the end of the interval [m]
  [[nodiscard]] Quat orientation() const;

 protected:
  void writeInputs(v1::DataPackage& package) const override;

 private:
  bool pose_set_ = false;
  bool velocity_set_ = false;
  ProtoPtr<v1::RigidBodyInput> input_;
};

}  // namespace demlink::client
