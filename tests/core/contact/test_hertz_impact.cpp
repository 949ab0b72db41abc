// Elastic (e = 1) normal impacts against the closed-form Hertz solution:
//   delta_max = (15 m* v^2 / (16 E* sqrt(R*)))^(2/5)
//   F_max     = 4/3 E* sqrt(R*) delta_max^(3/2)
//   t_c       = 2 delta_max / v * Int_0^1 (1 - x^(5/2))^(-1/2) dx
//             = 2 delta_max / v * (2/5) Gamma(2/5) Gamma(1/2) / Gamma(9/10)
// Bar: each within 1 %.
#include <gtest/gtest.h>

#include "test_scenes.hpp"

namespace demlink::core {
namespace {

struct HertzPrediction {
  double max_overlap;
  double max_force;
  double duration;
};

HertzPrediction hertzPrediction(double eStar, double rStar, double mStar, double v) {
  const double deltaMax = std::pow(15.0 * mStar * v * v / (16.0 * eStar * std::sqrt(rStar)), 0.4);
  const double integral = 0.4 * std::tgamma(0.4) * std::tgamma(0.5) / std::tgamma(0.9);
  return {deltaMax, 4.0 / 3.0 * eStar * std::sqrt(rStar) * std::pow(deltaMax, 1.5), 2.0 * deltaMax / v * integral};
}

struct Measured {
  double max_overlap = 0.0;
  double max_force = 0.0;
  double duration = 0.0;
};

constexpr double kRadius = 0.01;
constexpr double kSpeed = 1.0;
constexpr double kDt = 2.0e-7;  // ~600 steps per contact

TEST(HertzImpact, SphereOnPlaneMatchesClosedForm) {
  World world(test::fineSettings(kDt, kSpeed));
  const auto mat = world.addMaterial(test::testMaterial(1.0));
  test::addFloorAndSphere(world, mat, kRadius, Vec3(0.0, 0.0, -kSpeed), 1e-5);
  world.initialize();

  Measured m;
  std::uint64_t stepsInContact = 0;
  auto& q = world.particles();
  test::stepUntil(
      world,
      [&] {
        const double overlap = kRadius - q.position[0].z();
        m.max_overlap = std::max(m.max_overlap, overlap);
        m.max_force = std::max(m.max_force, q.force[0].z());
        if (q.force[0].z() > 0.0) ++stepsInContact;
        return q.velocity[0].z() > 0.0 && q.force[0].z() == 0.0;
      },
      2'000'000);
  m.duration = static_cast<double>(stepsInContact) * kDt;

  const double mass = test::sphereMass(kRadius, 2500.0);
  const HertzPrediction h = hertzPrediction(world.pairTable()(0, 0).effective_youngs, kRadius, mass, kSpeed);
  EXPECT_NEAR(m.max_overlap / h.max_overlap, 1.0, 0.01);
  EXPECT_NEAR(m.max_force / h.max_force, 1.0, 0.01);
  EXPECT_NEAR(m.duration / h.duration, 1.0, 0.01);
  EXPECT_NEAR(q.velocity[0].z() / kSpeed, 1.0, 0.01) << "elastic impact must rebound at the impact speed";
}

TEST(HertzImpact, SphereOnSphereMatchesClosedForm) {
  World world(test::fineSettings(kDt, kSpeed));
  world.addMaterial(test::testMaterial(1.0));
  test::addHeadOnPair(world, kRadius, kSpeed, 2e-5);
  world.initialize();
  auto& p = world.particles();
  // Slots may be reordered by the cell sort: identify particles by id.
  auto slotOf = [&](std::uint64_t id) { return p.id[0] == id ? 0u : 1u; };

  Measured m;
  std::uint64_t stepsInContact = 0;
  test::stepUntil(
      world,
      [&] {
        const std::size_t ia = slotOf(1);
        const std::size_t ib = slotOf(2);
        const double overlap = 2.0 * kRadius - (p.position[ib] - p.position[ia]).norm();
        m.max_overlap = std::max(m.max_overlap, overlap);
        m.max_force = std::max(m.max_force, p.force[ib].x());
        if (p.force[ib].x() > 0.0) ++stepsInContact;
        return p.velocity[ib].x() > 0.0 && p.force[ib].x() == 0.0;
      },
      2'000'000);
  m.duration = static_cast<double>(stepsInContact) * kDt;

  const double mass = test::sphereMass(kRadius, 2500.0);
  const HertzPrediction h =
      hertzPrediction(world.pairTable()(0, 0).effective_youngs, 0.5 * kRadius, 0.5 * mass, kSpeed);
  EXPECT_NEAR(m.max_overlap / h.max_overlap, 1.0, 0.01);
  EXPECT_NEAR(m.max_force / h.max_force, 1.0, 0.01);
  EXPECT_NEAR(m.duration / h.duration, 1.0, 0.01);
  // Momentum of the pair is conserved to round-off.
  const Vec3 momentum = p.mass[0] * p.velocity[0] + p.mass[1] * p.velocity[1];
  EXPECT_LT(momentum.norm(), 1e-15 * p.mass[0] * kSpeed);
}

}  // namespace
}  // namespace demlink::core
