#include <cmath>
#include <numbers>

#include <gtest/gtest.h>

#include "demlink/core/contact/contact_law_registry.hpp"
#include "demlink/core/contact/restitution_calibration.hpp"

namespace demlink::core {
namespace {

TEST(RestitutionCalibration, LinearUndampedAndClosedFormBounds) {
  EXPECT_NEAR(deliveredRestitution<LinearSpringDashpotLaw>(0.0), 1.0, 1e-6);
  EXPECT_NEAR(deliveredRestitution<HertzMindlinLaw>(0.0), 1.0, 1e-6);
  // Clamping ends the contact earlier than the overlap closing, so the delivered
  // restitution exceeds the unclamped closed form exp(-pi zeta / sqrt(1 - zeta^2)).
  const double zeta = 0.2;
  const double unclamped = std::exp(-std::numbers::pi * zeta / std::sqrt(1.0 - zeta * zeta));
  EXPECT_GT(deliveredRestitution<LinearSpringDashpotLaw>(2.0 * zeta), unclamped);
}

TEST(RestitutionCalibration, InverseRoundTrips) {
  for (const ContactLawEntry& law : contactLaws()) {
    for (double e : {0.1, 0.3, 0.5, 0.7, 0.9, 0.99}) {
      const double c = law.damping_for_restitution(e);
      EXPECT_NEAR(law.delivered_restitution(c), e, 1e-6) << law.name << " e=" << e;
    }
  }
}

}  // namespace
}  // namespace demlink::core
