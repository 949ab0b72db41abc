/// Seconds to whole steps (contract and rule in interval_steps.hpp).
///
/// The "too many steps" test comes first: it also keeps llround away from values it
/// cannot represent, and it catches a tiny time step (a valid 1e-220 s) as well as a
/// long interval.
#include "demlink/core/step/interval_steps.hpp"

#include <spdlog/fmt/fmt.h>

#include <cmath>

#include "demlink/core/base/input_error.hpp"

namespace demlink::core {

IntervalSteps intervalSteps(const std::string& field, double seconds, double timeStep, const IntervalRule& rule) {
  requirePositive("time_step", timeStep);
  if (rule.zero == ZeroInterval::Off) {
    requireNonNegative(field, seconds);
    if (seconds == 0.0) return {};
  } else {
    requirePositive(field, seconds);
  }
  const std::string value = formatValue(seconds);
  const double exact = seconds / timeStep;
  // Compared before rounding, as round(exact) <= max_steps.
  if (!(exact < static_cast<double>(rule.max_steps) + 0.5)) {
    throw InputError(field, value,
                     fmt::format("{:.3g} time steps of {} s; at most {}{}", exact, formatValue(timeStep),
                                 rule.max_steps, rule.max_steps_why.empty() ? "" : " " + rule.max_steps_why));
  }
  IntervalSteps out;
  out.steps = static_cast<std::uint64_t>(std::llround(exact));
  if (out.steps == 0) {
    throw InputError(field, value, "shorter than half a time step (" + formatValue(timeStep) + " s)");
  }
  const double rounded = static_cast<double>(out.steps) * timeStep;
  if (std::abs(rounded - seconds) > kOffGridTolerance * timeStep) {
    if (rule.strict) {
      throw InputError(field, value,
                       fmt::format("not a whole multiple of the time step {} s (strict_intervals); nearest: {} "
                                   "steps = {} s",
                                   formatValue(timeStep), out.steps, formatValue(rounded)));
    }
    out.warning = fmt::format("{} = {} s is not a multiple of the time step {} s; rounded to {} steps = {} s", field,
                              value, formatValue(timeStep), out.steps, formatValue(rounded));
  }
  return out;
}

}  // namespace demlink::core
