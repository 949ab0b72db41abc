#pragma once
/// The one rule that turns a duration in seconds into a whole number of time steps:
/// frame, checkpoint, sample and communication intervals and the end time, headless and
/// coupled alike (docs/headless.md, "Times in seconds become whole steps").
///
///   n = round(seconds / dt)
///   seconds == 0      -> n = 0 ("off") or refused, as the field says (IntervalRule::zero)
///   n == 0            -> refused: shorter than half a time step
///   n > max_steps     -> refused: too many steps (1e15 by default; a co-simulation caps
///                        one communication interval at 1e8, see cosim_compiler.cpp)
///   |n dt - seconds| > 1e-6 dt
///                     -> rounded, with a warning the caller reports, or refused when
///                        the rule is strict (coupling.strict_intervals)
///
/// Why one rule: time is an integer step counter in the engine, so every interval must
/// become steps once; when each caller did it its own way, the same vtk_interval was an
/// error headless and silently one step in a co-simulation.
#include <cstdint>
#include <string>

namespace demlink::core {

/// What an interval of exactly 0 s means for a field.
enum class ZeroInterval {
  Off,      ///< 0 steps: the output or exchange is off (vtk_interval, checkpoint_interval, ...)
  Refused,  ///< an InputError: the field needs a positive time (end_time of a headless run, ...)
};

/// Most steps an interval may span by default [-]: beyond this a step counter in a
/// double loses whole steps and no run could finish anyway.
inline constexpr std::uint64_t kMaxIntervalSteps = 1'000'000'000'000'000;

/// Largest difference between the requested time and the rounded n dt, as a fraction of
/// dt, that still counts as "a whole number of steps" [-].
inline constexpr double kOffGridTolerance = 1.0e-6;

/// How one field converts its interval.
struct IntervalRule {
  ZeroInterval zero = ZeroInterval::Off;
  bool strict = false;                         ///< refuse instead of rounding off-grid times
  std::uint64_t max_steps = kMaxIntervalSteps;  ///< [-]
  /// Appended to the "too many steps" reason, e.g. why a tighter cap applies.
  std::string max_steps_why;
};

/// A converted interval.
struct IntervalSteps {
  std::uint64_t steps = 0;  ///< [-]; 0 only for an interval of 0 s under ZeroInterval::Off
  /// Non-empty when the time was rounded: "<field> = <s> s is not a multiple of the time
  /// step <dt> s; rounded to <n> steps = <n dt> s". The caller logs or reports it.
  std::string warning;
};

/// Converts `seconds` to steps of `timeStep` [s] under `rule`. Throws InputError naming
/// `field`, the value and the reason (negative or not finite, 0 where refused, shorter
/// than half a step, too many steps, off the step grid in strict mode). `timeStep` must
/// be finite and > 0 (an InputError naming "time_step" otherwise).
[[nodiscard]] IntervalSteps intervalSteps(const std::string& field, double seconds, double timeStep,
                                          const IntervalRule& rule = {});

}  // namespace demlink::core
