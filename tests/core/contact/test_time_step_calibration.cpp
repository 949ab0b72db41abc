// The time-step calibration's discrete model against the independent Python
// study of the same ODE and integrator, its convergence to the calibrated e as
// dt -> 0, and the fraction it finds: within the tolerance there, beyond it
// just above.
#include <algorithm>
#include <cmath>
#include <numbers>

#include <gtest/gtest.h>

#include "demlink/core/contact/contact_law_registry.hpp"
#include "demlink/core/contact/time_step_calibration.hpp"

namespace demlink::core {
namespace {

TEST(TimeStepCalibration, ElasticDurations) {
  // Linear: half a period of x'' = -x. Hertz: 2 * 1.6093 (Johnson, Contact
  // Mechanics, 1985, sec. 11.4: t_c = 2.87 (m*^2 / (R* E*^2 v))^(1/5)).
  EXPECT_NEAR(contactLaw(ContactModel::LinearSpringDashpot).elastic_duration(), std::numbers::pi, 1e-6);
  EXPECT_NEAR(contactLaw(ContactModel::HertzMindlin).elastic_duration(), 3.2187, 1e-3);
}

TEST(TimeStepCalibration, MatchesThePhaseStudyAtOneHundredthOfTheContact) {
  // Worst error over 32 phases at dt = t_c / 100, Hertz, velocity Verlet, from the
  // Python study (x'' = -x^1.5 - c x^0.25 x', clamped, half-kicked damping velocity).
  const ContactLawEntry& law = contactLaw(ContactModel::HertzMindlin);
  const std::pair<double, double> study[] = {{0.1, 0.0280}, {0.2, 0.0145}, {0.5, 0.0034}, {0.9, 0.0002}};
  for (const auto& [e, worst] : study) {
    const double c = law.damping_for_restitution(e);
    const double got = worstRestitutionError(ContactModel::HertzMindlin, IntegratorKind::VelocityVerlet, e, c, 0.01, 32);
    EXPECT_NEAR(got, worst, 0.1 * worst + 5e-5) << "e=" << e;
  }
}

TEST(TimeStepCalibration, ConvergesToTheCalibratedRestitution) {
  for (const ContactLawEntry& law : contactLaws()) {
    for (double e : {0.1, 0.5, 1.0}) {
      const double c = law.damping_for_restitution(e);
      const double coarse = worstRestitutionError(law.model, IntegratorKind::VelocityVerlet, e, c, 0.01, 8);
      const double fine = worstRestitutionError(law.model, IntegratorKind::VelocityVerlet, e, c, 0.0005, 8);
      // First order in the step: 20 x smaller, ~20 x more accurate.
      EXPECT_LT(fine, 5e-3) << law.name << " e=" << e;
      EXPECT_LE(fine, 0.1 * coarse + 1e-5) << law.name << " e=" << e;
    }
  }
}

TEST(TimeStepCalibration, FractionIsWithinTheToleranceAndTight) {
  constexpr double kTolerance = 0.01;
  for (const ContactLawEntry& law : contactLaws()) {
    for (const IntegratorKind integrator : {IntegratorKind::VelocityVerlet, IntegratorKind::ExplicitEuler}) {
      for (double e : {0.05, 0.1, 0.2, 0.5, 0.9, 1.0}) {
        const double c = law.damping_for_restitution(e);
        const double f = accurateStepFraction(law.model, integrator, e, c, kTolerance);
        ASSERT_GT(f, 0.0);
        ASSERT_LE(f, kMaxStepFractionOfContact);
        // Denser phases than the search used: the margin covers them.
        EXPECT_LE(worstRestitutionError(law.model, integrator, e, c, f, 4 * kOnsetPhases), kTolerance)
            << law.name << " " << toString(integrator) << " e=" << e;
        EXPECT_LE(worstRestitutionError(law.model, integrator, e, c, 0.5 * f, 4 * kOnsetPhases), kTolerance)
            << law.name << " " << toString(integrator) << " e=" << e;
        // Just above f the error target or, for e = 1, the bound on gains (0.05 x tolerance) fails
        // (within 30 %: the error is not monotonic in f, so not necessarily at 1.01 f).
        if (f < kMaxStepFractionOfContact) {
          bool fails = false;
          for (double above : {1.005 * f, 1.01 * f, 1.02 * f, 1.05 * f, 1.1 * f, 1.2 * f, 1.3 * f}) {
            double gain = -1.0;
            for (int k = 0; k < kOnsetPhases; ++k) {
              const double phase = (k + 0.5) / kOnsetPhases;
              gain = std::max(gain, law.discrete_restitution(c, above * law.elastic_duration(), phase, integrator) - e);
            }
            fails = fails || worstRestitutionError(law.model, integrator, e, c, above) > kPhaseSafety * kTolerance ||
                    (e == 1.0 && gain > kPhaseSafety * 0.05 * kTolerance);
          }
          EXPECT_TRUE(fails) << law.name << " " << toString(integrator) << " e=" << e << " f=" << f;
        }
      }
    }
  }
}

}  // namespace
}  // namespace demlink::core
