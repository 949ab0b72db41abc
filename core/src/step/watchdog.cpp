#include "demlink/core/step/watchdog.hpp"

#include <algorithm>
#include <cmath>

#include <spdlog/fmt/fmt.h>
#include <spdlog/spdlog.h>

#include "demlink/core/base/input_error.hpp"

namespace demlink::core {

namespace {
/// An elastic rebound may leave at the impact speed plus integration error: a speed
/// counts as above the validated one beyond 1 % more.
constexpr double kSpeedMargin = 1.01;
}  // namespace

std::string_view toString(GuardPolicy policy) { return policy == GuardPolicy::Stop ? "stop" : "warn"; }

void WatchdogSettings::validate(const std::string& fieldPrefix) const {
  requireHalfOpenRange(fieldPrefix + ".max_overlap_fraction", max_overlap_fraction, 0.0, 2.0);
  requirePositive(fieldPrefix + ".max_energy_growth", max_energy_growth);
  requireFinite(fieldPrefix + ".max_energy_growth", max_energy_growth);
  requireFinite(fieldPrefix + ".max_speed_factor", max_speed_factor);
  if (!(max_speed_factor > 1.0)) {
    throw InputError(fieldPrefix + ".max_speed_factor", formatValue(max_speed_factor), "must be greater than 1");
  }
}

SimulationFault::SimulationFault(std::string check, std::string detail, std::uint64_t step)
    : std::runtime_error("watchdog " + check + " at step " + std::to_string(step) + ": " + detail),
      check_(std::move(check)),
      detail_(std::move(detail)),
      step_(step) {}

void Watchdog::warnOnce(const std::string& check, const std::string& message) {
  if (std::find(warned_checks_.begin(), warned_checks_.end(), check) != warned_checks_.end()) return;
  warned_checks_.push_back(check);
  warnings_.push_back(message);
  spdlog::warn("{}", message);
}

std::optional<SimulationFault> Watchdog::assess(const WatchdogReading& r, const WatchdogSettings& s,
                                                double validatedSpeed, std::uint64_t step) {
  if (!r.non_finite.empty()) return SimulationFault("non_finite", r.non_finite + " is not finite", step);
  std::vector<SimulationFault> faults;
  auto judge = [&](GuardPolicy policy, const std::string& check, const std::string& detail) {
    if (policy == GuardPolicy::Stop) {
      faults.emplace_back(check, detail, step);
    } else {
      warnOnce(check, fmt::format("watchdog {} at step {}: {}", check, step, detail));
    }
  };
  if (r.max_overlap_fraction > s.max_overlap_fraction) {
    judge(s.policy, "overlap",
          fmt::format("{} overlaps by {:.3g} of the smaller radius (max_overlap_fraction {:.3g}); the time step is "
                      "too large, or the material too soft for the speeds and loads",
                      r.deepest, r.max_overlap_fraction, s.max_overlap_fraction));
  }
  if (r.energy_checked) {
    if (!energy_seen_) {
      energy_seen_ = true;
      energy_min_ = r.total_energy;
      energy_scale_ = r.kinetic_energy + r.elastic_energy;
    } else {
      energy_scale_ = std::max(energy_scale_, r.kinetic_energy + r.elastic_energy);
      const double growth = r.total_energy - energy_min_;
      if (growth > s.max_energy_growth * energy_scale_ && growth > 0.0) {
        judge(s.policy, "energy",
              fmt::format("the energy rose by {:.4g} J since its minimum, {:.3g} of the largest energy in motion "
                          "{:.4g} J (max_energy_growth {:.3g}), with nothing feeding energy in; the time step is "
                          "too large",
                          growth, growth / energy_scale_, energy_scale_, s.max_energy_growth));
      }
      energy_min_ = std::min(energy_min_, r.total_energy);
    }
  }
  largest_speed_ = std::max(largest_speed_, r.max_speed);
  if (r.max_speed > s.max_speed_factor * validatedSpeed) {
    judge(s.policy, "speed_bound",
          fmt::format("{} moves at {:.4g} m/s, beyond {:.3g} x the validated impact speed {:.4g} m/s", r.fastest,
                      r.max_speed, s.max_speed_factor, validatedSpeed));
  } else if (r.max_speed > kSpeedMargin * validatedSpeed) {
    judge(s.speed_policy, "speed",
          fmt::format("{} moves at {:.4g} m/s, faster than the validated impact speed {:.4g} m/s: the time-step "
                      "limit was computed for slower impacts; raise max_impact_velocity",
                      r.fastest, r.max_speed, validatedSpeed));
  }
  if (faults.empty()) return std::nullopt;
  return faults.front();
}

}  // namespace demlink::core
