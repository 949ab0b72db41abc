// CoarseGraining: parcels of factor alpha carry the bulk mass of alpha^3 grains, and the
// scaling law keeps the Hertz contact's relative overlap under the same bulk stress and the
// cohesive law's bed Bond number and energy density.
#include <cmath>
#include <numbers>

#include <gtest/gtest.h>

#include "demlink/core/contact/contact_stage.hpp"
#include "demlink/core/base/input_error.hpp"
#include "demlink/core/particles/coarse_graining.hpp"

namespace demlink::core {
namespace {

TEST(CoarseGraining, ParcelsCarryTheGrainsMass) {
  const CoarseGraining cg{2.0};
  EXPECT_DOUBLE_EQ(cg.radius(0.0025), 0.005);
  EXPECT_EQ(cg.count(800), 100u);  // 800 / 2^3
  EXPECT_EQ(CoarseGraining{3.0}.count(10), 1u);  // never none
  // Same total volume (mass at equal density) within one parcel.
  const double grains = 1000.0 * std::pow(0.0025, 3);
  const double parcels = static_cast<double>(CoarseGraining{1.5}.count(1000)) * std::pow(1.5 * 0.0025, 3);
  EXPECT_NEAR(parcels / grains, 1.0, 1.5 * 1.5 * 1.5 / 1000.0);
}

TEST(CoarseGraining, HertzOverlapFractionIsKeptAndLinearStiffnessScales) {
  // Hertz: F = 4/3 E* sqrt(R) delta^{3/2}. A bulk stress sigma puts F = sigma R^2 on a
  // contact, so delta / R = (3 sigma / (4 E*))^{2/3} for every R: solve for both sizes.
  const double eStar = 5.5e7, sigma = 1.5e3, r = 0.0025;
  auto overlapFraction = [&](double radius) {
    const double force = sigma * radius * radius;
    const double delta = std::pow(force / (4.0 / 3.0 * eStar * std::sqrt(radius)), 2.0 / 3.0);
    return delta / radius;
  };
  const CoarseGraining cg{3.0};
  EXPECT_NEAR(overlapFraction(cg.radius(r)) / overlapFraction(r), 1.0, 1e-12);
  // Linear law: the same delta / R under F = sigma R^2 needs k ~ R.
  const double k = 1e4;
  const double deltaFraction = sigma * r * r / k / r;
  const double parcelFraction = sigma * cg.radius(r) * cg.radius(r) / cg.linearStiffness(k) / cg.radius(r);
  EXPECT_NEAR(parcelFraction / deltaFraction, 1.0, 1e-12);
}

/// Cohesive measures of a contact between two particles of radius `r` at overlap
/// `fraction` * r, with the simplified JKR law's k_c and the contact stage's own area and
/// potential: the bed Bond number F_coh / (rho g h d^2) at depth h, the single-particle
/// Bond number F_coh / (m g), and the cohesive energy per particle volume [J/m^3].
struct CohesiveMeasures {
  double bed_bond = 0.0;
  double particle_bond = 0.0;
  double energy_density = 0.0;
};
CohesiveMeasures cohesiveMeasures(double kc, double r, double fraction) {
  constexpr double kDensity = 2500.0, kGravity = 9.81, kDepth = 0.1;  // [kg/m^3], [m/s^2], [m]
  const double overlap = fraction * r;
  const double force = kc * pairContactArea(r, r, 2.0 * r - overlap, overlap);
  const double volume = 4.0 / 3.0 * std::numbers::pi * r * r * r;
  return {force / (kDensity * kGravity * kDepth * 4.0 * r * r), force / (kDensity * volume * kGravity),
          -cohesionEnergy(kc, r, r, overlap) / volume};
}

TEST(CoarseGraining, CohesionKeepsTheBedBondNumberAndTheCohesiveEnergyDensity) {
  // Hertz and a cohesive resting contact keep delta / R (sqrt(delta_eq) ~ k_c sqrt(R) / E*),
  // so compare grains and parcels at the same overlap fraction.
  const double kc = 1.5e5, r = 0.0025, fraction = 2e-3;
  const CohesiveMeasures grains = cohesiveMeasures(kc, r, fraction);
  for (double factor : {2.0, 3.0}) {
    const CoarseGraining cg{factor};
    const CohesiveMeasures parcels = cohesiveMeasures(cg.cohesionEnergyDensity(kc), cg.radius(r), fraction);
    EXPECT_NEAR(parcels.bed_bond / grains.bed_bond, 1.0, 1e-12) << factor;
    EXPECT_NEAR(parcels.energy_density / grains.energy_density, 1.0, 1e-12) << factor;
    // What coarse graining gives up: one parcel is alpha^2 grain contacts strong, not alpha^3.
    EXPECT_NEAR(parcels.particle_bond * factor / grains.particle_bond, 1.0, 1e-12) << factor;
  }
}

TEST(CoarseGraining, FactorBelowOneOrNotFiniteIsRefused) {
  EXPECT_NO_THROW(CoarseGraining{1.0}.validate("coarse_graining"));
  for (double bad : {0.5, std::nan(""), HUGE_VAL}) {
    try {
      CoarseGraining{bad}.validate("coarse_graining");
      FAIL() << bad;
    } catch (const InputError& error) {
      EXPECT_EQ(error.field(), "coarse_graining");
    }
  }
}

}  // namespace
}  // namespace demlink::core
