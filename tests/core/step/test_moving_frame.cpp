/// The moving frame (frame_motion.hpp) and growing domain
/// bounds: checked against analytic trajectories seen from a rotating frame, the
/// stick/slip threshold of a block on the floor of an accelerating frame, the
/// equivalence of a frame acceleration with a change of gravity, and the growth
/// and limit of the bounds box.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "demlink/core/base/input_error.hpp"
#include "test_scenes.hpp"

namespace demlink::core {
namespace {

using test::testMaterial;

/// Rotation about +z by angle [rad].
Vec3 rotateZ(const Vec3& v, double angle) {
  const double c = std::cos(angle);
  const double s = std::sin(angle);
  return {c * v.x() - s * v.y(), s * v.x() + c * v.y(), v.z()};
}

struct FreeFlightError {
  double position = 0.0;  ///< [m]
  double spin = 0.0;      ///< [rad/s]
};

/// A free sphere (no gravity, no contacts) seen from a frame turning about z with
/// Omega(t) = w0 + alpha t, over T = 1 s with time step dt. Inertially it flies
/// straight and keeps its spin: x_I = x0 + (v0 + Omega0 x x0) t, omega_abs = omega0 + Omega0;
/// in the frame x = R(-theta) x_I with theta = w0 t + alpha t^2 / 2, and the
/// relative spin is R(-theta) omega_abs - Omega(t).
FreeFlightError freeFlightInTurningFrame(double dt, double w0, double alpha) {
  SimulationSettings settings = test::fineSettings(dt, 1.0);
  settings.allow_unsafe_time_step = true;  // no contacts: the contact limit does not apply
  settings.frame.angular_velocity = Vec3(0.0, 0.0, w0);
  settings.frame.angular_acceleration = Vec3(0.0, 0.0, alpha);
  World world(settings);
  world.addMaterial(testMaterial(0.5));
  ParticleSpec s;
  s.radius = 0.005;
  s.position = Vec3(0.3, -0.1, 0.05);
  s.velocity = Vec3(-0.2, 0.4, 0.1);
  s.angular_velocity = Vec3(3.0, -1.0, 2.0);
  world.addParticle(s);
  constexpr double kEnd = 1.0;  // [s]
  const auto steps = static_cast<int>(std::lround(kEnd / dt));
  for (int n = 0; n < steps; ++n) world.step();
  const Vec3 omega0(0.0, 0.0, w0);
  const Vec3 inertialVelocity = s.velocity + omega0.cross(s.position);
  const double t = world.time();
  const double theta = w0 * t + 0.5 * alpha * t * t;
  const Vec3 expected = rotateZ(s.position + inertialVelocity * t, -theta);
  const Vec3 expectedSpin = rotateZ(s.angular_velocity + omega0, -theta) - Vec3(0.0, 0.0, w0 + alpha * t);
  return {(world.particles().position[0] - expected).norm(),
          (world.particles().angular_velocity[0] - expectedSpin).norm()};
}

TEST(MovingFrame, FreeParticleInUniformlyRotatingFrameFollowsTheRotatedStraightLine) {
  // Second order: halving dt divides the error by 4 (measured: 1.6e-4, 4.0e-5, 1.0e-5 m).
  const FreeFlightError coarse = freeFlightInTurningFrame(1.0e-2, 2.0, 0.0);
  const FreeFlightError mid = freeFlightInTurningFrame(5.0e-3, 2.0, 0.0);
  const FreeFlightError fine = freeFlightInTurningFrame(2.5e-3, 2.0, 0.0);
  EXPECT_LT(fine.position, 1.0e-5);  // over a path of ~0.5 m and two turns of the frame
  EXPECT_NEAR(coarse.position / mid.position, 4.0, 0.2);
  EXPECT_NEAR(mid.position / fine.position, 4.0, 0.2);
  // The spin transport is an exact rotation with a constant Omega.
  EXPECT_LT(coarse.spin, 1.0e-12);
}

TEST(MovingFrame, FreeParticleInAngularlyAcceleratingFrameConvergesAtSecondOrder) {
  const FreeFlightError coarse = freeFlightInTurningFrame(1.0e-2, 1.0, 3.0);
  const FreeFlightError mid = freeFlightInTurningFrame(5.0e-3, 1.0, 3.0);
  const FreeFlightError fine = freeFlightInTurningFrame(2.5e-3, 1.0, 3.0);
  EXPECT_LT(fine.position, 1.0e-4);
  EXPECT_NEAR(coarse.position / mid.position, 4.0, 0.3);
  EXPECT_NEAR(mid.position / fine.position, 4.0, 0.3);
  // Omega and alpha share an axis: the spin transport stays exact to rounding.
  EXPECT_LT(coarse.spin, 1.0e-12);
}

struct SlidingRun {
  double displacement = 0.0;  ///< relative to the floor, along x, after the hold [m]
  double acceleration = 0.0;  ///< relative, along x, over the last half of the hold [m/s^2]
};

/// A sphere that cannot turn (a block: inverse inertia 0, so the friction alone
/// must hold it; a free sphere would roll) rests on the floor of a frame under
/// gravity 9.81 m/s^2. The frame's x acceleration ramps from 0 to `ratio` mu g
/// over 0.05 s (quasi-static, so the tangential spring does not overshoot), then
/// stays for 0.1 s.
SlidingRun blockInAcceleratingFrame(double ratio) {
  constexpr double kMu = 0.5;
  constexpr double kG = 9.81;  // [m/s^2]
  constexpr double kDt = 1.0e-5;
  SimulationSettings settings = test::fineSettings(kDt, 0.5);
  settings.gravity = Vec3(0.0, 0.0, -kG);
  World world(settings);
  const auto material = world.addMaterial(testMaterial(0.3, kMu));
  test::addFloorAndSphere(world, material, 0.005, Vec3::Zero(), 0.0);
  world.particles().inv_inertia[0] = 0.0;
  for (int n = 0; n < 5000; ++n) world.step();  // settle on the floor
  const double x0 = world.particles().position[0].x();
  for (int n = 1; n <= 5000; ++n) {
    world.setFrameMotion({Vec3(ratio * kMu * kG * n / 5000.0, 0.0, 0.0), Vec3::Zero(), Vec3::Zero()});
    world.step();
  }
  for (int n = 0; n < 5000; ++n) world.step();
  const double v1 = world.particles().velocity[0].x();
  for (int n = 0; n < 5000; ++n) world.step();
  const double v2 = world.particles().velocity[0].x();
  return {world.particles().position[0].x() - x0, (v2 - v1) / (5000 * kDt)};
}

TEST(MovingFrame, BlockOnFloorSticksBelowMuGAndSlidesAbove) {
  constexpr double kMuG = 0.5 * 9.81;
  const SlidingRun stick = blockInAcceleratingFrame(0.98);
  const SlidingRun slip = blockInAcceleratingFrame(1.02);
  // Sticking: only the elastic tangential spring gives (~2e-6 m), no drift.
  EXPECT_LT(std::abs(stick.displacement), 1.0e-5);
  EXPECT_LT(std::abs(stick.acceleration), 1.0e-3 * kMuG);
  // Slipping: it slides backwards, relative acceleration -(a - mu g) = -0.02 mu g.
  EXPECT_LT(slip.displacement, -1.0e-4);
  EXPECT_NEAR(slip.acceleration, -0.02 * kMuG, 1.0e-3 * kMuG);
  const SlidingRun fast = blockInAcceleratingFrame(2.0);
  EXPECT_NEAR(fast.acceleration, -kMuG, 1.0e-3 * kMuG);
}

/// A sphere thrown with spin onto a rough floor; gravity and the frame's linear
/// acceleration as given.
World bouncingSphere(const Vec3& gravity, const Vec3& roomAcceleration) {
  SimulationSettings settings = test::fineSettings(2.0e-6, 2.0);
  settings.gravity = gravity;
  settings.frame.linear_acceleration = roomAcceleration;
  World world(settings);
  const auto material = world.addMaterial(testMaterial(0.6, 0.4, 0.05));
  ParticleSpec s;
  s.radius = 0.004;
  s.position = Vec3(0.0, 0.0, 0.01);
  s.velocity = Vec3(0.3, -0.2, -0.5);
  s.angular_velocity = Vec3(10.0, 5.0, -20.0);
  world.addPlane({"floor", Vec3::Zero(), Vec3::UnitZ(), material});
  world.addParticle(s);
  return world;
}

TEST(MovingFrame, ConstantFrameAccelerationEqualsChangedGravity) {
  const Vec3 gravity(0.0, 0.0, -9.81);
  const Vec3 roomAcceleration(1.5, -0.7, 2.0);
  World moving = bouncingSphere(gravity, roomAcceleration);
  World shifted = bouncingSphere(gravity - roomAcceleration, Vec3::Zero());
  double maxDifference = 0.0;
  int contactSteps = 0;
  for (int n = 0; n < 40000; ++n) {  // 0.08 s: several bounces, sliding and rolling
    moving.step();
    shifted.step();
    const ParticleArrays& a = moving.particles();
    const ParticleArrays& b = shifted.particles();
    maxDifference = std::max({maxDifference, (a.position[0] - b.position[0]).norm(),
                              (a.velocity[0] - b.velocity[0]).norm(),
                              (a.angular_velocity[0] - b.angular_velocity[0]).norm()});
    if (moving.planes()[0].force.norm() > 0.0) ++contactSteps;
  }
  // Bitwise: a purely translating frame runs the plain kick with gravity g - a_f.
  EXPECT_EQ(maxDifference, 0.0);
  EXPECT_GT(contactSteps, 500);  // the sphere bounced and rolled (measured 985 contact steps)
}

TEST(MovingFrame, InertialFrameRunsThePlainIntegrator) {
  SimulationSettings settings = test::fineSettings(1.0e-5, 1.0);
  World world(settings);
  world.addMaterial(testMaterial(0.5));
  const auto has = [&](const std::string& stage) {
    const auto stages = world.activeStages();
    return std::find(stages.begin(), stages.end(), stage) != stages.end();
  };
  EXPECT_FALSE(has("moving_frame"));
  world.setFrameMotion({Vec3::Zero(), Vec3(0.0, 0.0, 1.0), Vec3::Zero()});
  EXPECT_TRUE(has("moving_frame"));
  world.setFrameMotion({});
  EXPECT_FALSE(has("moving_frame"));
}

TEST(MovingFrame, BadFrameMotionNamesTheField) {
  World world(test::fineSettings(1.0e-5, 1.0));
  try {
    world.setFrameMotion({Vec3::Zero(), Vec3(0.0, std::nan(""), 0.0), Vec3::Zero()});
    FAIL() << "expected an InputError";
  } catch (const InputError& e) {
    EXPECT_EQ(e.field(), "frame.angular_velocity[1]");
  }
  SimulationSettings settings = test::fineSettings(1.0e-5, 1.0);
  settings.frame.angular_acceleration = Vec3(0.0, 0.0, INFINITY);
  try {
    World bad(settings);
    FAIL() << "expected an InputError";
  } catch (const InputError& e) {
    EXPECT_EQ(e.field(), "settings.frame.angular_acceleration[2]");
  }
}

TEST(GrowingBounds, BoxGrowsWithTheParticlesAndStopsAtTheLimit) {
  SimulationSettings settings = test::fineSettings(1.0e-3, 1.0);
  settings.allow_unsafe_time_step = true;
  settings.bounds = DomainBounds{Vec3::Constant(-0.1), Vec3::Constant(0.1), true, Vec3::Constant(-0.3),
                                 Vec3(0.3, 0.3, 0.3)};
  World world(settings);
  world.addMaterial(testMaterial(0.5));
  constexpr double kRadius = 0.01;
  ParticleSpec runner;
  runner.radius = kRadius;
  runner.velocity = Vec3(1.0, 0.0, 0.0);  // leaves the limit at x = 0.3 after 0.3 s
  ParticleSpec resting;
  resting.radius = kRadius;
  resting.position = Vec3(0.0, 0.05, -0.095);  // sticks out of the initial box below
  const std::uint64_t runnerId = world.addParticle(runner);
  world.addParticle(resting);
  double upper = 0.1;
  bool reachedLimit = false;
  for (int n = 0; n < 400; ++n) {
    const ParticleArrays& p = world.particles();
    const auto slot = static_cast<std::size_t>(std::find(p.id.begin(), p.id.end(), runnerId) - p.id.begin());
    const bool present = slot < p.size();
    const double x = present ? p.position[slot].x() : 1.0;  // the position the bounds pass sees
    world.step();
    const DomainBounds b = *world.currentBounds();
    if (present && x <= 0.3) upper = std::min(0.3, std::max(upper, x + kRadius));
    ASSERT_EQ(b.upper.x(), upper) << "step " << n;
    EXPECT_EQ(b.lower.z(), -0.095 - kRadius);  // grown around the resting sphere
    EXPECT_EQ(b.lower.x(), -0.1);              // never shrinks, never grows without cause
    reachedLimit = reachedLimit || b.upper.x() == 0.3;
  }
  EXPECT_TRUE(reachedLimit);
  EXPECT_EQ(world.particles().size(), 1u);  // the runner crossed the limit ...
  EXPECT_EQ(world.removedAtBounds().count, 1u);  // ... and was counted
  EXPECT_EQ(world.currentBounds()->upper.x(), 0.3);
}

TEST(GrowingBounds, LimitMustContainTheInitialBox) {
  SimulationSettings settings = test::fineSettings(1.0e-5, 1.0);
  settings.bounds = DomainBounds{Vec3::Constant(-0.1), Vec3::Constant(0.1), true, Vec3::Constant(-0.3),
                                 Vec3(0.3, 0.05, 0.3)};
  try {
    World world(settings);
    FAIL() << "expected an InputError";
  } catch (const InputError& e) {
    EXPECT_EQ(e.field(), "settings.bounds.limit_upper[1]");
  }
}

}  // namespace
}  // namespace demlink::core
