#pragma once
/// The excavator as a Modelica-style system model: a fixed-step ODE of the machine whose
/// only coupling to the DEM is the wrench on the bucket, read once per sample.
///
/// Why this structure: the coupling paper (section 6) drives the bucket from a system model
/// of the machine, and what makes the co-simulation meaningful is the feedback: the
/// particles' resistance loads the hydraulics and the machine slows. The model is kept
/// quasi-static (the links have weight but no inertia; the hydraulics are stiff next to the
/// 1 ms sample), so its states are only the four joint angles and the four valve openings,
/// integrated by semi-implicit Euler: valves first (first-order lag, solved exactly over
/// the step), then the actuator speeds from the new openings and the current loads, then
/// the angles.
///
/// Kinematics: the upper structure swings about the vertical axis at (kExcavatorX,
/// kExcavatorY); boom, stick and bucket form a planar chain in the vertical swing plane
/// spanned by the heading d = (cos psi, sin psi, 0) and z. theta1 is the boom's angle
/// above the horizontal, theta2 the stick's angle relative to the boom, theta3 the
/// bucket's relative to the stick; positive joint rotation turns d towards z, i.e. about
/// the axis a = d x z. The bucket frame (the mesh's frame, origin at the bucket pivot):
/// x along the pivot -> teeth line at absolute angle phi3 = theta1 + theta2 + theta3,
/// y = z x d (lateral), z the in-plane normal; rotation = Rz(psi) Ry(-phi3).
///
/// Hydraulics per joint (valve-controlled cylinder, swing: a motor): a valve opening u in
/// [-1, 1] follows its command with time constant tau; the flow through the valve is
/// u Q_max sqrt((p_max - p_load) / p_max) (orifice with the relief pressure p_max as
/// supply), so the speed is (Q/A) and falls to zero when the load pressure p_load =
/// F_required / A against the motion reaches p_max (the force limit p_max A). A load that
/// helps the motion does not speed it up beyond Q_max / A (a load-holding valve meters
/// the return flow). With the valve closed the actuator holds its position.
///
/// Cylinders act through a triangle linkage: l = sqrt(a^2 + b^2 - 2 a b cos gamma) with
/// gamma = ratio theta + beta (ratio != 1 stands in for the bucket's four-bar linkage),
/// so dl/dtheta = ratio a b sin(gamma) / l and the required force F = tau / (dl/dtheta)
/// (virtual work), tau being the torque the actuator must supply about its joint to hold
/// the links' weight and the DEM wrench.
#include <array>
#include <string>

#include <Eigen/Core>
#include <Eigen/Geometry>

namespace demlink::examples::excavator {

using Vec3 = Eigen::Vector3d;

/// One hydraulic actuator and its linkage.
struct ActuatorSpec {
  std::string name;
  double area = 0.0;          ///< piston area [m^2] (motor: displacement [m^3/rad])
  double p_max = 0.0;         ///< supply / relief pressure [Pa]
  double q_max = 0.0;         ///< valve flow at full opening [m^3/s]
  double valve_tau = 0.08;    ///< valve time constant [s]
  bool rotary = false;        ///< a motor: "length" = joint angle, dl/dtheta = 1
  double a = 0.0;             ///< linkage side on the proximal link [m]
  double b = 0.0;             ///< linkage side on the distal link [m]
  double ratio = 1.0;         ///< gamma = ratio theta + beta [-]
  double beta = 0.0;          ///< [rad]
  double theta_min = 0.0;     ///< joint limits [rad]
  double theta_max = 0.0;
};

/// Geometry and masses of the machine.
struct MachineSpec {
  double boom_pivot_r = 0.6;   ///< boom pivot ahead of the swing axis [m]
  double boom_pivot_z = 1.7;   ///< boom pivot above the ground [m]
  double boom_length = 3.4;    ///< boom pivot -> stick pivot [m]
  double stick_length = 2.0;   ///< stick pivot -> bucket pivot [m]
  double boom_mass = 1100.0;   ///< [kg], centre of mass mid-length
  double stick_mass = 550.0;   ///< [kg], centre of mass mid-length
  double bucket_mass = 450.0;  ///< [kg]
  Vec3 bucket_com{0.45, 0.0, 0.3};  ///< bucket frame [m]
  double gravity = 9.81;       ///< [m/s^2]
  std::array<ActuatorSpec, 4> actuators;  ///< swing, boom, stick, bucket
};

/// The default machine (about a 12 t class excavator with a 0.45 m^3 bucket).
[[nodiscard]] MachineSpec defaultMachine();

/// Joint indices.
enum Joint : int { kSwing = 0, kBoom = 1, kStick = 2, kBucket = 3 };

/// Task-space pose of the bucket: heading, pivot distance from the swing axis and height
/// above the ground, absolute bucket angle.
struct BucketTarget {
  double psi = 0.0;  ///< [rad]
  double r = 0.0;    ///< [m]
  double z = 0.0;    ///< [m]
  double phi = 0.0;  ///< [rad]
};

/// What one step computed, for logs and CSV.
struct ActuatorState {
  double valve = 0.0;         ///< opening [-]
  double length = 0.0;        ///< cylinder length [m] (motor: angle [rad])
  double speed = 0.0;         ///< [m/s] (motor: [rad/s])
  double free_speed = 0.0;    ///< speed at this opening without load: u Q_max / A
  double force = 0.0;         ///< required force [N] (motor: torque [N m]), + extends
  double dem_force = 0.0;     ///< the DEM wrench's share of it
  double load_ratio = 0.0;    ///< p_load / p_max against the motion [-]
};

class ExcavatorModel {
 public:
  ExcavatorModel(MachineSpec spec, Vec3 swingAxis);

  /// Puts the machine at joint angles solving `target` (no motion).
  void setPose(const BucketTarget& target);
  /// Joint angles solving `target` (elbow up: stick hanging from the boom) [rad];
  /// out-of-reach targets are clamped to the reach; angles clamped to the joint limits.
  [[nodiscard]] std::array<double, 4> inverseKinematics(const BucketTarget& target) const;

  /// One step of dt with valve commands in [-1, 1] and the DEM wrench on the bucket
  /// (world frame, torque about the bucket pivot).
  void step(double dt, const std::array<double, 4>& commands, const Vec3& demForce, const Vec3& demTorque);

  [[nodiscard]] const std::array<double, 4>& angles() const { return theta_; }
  [[nodiscard]] const std::array<ActuatorState, 4>& actuators() const { return act_; }
  [[nodiscard]] const MachineSpec& spec() const { return spec_; }

  // Bucket pose and twist at the current state (world frame).
  [[nodiscard]] Vec3 bucketPivot() const;
  [[nodiscard]] Eigen::Quaterniond bucketOrientation() const;
  [[nodiscard]] Vec3 bucketVelocity() const;         ///< of the pivot [m/s]
  [[nodiscard]] Vec3 bucketAngularVelocity() const;  ///< [rad/s]
  /// A point given in the bucket frame, in the world [m].
  [[nodiscard]] Vec3 bucketPointToWorld(const Vec3& local) const;
  /// Heading direction d and the joint axis a = d x z.
  [[nodiscard]] Vec3 heading() const;
  [[nodiscard]] Vec3 jointAxis() const;

  /// Joint torques [N m] the external loads exert (about each joint, in its positive
  /// direction) and the DEM share of them; exposed for tests.
  void loadTorques(const Vec3& demForce, const Vec3& demTorque, std::array<double, 4>& total,
                   std::array<double, 4>& dem) const;
  /// dl/dtheta of actuator i at angle theta [m/rad] (motor: 1).
  [[nodiscard]] double leverArm(int i, double theta) const;
  /// Actuator length at angle theta [m] (motor: the angle).
  [[nodiscard]] double length(int i, double theta) const;

 private:
  [[nodiscard]] Vec3 boomPivot() const;
  [[nodiscard]] Vec3 stickPivot() const;

  MachineSpec spec_;
  Vec3 axis_;                          ///< swing axis foot point at ground level [m]
  std::array<double, 4> theta_{};      ///< psi, theta1, theta2, theta3 [rad]
  std::array<double, 4> rate_{};       ///< their rates over the last step [rad/s]
  std::array<ActuatorState, 4> act_{};
};

}  // namespace demlink::examples::excavator
