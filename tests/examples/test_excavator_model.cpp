// The excavator system model without a server: kinematics against an independent
// computation, the wrench-to-cylinder mapping against virtual work, and the hydraulic
// limits (free speed without load, stall at the pressure limit).
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <numbers>

#include "bucket_mesh.hpp"
#include "excavator_model.hpp"
#include "excavator_operator.hpp"

namespace ex = demlink::examples::excavator;

namespace {

constexpr double kDeg = std::numbers::pi / 180.0;
const ex::Vec3 kAxis{0.0, -3.5, 0.0};

ex::ExcavatorModel modelAt(const ex::BucketTarget& t) {
  ex::ExcavatorModel m(ex::defaultMachine(), kAxis);
  m.setPose(t);
  return m;
}

}  // namespace

TEST(ExcavatorModel, InverseKinematicsPlacesThePivotAndTheBucketAngle) {
  const ex::BucketTarget t{100.0 * kDeg, 3.7, 0.4, -130.0 * kDeg};
  const auto m = modelAt(t);
  const ex::Vec3 p = m.bucketPivot();
  const ex::Vec3 d{std::cos(t.psi), std::sin(t.psi), 0.0};
  EXPECT_NEAR((p - kAxis).dot(d), t.r, 1e-9);
  EXPECT_NEAR(p.z(), t.z, 1e-9);
  ex::Vec3 horizontal = p - kAxis;
  horizontal.z() = 0.0;
  EXPECT_NEAR(horizontal.cross(d).norm(), 0.0, 1e-9);  // in the swing plane
  // The bucket frame's x axis points along phi in the swing plane; y is lateral (z x d).
  const ex::Vec3 x = m.bucketOrientation() * ex::Vec3::UnitX();
  EXPECT_NEAR(x.dot(d), std::cos(t.phi), 1e-9);
  EXPECT_NEAR(x.z(), std::sin(t.phi), 1e-9);
  const ex::Vec3 y = m.bucketOrientation() * ex::Vec3::UnitY();
  EXPECT_NEAR((y - ex::Vec3::UnitZ().cross(d)).norm(), 0.0, 1e-9);
}

TEST(ExcavatorModel, TwistMatchesTheFiniteDifferenceOfThePose) {
  auto m = modelAt({80.0 * kDeg, 3.9, 0.8, -100.0 * kDeg});
  const double dt = 1e-4;
  m.step(dt, {0.4, -0.6, 0.7, -0.5}, ex::Vec3::Zero(), ex::Vec3::Zero());  // open the valves a little
  for (int i = 0; i < 200; ++i) m.step(dt, {0.4, -0.6, 0.7, -0.5}, ex::Vec3::Zero(), ex::Vec3::Zero());
  const ex::Vec3 p0 = m.bucketPivot();
  const Eigen::Quaterniond q0 = m.bucketOrientation();
  m.step(dt, {0.4, -0.6, 0.7, -0.5}, ex::Vec3::Zero(), ex::Vec3::Zero());
  const ex::Vec3 v = m.bucketVelocity();
  const ex::Vec3 w = m.bucketAngularVelocity();
  ASSERT_GT(v.norm(), 0.05);
  // Over one step at the step's rates: error O(dt^2) relative to the motion.
  EXPECT_NEAR((m.bucketPivot() - p0 - v * dt).norm() / (v.norm() * dt), 0.0, 1e-2);
  const Eigen::AngleAxisd rot(m.bucketOrientation() * q0.inverse());
  EXPECT_NEAR((rot.axis() * rot.angle() - w * dt).norm() / (w.norm() * dt), 0.0, 1e-2);
}

TEST(ExcavatorModel, DemWrenchMapsToActuatorLoadsByVirtualWork) {
  // Power of the DEM wrench on the moving bucket = minus the power the actuators must
  // supply against it: sum_i F_dem,i v_i = -(F . v_pivot + M . omega).
  auto m = modelAt({95.0 * kDeg, 3.6, 0.6, -115.0 * kDeg});
  const ex::Vec3 force{1500.0, -8000.0, 5000.0};  // [N]
  const ex::Vec3 torque{-900.0, 2000.0, 700.0};   // [N m]
  for (int i = 0; i < 100; ++i) m.step(1e-3, {0.5, 0.5, -0.5, 0.5}, force, torque);
  // A last, tiny step: loads and rates then belong to (nearly) the same state.
  m.step(1e-9, {0.5, 0.5, -0.5, 0.5}, force, torque);
  double actuatorPower = 0.0;
  for (const auto& a : m.actuators()) actuatorPower += a.dem_force * a.speed;
  const double wrenchPower = force.dot(m.bucketVelocity()) + torque.dot(m.bucketAngularVelocity());
  ASSERT_GT(std::abs(wrenchPower), 100.0);
  EXPECT_NEAR(actuatorPower, -wrenchPower, 1e-9 * std::abs(wrenchPower) + 1e-6);
}

TEST(ExcavatorModel, CylinderRunsAtFreeSpeedUnloadedAndStallsAtThePressureLimit) {
  const ex::BucketTarget t{90.0 * kDeg, 3.6, 0.6, -115.0 * kDeg};
  auto m = modelAt(t);
  const auto& spec = m.spec().actuators[ex::kBucket];
  // Open the bucket valve fully with a DEM torque that cancels the bucket's weight about
  // its pivot at every step: no load, so the free speed Q / A.
  for (int i = 0; i < 500; ++i) {
    std::array<double, 4> total{};
    std::array<double, 4> dem{};
    m.loadTorques(ex::Vec3::Zero(), ex::Vec3::Zero(), total, dem);
    m.step(1e-3, {0.0, 0.0, 0.0, 1.0}, ex::Vec3::Zero(), -total[ex::kBucket] * m.jointAxis());
  }
  const auto& free = m.actuators()[ex::kBucket];
  EXPECT_NEAR(free.valve, 1.0, 0.01);  // 0.5 s = 6 valve time constants
  EXPECT_NEAR(free.load_ratio, 0.0, 1e-9);
  EXPECT_NEAR(free.speed, free.valve * spec.q_max / spec.area, 1e-9);
  // A DEM torque about the bucket pivot that needs 1.2 x the force limit against the motion.
  auto m2 = modelAt(t);
  for (int i = 0; i < 300; ++i) m2.step(1e-3, {0.0, 0.0, 0.0, 1.0}, ex::Vec3::Zero(), ex::Vec3::Zero());
  const double arm = m2.leverArm(ex::kBucket, m2.angles()[ex::kBucket]);
  // Required force F = -tau / arm; against extension means F > 0: tau = -1.2 Fmax arm.
  const double tau = -1.2 * spec.p_max * spec.area * arm;
  const ex::Vec3 torque = tau * m2.jointAxis();
  const double before = m2.angles()[ex::kBucket];
  m2.step(1e-3, {0.0, 0.0, 0.0, 1.0}, ex::Vec3::Zero(), torque);
  EXPECT_GT(m2.actuators()[ex::kBucket].load_ratio, 1.0);
  EXPECT_EQ(m2.actuators()[ex::kBucket].speed, 0.0);
  EXPECT_EQ(m2.angles()[ex::kBucket], before);
}

TEST(ExcavatorOperator, RunsTheCycleWithoutLoadAndEndsAtHome) {
  ex::ExcavatorOperator op({1});
  auto m = modelAt(op.start());
  double t = 0.0;
  bool dumped = false;
  while (!op.done() && t < 60.0) {
    const auto c = op.update(1e-3, m);
    m.step(1e-3, c, ex::Vec3::Zero(), ex::Vec3::Zero());
    t += 1e-3;
    if (op.phase() == ex::Phase::kDump) {
      // Over the truck bed (5.5 m towards +x from the swing axis), bucket above its rim.
      const ex::Vec3 p = m.bucketPivot();
      EXPECT_NEAR(p.y(), kAxis.y(), 0.4);
      EXPECT_GT(p.x(), 4.5);
      dumped = true;
    }
  }
  EXPECT_TRUE(op.done());
  EXPECT_TRUE(dumped);
  EXPECT_EQ(op.timeouts(), 0);
  EXPECT_LT(t, 25.0);
}

TEST(BucketMesh, FillBoxHoldsTheWholeShellInteriorAndNoMoreThanItsBoundsAndHeap) {
  const auto mesh = ex::makeBucketMesh();
  EXPECT_EQ(mesh.triangles.size(), 10u);
  EXPECT_NEAR(ex::bucketCapacity(), 0.4275 * ex::kBucketWidth, 1e-12);
  const Eigen::Vector3d lo = ex::kFillBoxCentre - 0.5 * ex::kFillBoxSize;
  const Eigen::Vector3d hi = ex::kFillBoxCentre + 0.5 * ex::kFillBoxSize;
  // Every shell vertex is inside the box (the interior is their convex hull, so all of it
  // is), and the box reaches no further than the shell's bounds along x and y.
  Eigen::Vector3d shellLo = mesh.vertices.front(), shellHi = mesh.vertices.front();
  for (const auto& v : mesh.vertices) {
    for (int i = 0; i < 3; ++i) {
      EXPECT_GE(v[i], lo[i] - 1e-12) << "vertex (" << v.transpose() << ") axis " << i;
      EXPECT_LE(v[i], hi[i] + 1e-12) << "vertex (" << v.transpose() << ") axis " << i;
    }
    shellLo = shellLo.cwiseMin(v);
    shellHi = shellHi.cwiseMax(v);
  }
  for (int i = 0; i < 2; ++i) {
    EXPECT_NEAR(lo[i], shellLo[i], 1e-12);
    EXPECT_NEAR(hi[i], shellHi[i], 1e-12);
  }
  // Beyond the mouth (z < 0 side) the box holds a heap of at most 0.15 m.
  EXPECT_NEAR(hi.z(), shellHi.z(), 1e-12);
  EXPECT_GE(lo.z(), shellLo.z() - 0.15 - 1e-12);
}
