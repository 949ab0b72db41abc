// Cohesion (simplified JKR, F_coh = k_c A): the contact area against the
// sphere-sphere intersection, the force at a given overlap against the closed
// form for pairs and walls, conservation of energy with a cohesive contact, a
// slow impact that cohesion captures, a cohesive block that stands where a dry
// one slumps, the stage report and bad cohesion values refused.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <random>

#include "demlink/core/contact/contact_stage.hpp"
#include "demlink/core/base/input_error.hpp"
#include "test_scenes.hpp"

namespace demlink::core {
namespace {

constexpr double kRadius = 0.002;  // [m]
constexpr int kBlockLayers = 8;

Material cohesiveMaterial(double kc, double restitution = 0.5, double friction = 0.5) {
  Material m = test::testMaterial(restitution, friction);
  m.name = kc > 0.0 ? "moist" : "dry";
  m.cohesion_energy_density = kc;
  return m;
}

/// Hertz elastic force (4/3) E* sqrt(R*) delta^1.5 of two like materials (or one on a like wall).
double hertzForce(const Material& m, double rStar, double overlap) {
  const double eStar = m.youngs_modulus / (2.0 * (1.0 - m.poisson_ratio * m.poisson_ratio));
  return 4.0 / 3.0 * eStar * std::sqrt(rStar) * std::pow(overlap, 1.5);
}

TEST(CohesionArea, PairAreaIsTheSphereIntersectionCircle) {
  // Circle of two spheres: its plane is x from the first centre, x = (d^2 + r1^2 - r2^2) / (2 d),
  // and a^2 = r1^2 - x^2 (direct form, fine at these overlaps).
  for (const double r2 : {0.002, 0.005}) {
    for (const double overlap : {1.0e-6, 1.0e-4, 5.0e-4}) {
      const double r1 = 0.003;
      const double d = r1 + r2 - overlap;
      const double x = (d * d + r1 * r1 - r2 * r2) / (2.0 * d);
      const double direct = std::numbers::pi * (r1 * r1 - x * x);
      EXPECT_NEAR(pairContactArea(r1, r2, d, overlap) / direct, 1.0, 1.0e-9) << r2 << " " << overlap;
    }
  }
  // The wall is the limit of an ever larger partner.
  const double overlap = 1.0e-4;
  const double big = 1.0e4;
  EXPECT_NEAR(pairContactArea(kRadius, big, kRadius + big - overlap, overlap) / wallContactArea(kRadius, overlap),
              1.0, 1.0e-6);
  EXPECT_DOUBLE_EQ(wallContactArea(kRadius, overlap), std::numbers::pi * overlap * (2.0 * kRadius - overlap));
}

TEST(CohesionForce, PairAtRestPullsWithKcTimesTheContactArea) {
  constexpr double kKc = 2.0e5;      // [J/m^3]
  constexpr double kOverlap = 2.0e-5;  // [m]
  World world(test::fineSettings(1.0e-6, 0.1));
  const Material m = cohesiveMaterial(kKc);
  world.addMaterial(m);
  ParticleSpec a;
  a.radius = kRadius;
  a.position = Vec3(-kRadius + 0.5 * kOverlap, 0.0, 0.0);
  ParticleSpec b = a;
  b.position = -a.position;
  world.addParticle(a);
  world.addParticle(b);
  world.initialize();
  const double d = 2.0 * kRadius - kOverlap;
  const double area = std::numbers::pi * kOverlap * (d + 2.0 * kRadius) * d * d / (4.0 * d * d);
  const double expected = hertzForce(m, 0.5 * kRadius, kOverlap) - kKc * area;
  // Force on the particle at +x: elastic push along +x minus the cohesive pull.
  EXPECT_NEAR(world.particles().force[1].x() / expected, 1.0, 1.0e-12);
  EXPECT_LT(expected, hertzForce(m, 0.5 * kRadius, kOverlap));
  EXPECT_NEAR(world.particles().force[0].x(), -world.particles().force[1].x(), 1.0e-15);
}

TEST(CohesionForce, SphereOnAWallPullsWithKcTimesTheCapArea) {
  constexpr double kKc = 3.0e5;       // [J/m^3]
  constexpr double kOverlap = 1.0e-5;  // [m]
  World world(test::fineSettings(1.0e-6, 0.1));
  const Material m = cohesiveMaterial(kKc);
  const auto material = world.addMaterial(m);
  test::addFloorAndSphere(world, material, kRadius, Vec3::Zero(), -kOverlap);
  world.initialize();
  const double expected =
      hertzForce(m, kRadius, kOverlap) - kKc * std::numbers::pi * kOverlap * (2.0 * kRadius - kOverlap);
  EXPECT_NEAR(world.particles().force[0].z() / expected, 1.0, 1.0e-12);
  EXPECT_NEAR(world.planes()[0].force.z(), -expected, 1.0e-12 * std::abs(expected));
}

TEST(CohesionForce, ASphereLeavesAWallWhenThePullExceedsTheLawsLargestTension) {
  // The tension a sphere-wall contact holds at overlap d is
  //   T(d) = k_c pi d (2R - d) - (4/3) E* sqrt(R) d^1.5,
  // largest at sqrt(d*) = pi k_c sqrt(R) / E* (with 2R - d ~ 2R), where
  //   T_max = (2/3) pi^3 k_c^3 R^2 / E*^2,
  // the pull-off force. A sphere held to a floor by cohesion alone is pulled up by a
  // slowly growing body force (gravity pointing up); it must hold every pull below T_max
  // and leave the floor as the pull passes it.
  constexpr double kKc = 2.0e5;  // [J/m^3]
  const Material m = cohesiveMaterial(kKc);
  const double eStar = m.youngs_modulus / (2.0 * (1.0 - m.poisson_ratio * m.poisson_ratio));
  const double pi = std::numbers::pi;
  const double closedForm = 2.0 / 3.0 * std::pow(pi, 3) * std::pow(kKc, 3) * kRadius * kRadius / (eStar * eStar);
  auto tension = [&](double d) { return kKc * pi * d * (2.0 * kRadius - d) - hertzForce(m, kRadius, d); };
  // The law's exact maximum and the rest overlap without a pull (T = 0 beyond the maximum).
  double tMax = 0.0;
  double dStar = 0.0;
  for (int k = 1; k <= 200000; ++k) {
    const double d = 5.0e-10 * k;  // up to 1e-4 m, ~4 d*
    if (tension(d) > tMax) {
      tMax = tension(d);
      dStar = d;
    }
  }
  // The closed form drops the cap area's -d^2 term: low by ~1.5 d*/R (1.9 % here).
  EXPECT_NEAR(tMax / closedForm, 1.0, 0.03);
  double lo = dStar;
  double hi = 1.0e-3;
  for (int k = 0; k < 100; ++k) (tension(0.5 * (lo + hi)) > 0.0 ? lo : hi) = 0.5 * (lo + hi);
  const double restOverlap = 0.5 * (lo + hi);

  World world(test::fineSettings(1.0e-6, 0.1));
  const auto material = world.addMaterial(m);
  test::addFloorAndSphere(world, material, kRadius, Vec3::Zero(), -restOverlap);
  world.initialize();
  const double mass = 1.0 / world.particles().inv_mass[0];
  // The pull rises to 0.95 T_max in 0.05 s, is held for 0.05 s (the oscillation it
  // started dies out) and then grows by 0.15 T_max per second: slowly, because near
  // T_max the equilibrium overlap runs away ever faster and the damping, which resists
  // the sphere's velocity, holds a little extra tension the faster the pull grows.
  auto pullAt = [&](double t) {
    if (t < 0.05) return 0.95 * tMax * t / 0.05;
    return t < 0.1 ? 0.95 * tMax : tMax * (0.95 + 0.15 * (t - 0.1));
  };
  double pullAtRelease = -1.0;
  for (int step = 0; step < 1'500'000 && pullAtRelease < 0.0; ++step) {
    const double pull = pullAt(world.time());
    world.setGravity(Vec3(0.0, 0.0, pull / mass));
    world.step();
    if (world.particles().position[0].z() > kRadius) pullAtRelease = pull;
  }
  ASSERT_GT(pullAtRelease, 0.0) << "the sphere never left the floor";
  EXPECT_NEAR(pullAtRelease / tMax, 1.0, 0.02) << "T_max " << tMax << " N, released at " << pullAtRelease << " N";
}

TEST(CohesionForce, EnergyOfAnUndampedCohesiveImpactIsConserved) {
  // e = 1: no damping, so the contact is conservative and the pair leaves at its
  // impact speed; the cohesive work on the way in is returned on the way out.
  constexpr double kSpeed = 0.5;  // [m/s]
  World world(test::fineSettings(1.0e-6, kSpeed));
  world.addMaterial(cohesiveMaterial(2.0e5, 1.0, 0.0));
  const std::optional<double> rebound = test::headOnRebound(world, kRadius, kSpeed, 2'000'000);
  ASSERT_TRUE(rebound);
  EXPECT_NEAR(*rebound, 1.0, 2.0e-3);
}

/// Separation of a slow head-on pair after `steps`, the watchdog on (it includes
/// the cohesive potential in its energy check).
double separationAfterSlowImpact(double kc) {
  constexpr double kSpeed = 0.02;  // [m/s]
  World world(test::fineSettings(1.0e-6, 0.3));  // cohesion pulls the pair in at up to ~0.13 m/s
  world.addMaterial(cohesiveMaterial(kc, 0.5, 0.0));
  test::addHeadOnPair(world, kRadius, kSpeed, 1.0e-6);
  world.initialize();
  for (int n = 0; n < 20'000; ++n) world.step();
  const ParticleArrays& p = world.particles();
  return (p.position[1] - p.position[0]).norm() - 2.0 * kRadius;
}

TEST(CohesionForce, CohesionCapturesASlowImpactThatADryPairSurvives) {
  EXPECT_GT(separationAfterSlowImpact(0.0), 1.0e-4);  // dry: 20 ms at >= 0.01 m/s apart
  EXPECT_LT(separationAfterSlowImpact(5.0e5), 0.0);   // cohesive: still overlapping
}

/// Height of the highest centre of a 3 x 3 x 8 block of touching spheres (a cubic
/// packing, centres jittered by 0.2 % of the radius to break its symmetry) after
/// 0.4 s on a floor.
double blockHeightAfterSettling(double kc) {
  SimulationSettings settings = test::fineSettings(1.0e-5, 1.0);
  settings.gravity = Vec3(0.0, 0.0, -9.81);
  World world(settings);
  const auto material = world.addMaterial(cohesiveMaterial(kc, 0.3, 0.5));
  world.addPlane({"floor", Vec3::Zero(), Vec3::UnitZ(), material});
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> jitter(-0.002 * kRadius, 0.002 * kRadius);
  for (int layer = 0; layer < kBlockLayers; ++layer) {
    for (int ix = 0; ix < 3; ++ix) {
      for (int iy = 0; iy < 3; ++iy) {
        ParticleSpec s;
        s.radius = kRadius;
        s.position = Vec3(2.0 * kRadius * ix + jitter(rng), 2.0 * kRadius * iy + jitter(rng),
                          kRadius + 2.0 * kRadius * layer);
        world.addParticle(s);
      }
    }
  }
  world.initialize();
  for (int n = 0; n < 40'000; ++n) world.step();
  const ParticleArrays& p = world.particles();
  return std::max_element(p.position.begin(), p.position.end(),
                          [](const Vec3& a, const Vec3& b) { return a.z() < b.z(); })
      ->z();
}

TEST(CohesionColumn, CohesiveBlockStandsWhereADryOneSlumps) {
  const double initial = kRadius + 2.0 * kRadius * (kBlockLayers - 1);
  const double dry = blockHeightAfterSettling(0.0);
  const double moist = blockHeightAfterSettling(2.0e5);
  EXPECT_LT(dry, 0.6 * initial) << "dry block kept " << dry / initial;
  EXPECT_GT(moist, 0.95 * initial) << "cohesive block fell to " << moist / initial;
}

TEST(CohesionStages, CohesionPassRunsOnlyWhenAPairIsCohesive) {
  for (const double kc : {0.0, 1.0e5}) {
    World world(test::fineSettings(1.0e-6, 0.1));
    world.addMaterial(cohesiveMaterial(kc));
    test::addHeadOnPair(world, kRadius, 0.1, 1.0e-5);
    world.initialize();
    const std::vector<std::string> stages = world.activeStages();
    EXPECT_EQ(std::count(stages.begin(), stages.end(), "cohesion"), kc > 0.0 ? 1 : 0) << kc;
  }
}

TEST(CohesionInput, NegativeOrNonFiniteCohesionIsRefused) {
  for (const double kc : {-1.0, std::numeric_limits<double>::quiet_NaN()}) {
    World world(test::fineSettings(1.0e-6, 0.1));
    try {
      world.addMaterial(cohesiveMaterial(kc));
      FAIL() << "accepted " << kc;
    } catch (const InputError& error) {
      EXPECT_NE(error.field().find("cohesion_energy_density"), std::string::npos) << error.what();
    }
    PairOverride override;
    override.cohesion_energy_density = kc;
    EXPECT_THROW(override.validate("pair"), InputError);
  }
}

}  // namespace
}  // namespace demlink::core
