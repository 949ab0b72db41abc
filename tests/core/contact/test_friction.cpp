// Tangential contact physics against rigid-body formulas.
//  - Oblique impact in gross sliding: the tangential impulse is mu times the
//    normal impulse, J_n = m (1 + e) v_n, so
//      v_t' = v_t - mu (1 + e) v_n,    omega' = (5/2) mu (1 + e) v_n / R.
//    (Sliding throughout needs v_t > 7/2 mu (1 + e) v_n.)
//  - Rolling resistance (EPSD): a sphere rolling without slip on a plane under
//    a constant torque mu_r R F_n decelerates at a = 5/7 mu_r g.
#include <gtest/gtest.h>

#include "test_scenes.hpp"

namespace demlink::core {
namespace {

constexpr double kRadius = 0.01;

TEST(ObliqueImpact, GrossSlidingMatchesImpulseFormulas) {
  const double mu = 0.1;
  const double e = 0.5;
  const double vn = 1.0;
  const double vt = 2.0;
  ASSERT_GT(vt, 3.5 * mu * (1.0 + e) * vn);
  // Stiff (E = 10 GPa) so the overlap, and with it the shortened lever arm
  // R - delta, stays below 0.5 % of R: the formulas are for rigid spheres.
  World world(test::fineSettings(2e-8, std::hypot(vn, vt)));
  Material material = test::testMaterial(e, mu);
  material.youngs_modulus = 1e10;
  const auto mat = world.addMaterial(material);
  test::addFloorAndSphere(world, mat, kRadius, Vec3(vt, 0.0, -vn), 1e-6);
  world.initialize();
  auto& p = world.particles();
  test::stepUntil(world, [&] { return p.position[0].z() > kRadius + 2e-6; }, 40'000'000);

  const double expectedVt = vt - mu * (1.0 + e) * vn;
  const double expectedSpin = 2.5 * mu * (1.0 + e) * vn / kRadius;
  EXPECT_NEAR(p.velocity[0].x() / expectedVt, 1.0, 0.01);
  // Friction at the bottom pushing -x: torque (-R z) x (-F x) = R F y, spin about +y.
  EXPECT_NEAR(p.angular_velocity[0].y() / expectedSpin, 1.0, 0.01);
  EXPECT_NEAR(p.velocity[0].z() / (e * vn), 1.0, 0.01);
}

TEST(RollingResistance, RollingSphereDeceleratesAtPredictedRate) {
  const double muR = 0.05;
  const double g = 9.81;
  SimulationSettings settings = test::fineSettings(2e-6, 1.0);
  settings.gravity = Vec3(0.0, 0.0, -g);
  World world(settings);
  Material m = test::testMaterial(0.3, 0.5, muR);
  const auto mat = world.addMaterial(m);
  world.addPlane({"floor", Vec3::Zero(), Vec3::UnitZ(), mat});
  // Start at the static Hertz overlap, rolling without slip: omega_y = v / R.
  const double mass = test::sphereMass(kRadius, m.density);
  const double eStar = 1.0 / (2.0 * (1.0 - m.poisson_ratio * m.poisson_ratio) / m.youngs_modulus);
  const double staticOverlap = std::pow(mass * g / (4.0 / 3.0 * eStar * std::sqrt(kRadius)), 2.0 / 3.0);
  const double v0 = 0.5;
  ParticleSpec s;
  s.radius = kRadius;
  s.position = Vec3(0.0, 0.0, kRadius - staticOverlap);
  s.velocity = Vec3(v0, 0.0, 0.0);
  s.angular_velocity = Vec3(0.0, v0 / (kRadius - staticOverlap), 0.0);
  world.addParticle(s);
  world.initialize();
  auto& p = world.particles();
  // Let the small normal oscillation from the start die out, then measure.
  for (int i = 0; i < 5000; ++i) world.step();
  const double t0 = world.time();
  const double v1 = p.velocity[0].x();
  for (int i = 0; i < 20000; ++i) world.step();
  const double deceleration = (v1 - p.velocity[0].x()) / (world.time() - t0);
  EXPECT_NEAR(deceleration / (5.0 / 7.0 * muR * g), 1.0, 0.01);
  // Still rolling, not sliding: the contact point (lever arm = centre height z)
  // is at rest to within 0.1 % of v.
  const double slip = p.velocity[0].x() - p.angular_velocity[0].y() * p.position[0].z();
  EXPECT_LT(std::abs(slip), 1e-3 * p.velocity[0].x());
}

TEST(RollingResistance, StopsWithoutReversing) {
  SimulationSettings settings = test::fineSettings(2e-6, 1.0);
  settings.gravity = Vec3(0.0, 0.0, -9.81);
  World world(settings);
  const auto mat = world.addMaterial(test::testMaterial(0.3, 0.5, 0.5));
  world.addPlane({"floor", Vec3::Zero(), Vec3::UnitZ(), mat});
  ParticleSpec s;
  s.radius = kRadius;
  s.position = Vec3(0.0, 0.0, kRadius);
  s.velocity = Vec3(0.02, 0.0, 0.0);
  s.angular_velocity = Vec3(0.0, 0.02 / kRadius, 0.0);
  world.addParticle(s);
  world.initialize();
  for (int i = 0; i < 100000; ++i) world.step();  // 0.2 s >> v0 / a = 0.006 s
  EXPECT_LT(std::abs(world.particles().angular_velocity[0].y()), 0.05);
  EXPECT_LT(std::abs(world.particles().velocity[0].x()), 1e-3);
}

}  // namespace
}  // namespace demlink::core
