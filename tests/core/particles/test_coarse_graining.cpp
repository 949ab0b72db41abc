// CoarseGraining: parcels of factor alpha carry the bulk mass of alpha^3 grains, and the
// scaling law keeps the Hertz contact's relative overlap under the same bulk stress.
#include <cmath>

#include <gtest/gtest.h>

#include "demlink/core/input_error.hpp"
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
  // Bond number Gamma R / (rho g R^3) kept by Gamma ~ alpha^2.
  const double bond = 0.05 * r / std::pow(r, 3);
  EXPECT_NEAR(cg.cohesionEnergy(0.05) * cg.radius(r) / std::pow(cg.radius(r), 3) / bond, 1.0, 1e-12);
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
