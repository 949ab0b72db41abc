#include "demlink/core/simulation_settings.hpp"

#include <thread>

#include "demlink/core/base/input_bounds.hpp"
#include "demlink/core/base/input_error.hpp"

namespace demlink::core {

std::uint32_t maxThreads() {
  const unsigned hardware = std::thread::hardware_concurrency();  // 0: unknown
  return hardware > 0 ? hardware : kMaxThreadsUnknownHardware;
}

void SimulationSettings::validate(const std::string& fieldPrefix) const {
  requirePositive(fieldPrefix + ".time_step", time_step);
  requireBoundedVector(fieldPrefix + ".gravity", gravity, kMaxAcceleration, "m/s^2");
  // The first step's velocity change g dt must stay a sane speed (a huge time step
  // accepted with allow_unsafe_time_step would otherwise overflow the positions).
  if (!(gravity.norm() * time_step <= kMaxSpeed)) {
    throw InputError(fieldPrefix + ".time_step", formatValue(time_step),
                     "|gravity| x time_step = " + formatValue(gravity.norm() * time_step) + " m/s exceeds " +
                         formatValue(kMaxSpeed) + " m/s per step");
  }
  requireNonNegative(fieldPrefix + ".neighbour_skin", neighbour_skin);
  requirePositive(fieldPrefix + ".max_impact_velocity", max_impact_velocity);
  requireNonNegative(fieldPrefix + ".linear_normal_stiffness", linear_normal_stiffness);
  requireOpenRange(fieldPrefix + ".restitution_tolerance", restitution_tolerance, 0.0, 1.0);
  if (threads < 1 || threads > maxThreads()) {
    throw InputError(fieldPrefix + ".threads", std::to_string(threads),
                     "must be between 1 and " + std::to_string(maxThreads()) +
                         " (this machine's hardware threads; 0 in a scene picks a count automatically)");
  }
  if (bounds) {
    requireFiniteVector(fieldPrefix + ".bounds.lower", bounds->lower);
    requireFiniteVector(fieldPrefix + ".bounds.upper", bounds->upper);
    for (int k = 0; k < 3; ++k) {
      if (!(bounds->upper[k] > bounds->lower[k])) {
        throw InputError(fieldPrefix + ".bounds.upper[" + std::to_string(k) + "]", formatValue(bounds->upper[k]),
                         "must be greater than bounds.lower[" + std::to_string(k) + "] = " +
                             formatValue(bounds->lower[k]));
      }
    }
    if (bounds->growing) {
      requireFiniteVector(fieldPrefix + ".bounds.limit_lower", bounds->limit_lower);
      requireFiniteVector(fieldPrefix + ".bounds.limit_upper", bounds->limit_upper);
      for (int k = 0; k < 3; ++k) {
        const std::string kText = std::to_string(k);
        if (bounds->limit_lower[k] > bounds->lower[k]) {
          throw InputError(fieldPrefix + ".bounds.limit_lower[" + kText + "]", formatValue(bounds->limit_lower[k]),
                           "the limit box must contain the initial box (bounds.lower[" + kText + "] = " +
                               formatValue(bounds->lower[k]) + ")");
        }
        if (bounds->limit_upper[k] < bounds->upper[k]) {
          throw InputError(fieldPrefix + ".bounds.limit_upper[" + kText + "]", formatValue(bounds->limit_upper[k]),
                           "the limit box must contain the initial box (bounds.upper[" + kText + "] = " +
                               formatValue(bounds->upper[k]) + ")");
        }
      }
    }
  }
  frame.validate(fieldPrefix + ".frame");
  watchdog.validate(fieldPrefix + ".watchdog");
}

}  // namespace demlink::core
