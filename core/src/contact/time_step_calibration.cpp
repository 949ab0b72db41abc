#include "demlink/core/contact/time_step_calibration.hpp"

#include <algorithm>
#include <cmath>
#include <map>
#include <mutex>
#include <tuple>

#include "demlink/core/contact/contact_law_registry.hpp"

namespace demlink::core {

double restitutionError(double delivered, double requested) {
  return std::abs(delivered - requested) / std::max(requested, kRestitutionErrorFloor);
}

double worstRestitutionError(ContactModel model, IntegratorKind integrator, double e, double c, double fraction,
                             int phases) {
  const ContactLawEntry& law = contactLaw(model);
  const double h = fraction * law.elastic_duration();
  double worst = 0.0;
  for (int k = 0; k < phases; ++k) {
    const double phase = (k + 0.5) / phases;
    worst = std::max(worst, restitutionError(law.discrete_restitution(c, h, phase, integrator), e));
  }
  return worst;
}

namespace {

/// An elastic contact (e = 1) may rebound faster than it came by at most this share
/// of the tolerance: at the default 0.01 it gains at most 1e-3 of its kinetic energy.
constexpr double kGainShareOfTolerance = 0.05;

bool gainsWithinBound(ContactModel model, IntegratorKind integrator, double e, double c, double fraction,
                      double maxGain) {
  const ContactLawEntry& law = contactLaw(model);
  const double h = fraction * law.elastic_duration();
  for (int k = 0; k < kOnsetPhases; ++k) {
    const double phase = (k + 0.5) / kOnsetPhases;
    if (law.discrete_restitution(c, h, phase, integrator) - e > kPhaseSafety * maxGain) return false;
  }
  return true;
}

double searchStepFraction(ContactModel model, IntegratorKind integrator, double e, double c, double tolerance) {
  const double target = kPhaseSafety * tolerance;
  auto passes = [&](double f) {
    return worstRestitutionError(model, integrator, e, c, f) <= target &&
           (e < 1.0 || gainsWithinBound(model, integrator, e, c, f, kGainShareOfTolerance * tolerance));
  };
  constexpr double kScan = 0.8;        // downward scan ratio
  constexpr double kSmallest = 1e-7;   // below this the rule gives up (the step would be useless)
  double upper = kMaxStepFractionOfContact / kScan;  // a failing (or capped) fraction above `f`
  double f = kMaxStepFractionOfContact;
  for (;;) {
    while (f > kSmallest && !passes(f)) {
      upper = f;
      f *= kScan;
    }
    if (f <= kSmallest) return f;
    // Errors fall roughly linearly with f but not monotonically: a few smaller
    // fractions must pass too, else the scan goes on below the one that failed.
    double failedBelow = 0.0;
    for (double s : {0.8, 0.6, 0.4, 0.2}) {
      if (!passes(s * f)) {
        failedBelow = s * f;
        break;
      }
    }
    if (failedBelow == 0.0) break;
    upper = failedBelow;
    f = failedBelow * kScan;
  }
  if (f >= kMaxStepFractionOfContact) return kMaxStepFractionOfContact;
  double lower = f;
  while (upper - lower > 0.005 * lower) {
    const double mid = 0.5 * (lower + upper);
    if (passes(mid)) lower = mid; else upper = mid;
  }
  return lower;
}

}  // namespace

double accurateStepFraction(ContactModel model, IntegratorKind integrator, double e, double c, double tolerance) {
  using Key = std::tuple<ContactModel, IntegratorKind, double, double>;
  static std::mutex mutex;
  static std::map<Key, double> cache;
  const Key key{model, integrator, e, tolerance};
  {
    const std::lock_guard lock(mutex);
    if (const auto it = cache.find(key); it != cache.end()) return it->second;
  }
  const double f = searchStepFraction(model, integrator, e, c, tolerance);
  const std::lock_guard lock(mutex);
  cache.emplace(key, f);
  return f;
}

}  // namespace demlink::core
