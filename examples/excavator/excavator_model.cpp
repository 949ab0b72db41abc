/// The excavator's kinematics, load torques and hydraulics (see the header for the model).
/// Why quasi-static torques: the links' accelerations in a dig cycle are small next to
/// gravity and the digging forces, and leaving out the inertia keeps the model a handful
/// of explicit formulas a reader can check by hand.
#include "excavator_model.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <utility>

namespace demlink::examples::excavator {
namespace {

constexpr double kDeg = std::numbers::pi / 180.0;
const Vec3 kUp{0.0, 0.0, 1.0};

/// Unit vector at angle phi above the horizontal in the plane of heading d and z.
Vec3 inPlane(const Vec3& d, double phi) { return std::cos(phi) * d + std::sin(phi) * kUp; }

ActuatorSpec cylinder(std::string name, double bore, double pMax, double qMax, double a, double b,
                      double ratio, double betaDeg, double minDeg, double maxDeg) {
  ActuatorSpec s;
  s.name = std::move(name);
  s.area = std::numbers::pi * bore * bore / 4.0;
  s.p_max = pMax;
  s.q_max = qMax;
  s.a = a;
  s.b = b;
  s.ratio = ratio;
  s.beta = betaDeg * kDeg;
  s.theta_min = minDeg * kDeg;
  s.theta_max = maxDeg * kDeg;
  return s;
}

}  // namespace

MachineSpec defaultMachine() {
  MachineSpec m;
  constexpr double kSupply = 25.0e6;  // [Pa]
  ActuatorSpec swing;
  swing.name = "swing";
  swing.rotary = true;
  swing.p_max = kSupply;
  swing.area = 40.0e3 / kSupply;       // displacement for a 40 kN m torque limit [m^3/rad]
  swing.q_max = 0.8 * swing.area;      // 0.8 rad/s at full opening [m^3/s]
  swing.valve_tau = 0.1;
  swing.theta_min = -4.0 * std::numbers::pi;
  swing.theta_max = 4.0 * std::numbers::pi;
  m.actuators[kSwing] = swing;
  // Boom: extension raises the boom; gamma = theta1 + 60 deg.
  m.actuators[kBoom] = cylinder("boom", 0.13, kSupply, 3.3e-3, 1.0, 1.5, 1.0, 60.0, -20.0, 70.0);
  // Stick: extension crowds the stick in (theta2 decreases); gamma = -theta2 - 10 deg.
  m.actuators[kStick] = cylinder("stick", 0.11, kSupply, 2.5e-3, 1.8, 0.55, -1.0, -10.0, -150.0, -30.0);
  // Bucket: extension curls (theta3 decreases); four-bar linkage as gamma = -0.6 theta3 + 30 deg.
  m.actuators[kBucket] = cylinder("bucket", 0.095, kSupply, 3.0e-3, 1.4, 0.45, -0.6, 30.0, -175.0, 20.0);
  return m;
}

ExcavatorModel::ExcavatorModel(MachineSpec spec, Vec3 swingAxis) : spec_(std::move(spec)), axis_(std::move(swingAxis)) {
  for (int i = 0; i < 4; ++i) act_[static_cast<std::size_t>(i)].length = length(i, 0.0);
}

Vec3 ExcavatorModel::heading() const { return {std::cos(theta_[kSwing]), std::sin(theta_[kSwing]), 0.0}; }
Vec3 ExcavatorModel::jointAxis() const { return heading().cross(kUp); }

Vec3 ExcavatorModel::boomPivot() const {
  return axis_ + spec_.boom_pivot_r * heading() + spec_.boom_pivot_z * kUp;
}
Vec3 ExcavatorModel::stickPivot() const {
  return boomPivot() + spec_.boom_length * inPlane(heading(), theta_[kBoom]);
}
Vec3 ExcavatorModel::bucketPivot() const {
  return stickPivot() + spec_.stick_length * inPlane(heading(), theta_[kBoom] + theta_[kStick]);
}

Eigen::Quaterniond ExcavatorModel::bucketOrientation() const {
  const double phi = theta_[kBoom] + theta_[kStick] + theta_[kBucket];
  return Eigen::Quaterniond(Eigen::AngleAxisd(theta_[kSwing], Vec3::UnitZ())) *
         Eigen::Quaterniond(Eigen::AngleAxisd(-phi, Vec3::UnitY()));
}

Vec3 ExcavatorModel::bucketPointToWorld(const Vec3& local) const {
  return bucketPivot() + bucketOrientation() * local;
}

Vec3 ExcavatorModel::bucketVelocity() const {
  const Vec3 p = bucketPivot();
  const Vec3 a = jointAxis();
  return rate_[kSwing] * kUp.cross(p - axis_) + rate_[kBoom] * a.cross(p - boomPivot()) +
         rate_[kStick] * a.cross(p - stickPivot());
}

Vec3 ExcavatorModel::bucketAngularVelocity() const {
  return rate_[kSwing] * kUp + (rate_[kBoom] + rate_[kStick] + rate_[kBucket]) * jointAxis();
}

double ExcavatorModel::length(int i, double theta) const {
  const ActuatorSpec& s = spec_.actuators[static_cast<std::size_t>(i)];
  if (s.rotary) return theta;
  const double gamma = s.ratio * theta + s.beta;
  return std::sqrt(s.a * s.a + s.b * s.b - 2.0 * s.a * s.b * std::cos(gamma));
}

double ExcavatorModel::leverArm(int i, double theta) const {
  const ActuatorSpec& s = spec_.actuators[static_cast<std::size_t>(i)];
  if (s.rotary) return 1.0;
  const double gamma = s.ratio * theta + s.beta;
  const double arm = s.ratio * s.a * s.b * std::sin(gamma) / length(i, theta);
  // The joint limits keep gamma inside (0, pi); the floor only guards a bad spec.
  return std::abs(arm) < 1e-3 ? std::copysign(1e-3, arm) : arm;
}

std::array<double, 4> ExcavatorModel::inverseKinematics(const BucketTarget& t) const {
  const double l1 = spec_.boom_length;
  const double l2 = spec_.stick_length;
  const double dx = t.r - spec_.boom_pivot_r;
  const double dz = t.z - spec_.boom_pivot_z;
  const double reach = std::clamp(std::hypot(dx, dz), std::abs(l1 - l2) + 1e-6, l1 + l2 - 1e-6);
  const double c = (reach * reach - l1 * l1 - l2 * l2) / (2.0 * l1 * l2);
  const double theta2 = -std::acos(std::clamp(c, -1.0, 1.0));
  const double theta1 = std::atan2(dz, dx) - std::atan2(l2 * std::sin(theta2), l1 + l2 * std::cos(theta2));
  std::array<double, 4> q{t.psi, theta1, theta2, t.phi - theta1 - theta2};
  for (std::size_t i = 0; i < 4; ++i) {
    q[i] = std::clamp(q[i], spec_.actuators[i].theta_min, spec_.actuators[i].theta_max);
  }
  return q;
}

void ExcavatorModel::setPose(const BucketTarget& target) {
  theta_ = inverseKinematics(target);
  rate_ = {};
  for (int i = 0; i < 4; ++i) {
    auto& st = act_[static_cast<std::size_t>(i)];
    st = ActuatorState{};
    st.length = length(i, theta_[static_cast<std::size_t>(i)]);
  }
}

void ExcavatorModel::loadTorques(const Vec3& demForce, const Vec3& demTorque, std::array<double, 4>& total,
                                 std::array<double, 4>& dem) const {
  const Vec3 a = jointAxis();
  const Vec3 j1 = boomPivot();
  const Vec3 j2 = stickPivot();
  const Vec3 j3 = bucketPivot();
  const Vec3 g{0.0, 0.0, -spec_.gravity};
  const Vec3 boomCom = 0.5 * (j1 + j2);
  const Vec3 stickCom = 0.5 * (j2 + j3);
  const Vec3 bucketCom = bucketPointToWorld(spec_.bucket_com);
  auto moment = [&](const Vec3& joint, const Vec3& at, const Vec3& force) { return (at - joint).cross(force).dot(a); };
  // DEM wrench: force at the pivot j3, torque about j3.
  dem[kSwing] = ((j3 - axis_).cross(demForce) + demTorque).dot(kUp);
  dem[kBoom] = moment(j1, j3, demForce) + demTorque.dot(a);
  dem[kStick] = moment(j2, j3, demForce) + demTorque.dot(a);
  dem[kBucket] = demTorque.dot(a);
  total = dem;
  total[kBoom] += moment(j1, boomCom, spec_.boom_mass * g) + moment(j1, stickCom, spec_.stick_mass * g) +
                  moment(j1, bucketCom, spec_.bucket_mass * g);
  total[kStick] += moment(j2, stickCom, spec_.stick_mass * g) + moment(j2, bucketCom, spec_.bucket_mass * g);
  total[kBucket] += moment(j3, bucketCom, spec_.bucket_mass * g);
}

void ExcavatorModel::step(double dt, const std::array<double, 4>& commands, const Vec3& demForce,
                          const Vec3& demTorque) {
  std::array<double, 4> tau{};
  std::array<double, 4> tauDem{};
  loadTorques(demForce, demTorque, tau, tauDem);
  for (std::size_t i = 0; i < 4; ++i) {
    const int idx = static_cast<int>(i);
    const ActuatorSpec& s = spec_.actuators[i];
    ActuatorState& st = act_[i];
    // Valve: first-order lag, exact over the step for a constant command.
    const double cmd = std::clamp(commands[i], -1.0, 1.0);
    st.valve += (1.0 - std::exp(-dt / s.valve_tau)) * (cmd - st.valve);
    // Required actuator force: it must supply -tau about its joint; F = -tau / (dl/dtheta).
    const double arm = leverArm(idx, theta_[i]);
    st.force = -tau[i] / arm;
    st.dem_force = -tauDem[i] / arm;
    const double direction = st.valve > 0.0 ? 1.0 : (st.valve < 0.0 ? -1.0 : 0.0);
    st.load_ratio = direction * st.force / (s.area * s.p_max);
    st.free_speed = st.valve * s.q_max / s.area;
    const double orifice = std::sqrt(std::clamp(1.0 - st.load_ratio, 0.0, 1.0));
    const double speed = st.free_speed * orifice;
    // Angles from the new speed; a joint at its limit stops.
    const double before = theta_[i];
    theta_[i] = std::clamp(before + dt * speed / arm, s.theta_min, s.theta_max);
    rate_[i] = (theta_[i] - before) / dt;
    st.speed = rate_[i] * arm;
    st.length = length(idx, theta_[i]);
  }
}

}  // namespace demlink::examples::excavator
