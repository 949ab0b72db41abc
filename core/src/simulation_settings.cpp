#include "demlink/core/simulation_settings.hpp"

#include "demlink/core/input_error.hpp"

namespace demlink::core {

namespace {
void requireFiniteVector(const std::string& field, const Vec3& v) {
  for (int k = 0; k < 3; ++k) requireFinite(field + "[" + std::to_string(k) + "]", v[k]);
}
}  // namespace

void SimulationSettings::validate(const std::string& fieldPrefix) const {
  requirePositive(fieldPrefix + ".time_step", time_step);
  requireFiniteVector(fieldPrefix + ".gravity", gravity);
  requireNonNegative(fieldPrefix + ".neighbour_skin", neighbour_skin);
  requirePositive(fieldPrefix + ".max_impact_velocity", max_impact_velocity);
  requireNonNegative(fieldPrefix + ".linear_normal_stiffness", linear_normal_stiffness);
  requireOpenRange(fieldPrefix + ".restitution_tolerance", restitution_tolerance, 0.0, 1.0);
  if (threads < 1 || threads > 1024) {
    throw InputError(fieldPrefix + ".threads", std::to_string(threads), "must be between 1 and 1024");
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
