// Motion coupling of a client's rigid body through the host: LAGGED lands on every sent
// pose, PREDICTED follows a smooth trajectory within O(a T^2) without drift, a body moved
// at constant velocity does not pump energy into a sphere resting on it, and the wrench
// of a resting sphere is its weight with torque r x F about the reference point.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "cosim_test_support.hpp"
#include "demlink/server/cosim/cosim_simulation.hpp"

namespace demlink::server::test {
namespace {

constexpr double kPi = std::numbers::pi;

/// A plate (top face at z = 0 when at its initial pose; reference point = box centre at
/// z = -0.005) declared by client 1, plus `extra` components; compiled on the last one.
/// The plate's declared max_speed covers the jumps these tests send (else the watchdog
/// stops a body moving 10 x faster than the validated speed).
void startPlate(CosimHarness& h, double dt, double interval, const std::string& motion,
                const std::vector<std::string>& extra) {
  h.hello(1, "driver");
  h.declare(1, boxJson(dt, 0.0, R"("coupling": {"expected_count": )" + std::to_string(3 + extra.size()) + "}"));
  h.declare(1, smallBedJson()[0]);
  for (const std::string& c : extra) h.declare(1, c);
  h.declare(1, R"({"name": "plate", "communication_interval": )" + std::to_string(interval) +
                   R"(, "rigid_body": {"material": "glass", "box": {"size": {"x": 0.05, "y": 0.05, "z": 0.01}},
                   "position": {"z": -0.005}, "max_speed": 100, "motion": ")" + motion + R"("}})");
  ASSERT_TRUE(h.compiled(1));
}

TEST(CosimMotion, LaggedLandsExactlyOnEverySentPose) {
  ScratchDir dir;
  CosimHarness h(dir.path());
  startPlate(h, 1e-4, 4e-4, "LAGGED", {});
  const std::uint32_t plate = h.idOf(1, "plate");
  core::Vec3 previous(0, 0, -0.005);
  core::Quat previousQ = core::Quat::Identity();
  for (std::uint64_t k = 0; k < 60; ++k) {
    const double t = static_cast<double>(k);
    const core::Vec3 p(0.01 * std::sin(0.3 * t), 0.004 * std::cos(0.7 * t), -0.005 + 0.002 * std::sin(t));
    const core::Quat q(Eigen::AngleAxisd(0.9 * std::sin(0.2 * t), core::Vec3(1, 2, 3).normalized()));
    // A twist that is deliberately inconsistent: LAGGED must ignore it.
    h.sampleBody(1, plate, 4 * k, bodyInput(p, q, {1, 2, 3}, {4, 5, 6}));
    const std::optional<v1::DataPackage> answer = h.lastData(1, plate);
    ASSERT_TRUE(answer);
    ASSERT_EQ(answer->step(), 4 * (k + 1));
    const v1::RigidBodyOutput& out = answer->rigid_body();
    EXPECT_EQ(toVec3(out.position()), p) << "interval " << k;  // bitwise: the pose is set, not integrated
    const core::Quat landed = toQuat(out.orientation());
    EXPECT_LT(landed.angularDistance(q), 1e-12);
    const core::CoupledMotion* coupling = h.host().simulation()->coupling(plate - 1);
    ASSERT_NE(coupling, nullptr);
    EXPECT_LT(coupling->lastSnapDistance(), 1e-12);  // the constant twist arrived by itself
    EXPECT_LT(coupling->lastSnapAngle(), 1e-12);
    previous = p;
    previousQ = q;
  }
  EXPECT_TRUE(h.errors(1).empty());
}

TEST(CosimMotion, PredictedFollowsASmoothTrajectoryWithoutDrift) {
  ScratchDir dir;
  CosimHarness h(dir.path());
  const double dt = 1e-4;
  const std::uint64_t n = 2;
  const double T = static_cast<double>(n) * dt;
  startPlate(h, dt, T, "PREDICTED", {});
  const std::uint32_t plate = h.idOf(1, "plate");
  const double A = 0.01;             // [m]
  const double B = 0.5;              // [rad]
  const double w = 2.0 * kPi * 5.0;  // [rad/s]
  const core::Vec3 axis = core::Vec3(0, 1, 1).normalized();
  const auto exact = [&](double t) {
    return std::pair{core::Vec3(A * std::sin(w * t), 0.0, -0.005),
                     core::Quat(Eigen::AngleAxisd(B * std::sin(w * t), axis))};
  };
  // Error of one prediction step: position A w^2 T^2 / 2, angle B w^2 T^2 / 2.
  const double positionBound = 0.5 * A * w * w * T * T;
  const double angleBound = 0.5 * B * w * w * T * T;
  double firstMax = 0.0;
  double lastMax = 0.0;
  double angleMax = 0.0;
  const std::uint64_t intervals = 1000;
  for (std::uint64_t k = 0; k < intervals; ++k) {
    const double t = static_cast<double>(k) * T;
    const auto [p, q] = exact(t);
    const core::Vec3 v(A * w * std::cos(w * t), 0.0, 0.0);
    const core::Vec3 omega = axis * (B * w * std::cos(w * t));
    h.sampleBody(1, plate, n * k, bodyInput(p, q, v, omega));
    const v1::RigidBodyOutput out = h.lastData(1, plate)->rigid_body();
    const auto [pNext, qNext] = exact(t + T);
    const double error = (toVec3(out.position()) - pNext).norm();
    const core::Quat landed = toQuat(out.orientation());
    angleMax = std::max(angleMax, landed.angularDistance(qNext));
    if (k < 100) firstMax = std::max(firstMax, error);
    if (k >= intervals - 100) lastMax = std::max(lastMax, error);
  }
  EXPECT_LT(firstMax, 1.01 * positionBound);
  EXPECT_LT(lastMax, 1.01 * positionBound);  // no accumulation over 1000 intervals
  EXPECT_GT(lastMax, 0.1 * positionBound);   // the bound is tight, not vacuous
  EXPECT_LT(angleMax, 1.01 * angleBound + 1e-12);
  EXPECT_TRUE(h.errors(1).empty());
}

/// One sphere of radius r resting at (x0, y0) on the plate's top face (z = 0).
std::string sphereJson(double x0, double y0) {
  return R"({"name": "ball", "single_particle": {"material": "glass", "diameter": 0.004, "position": {"x": )" +
         std::to_string(x0) + R"(, "y": )" + std::to_string(y0) + R"(, "z": 0.002}}})";
}

TEST(CosimMotion, WrenchOfARestingSphereIsItsWeightAboutTheReferencePoint) {
  ScratchDir dir;
  CosimHarness h(dir.path());
  const double x0 = 0.01;
  const double y0 = -0.006;
  startPlate(h, 1e-5, 1e-3, "PREDICTED", {sphereJson(x0, y0)});
  const std::uint32_t plate = h.idOf(1, "plate");
  const core::Quat still = core::Quat::Identity();
  for (std::uint64_t k = 0; k < 60; ++k) h.sampleBody(1, plate, 100 * k, bodyInput({0, 0, -0.005}, still));
  ASSERT_TRUE(h.errors(1).empty());
  const core::World& world = *h.host().world();
  ASSERT_EQ(world.particles().size(), 1u);
  const double weight = world.particles().mass[0] * 9.81;
  const v1::RigidBodyOutput out = h.lastData(1, plate)->rigid_body();
  const core::Vec3 mean = toVec3(out.mean_force());
  EXPECT_NEAR(mean.z(), -weight, 0.01 * weight);  // ON the plate BY the sphere: downwards
  EXPECT_NEAR(mean.x(), 0.0, 0.01 * weight);
  EXPECT_NEAR(mean.y(), 0.0, 0.01 * weight);
  EXPECT_NEAR(toVec3(out.force()).z(), -weight, 0.01 * weight);
  // Torque about the reference point (0, 0, -0.005): r x F with r = (x0, y0, 0.005).
  const core::Vec3 expected = core::Vec3(x0, y0, 0.005).cross(core::Vec3(0, 0, -weight));
  const core::Vec3 torque = toVec3(out.mean_torque());
  EXPECT_NEAR(torque.x(), expected.x(), 0.01 * std::abs(expected.x()));
  EXPECT_NEAR(torque.y(), expected.y(), 0.01 * std::abs(expected.y()));
  EXPECT_NEAR(torque.z(), 0.0, 0.01 * expected.norm());
}

TEST(CosimMotion, ConstantVelocityPlateInjectsNoEnergy) {
  ScratchDir dir;
  CosimHarness h(dir.path());
  startPlate(h, 1e-5, 2e-4, "PREDICTED", {sphereJson(0.0, 0.0)});
  const std::uint32_t plate = h.idOf(1, "plate");
  const double v = 0.05;  // [m/s] along x
  const double T = 2e-4;
  // Settle first, then move at constant velocity for 0.1 s (500 intervals).
  std::uint64_t k = 0;
  for (; k < 100; ++k) h.sampleBody(1, plate, 20 * k, bodyInput({0, 0, -0.005}, core::Quat::Identity()));
  double early = 0.0;  // largest kinetic energy in intervals 100..199 [J]
  double late = 0.0;   // ... in intervals 400..499 [J]
  double mass = 0.0;
  for (std::uint64_t j = 0; j < 500; ++j, ++k) {
    const core::Vec3 p(v * static_cast<double>(j) * T, 0.0, -0.005);
    h.sampleBody(1, plate, 20 * k, bodyInput(p, core::Quat::Identity(), {v, 0, 0}));
    const core::World& world = *h.host().world();
    mass = world.particles().mass[0];
    if (j >= 100 && j < 200) early = std::max(early, world.kineticEnergy());
    if (j >= 400) late = std::max(late, world.kineticEnergy());
  }
  ASSERT_TRUE(h.errors(1).empty());
  // A sphere set rolling by a belt of speed v ends with centre speed 2v/7 and spin 5v/(7r):
  // kinetic energy m v^2 / 7 = (2/7) of (1/2) m v^2. The tangential spring makes it oscillate
  // about that state, but the energy must stay below (1/2) m v^2 and must not grow.
  const double carried = 0.5 * mass * v * v;
  EXPECT_GT(early, 2.0 / 7.0 * carried * 0.9);
  EXPECT_LT(early, carried);
  EXPECT_LT(late, carried);
  EXPECT_LT(late, 1.05 * early);
  EXPECT_NEAR(h.host().world()->particles().position[0].z(), 0.002, 1e-4);
}

}  // namespace
}  // namespace demlink::server::test
