/// Configuration and running state are apart: the settings a world was built
/// with stay what the user chose, while the frame's angular velocity, gravity,
/// the skin in force and the counters evolve in World::state().
#include <gtest/gtest.h>

#include "test_scenes.hpp"

namespace demlink::core {
namespace {

void expectSameSettings(const SimulationSettings& a, const SimulationSettings& b) {
  EXPECT_EQ(a.time_step, b.time_step);
  EXPECT_EQ(a.gravity, b.gravity);
  EXPECT_EQ(a.neighbour_skin, b.neighbour_skin);
  EXPECT_EQ(a.frame.linear_acceleration, b.frame.linear_acceleration);
  EXPECT_EQ(a.frame.angular_velocity, b.frame.angular_velocity);
  EXPECT_EQ(a.frame.angular_acceleration, b.frame.angular_acceleration);
  EXPECT_EQ(a.frame.origin, b.frame.origin);
  ASSERT_EQ(a.bounds.has_value(), b.bounds.has_value());
  if (a.bounds) {
    EXPECT_EQ(a.bounds->lower, b.bounds->lower);
    EXPECT_EQ(a.bounds->upper, b.bounds->upper);
  }
}

TEST(WorldState, SettingsStayWhatTheUserChoseWhileTheFrameTurnsFaster) {
  SimulationSettings chosen = test::fineSettings(1.0e-4, 1.0);
  chosen.allow_unsafe_time_step = true;  // one free sphere: no contact to resolve
  chosen.gravity = Vec3(0.0, 0.0, -9.81);
  chosen.frame.angular_velocity = Vec3(0.0, 0.0, 0.5);      // Omega0 [rad/s]
  chosen.frame.angular_acceleration = Vec3(0.0, 0.0, 2.0);  // alpha [rad/s^2]
  DomainBounds bounds{Vec3::Constant(-10.0), Vec3::Constant(10.0)};
  bounds.growing = true;
  bounds.limit_lower = Vec3::Constant(-100.0);
  bounds.limit_upper = Vec3::Constant(100.0);
  chosen.bounds = bounds;
  World world(chosen);
  world.addMaterial(test::testMaterial(0.5));
  ParticleSpec s;
  s.radius = 0.01;
  s.position = Vec3(1.0, 0.0, 0.0);
  world.addParticle(s);

  const int steps = 1000;
  for (int n = 0; n < steps; ++n) world.step();
  expectSameSettings(world.settings(), chosen);

  const double t = world.time();  // [s]
  EXPECT_DOUBLE_EQ(t, steps * chosen.time_step);
  const Vec3 expected = chosen.frame.angular_velocity + chosen.frame.angular_acceleration * t;
  EXPECT_NEAR((world.state().frame.angular_velocity - expected).norm(), 0.0, 1e-12);
  EXPECT_EQ(world.frameMotion().angular_velocity, world.state().frame.angular_velocity);
  EXPECT_GT(world.state().frame.angular_velocity.z(), 0.69);  // 0.5 + 2 * 0.1 = 0.7 rad/s
  // The skin was defaulted (half the radius) in the state, not in the settings.
  EXPECT_EQ(world.neighbourSkin(), 0.005);
  // Growing bounds grew in the state only.
  ASSERT_TRUE(world.currentBounds());
  EXPECT_EQ(world.currentBounds()->lower, Vec3::Constant(-10.0));
  EXPECT_EQ(world.state().step_count, static_cast<std::uint64_t>(steps));
}

TEST(WorldState, CoSimulationChangesAreStateChanges) {
  SimulationSettings chosen = test::fineSettings(1.0e-5, 1.0);
  World world(chosen);
  world.addMaterial(test::testMaterial(0.5));
  world.initialize();
  const FrameMotion turning{Vec3(0.1, 0.0, 0.0), Vec3(0.0, 0.0, 1.0), Vec3::Zero()};
  world.setFrameMotion(turning);
  world.setGravity(Vec3(0.0, -9.81, 0.0));
  world.step();
  expectSameSettings(world.settings(), chosen);
  EXPECT_EQ(world.gravity(), Vec3(0.0, -9.81, 0.0));
  EXPECT_EQ(world.frameMotion().linear_acceleration, turning.linear_acceleration);
  EXPECT_EQ(world.frameMotion().angular_velocity, turning.angular_velocity);
  EXPECT_TRUE(world.state().frame_moving);
}

}  // namespace
}  // namespace demlink::core
