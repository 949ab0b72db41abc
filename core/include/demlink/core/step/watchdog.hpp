#pragma once
/// The run-time watchdog (stage `watchdog`, every WatchdogSettings::every_steps
/// steps) and the speeds the time-step limit is validated against.
///
/// Checks, in this order (docs/physics.md "Watchdog"):
///   non_finite    a particle position, velocity, spin or force is NaN or infinite:
///                 always stops (nothing after it means anything);
///   overlap       a particle pair or a particle on a plane overlaps by more than
///                 max_overlap_fraction of the smaller radius;
///   energy        kinetic + gravitational + elastic contact energy rose by more
///                 than max_energy_growth of the largest energy in motion seen
///                 (kinetic + elastic), since the smallest total seen; only while
///                 nothing feeds energy in (no source, no moving mesh, an inertial
///                 frame; a gravity change restarts it);
///   speed_bound   a particle (or a mesh point) moves faster than
///                 max_speed_factor x the validated impact speed;
///   speed         faster than the validated impact speed itself: the time-step
///                 limit was computed for a slower impact. speed_policy decides
///                 (WARN: once per run; STOP: the strict policy).
/// policy decides for overlap, energy and speed_bound: STOP ends the run with a
/// SimulationFault naming the check, WARN logs each check once.
#include <cstdint>
#include <optional>
#include <stdexcept>
#include <string>
#include <utility>
#include <string_view>
#include <vector>

namespace demlink::core {

enum class GuardPolicy : std::uint8_t {
  Warn,  ///< log once per check and go on
  Stop,  ///< end the run with a SimulationFault
};
std::string_view toString(GuardPolicy policy);

struct WatchdogSettings {
  /// Steps between checks; 0 switches the watchdog off (the stage is not selected).
  std::uint32_t every_steps = 100;
  GuardPolicy policy = GuardPolicy::Stop;        ///< overlap, energy, speed_bound
  GuardPolicy speed_policy = GuardPolicy::Warn;  ///< above the validated impact speed (Stop: strict)
  double max_overlap_fraction = 0.5;  ///< of the smaller radius, in (0, 2]
  double max_energy_growth = 0.1;     ///< of the energy scale in motion, > 0
  double max_speed_factor = 10.0;     ///< x the validated impact speed, > 1

  /// Throws InputError naming `fieldPrefix + ".<field>"`.
  void validate(const std::string& fieldPrefix) const;
};

/// Thrown by World::step when a watchdog check under the STOP policy fails.
class SimulationFault : public std::runtime_error {
 public:
  SimulationFault(std::string check, std::string detail, std::uint64_t step);
  /// "non_finite", "overlap", "energy", "speed_bound" or "speed".
  [[nodiscard]] const std::string& check() const { return check_; }
  [[nodiscard]] const std::string& detail() const { return detail_; }
  /// The step count when the check ran.
  [[nodiscard]] std::uint64_t step() const { return step_; }

 private:
  std::string check_;
  std::string detail_;
  std::uint64_t step_;
};

/// What one check measured (World::watch fills it).
struct WatchdogReading {
  std::string non_finite;            ///< what is not finite; empty: all finite
  double max_speed = 0.0;            ///< [m/s]
  std::string fastest;               ///< what moves at max_speed
  double max_overlap_fraction = 0.0; ///< overlap / smaller radius
  std::string deepest;               ///< which contact
  bool energy_checked = false;       ///< nothing fed energy in since the last reset
  double kinetic_energy = 0.0;       ///< [J]
  double total_energy = 0.0;         ///< kinetic + gravitational + elastic + cohesive [J]
  double elastic_energy = 0.0;       ///< [J]
  double cohesion_energy = 0.0;      ///< potential of the cohesive contacts, <= 0 [J]
};

/// The watchdog's memory between checks.
class Watchdog {
 public:
  /// Forgets the energy history (start, gravity changed, energy fed in).
  void resetEnergy() { energy_seen_ = false; }
  /// Decides on a reading: the fault to throw (STOP policies), warnings logged
  /// once per check (WARN policies). `validatedSpeed` [m/s].
  [[nodiscard]] std::optional<SimulationFault> assess(const WatchdogReading& reading, const WatchdogSettings& settings,
                                                      double validatedSpeed, std::uint64_t step);
  /// Warnings given so far (each check at most once), for reports.
  [[nodiscard]] const std::vector<std::string>& warnings() const { return warnings_; }
  /// Largest speed any check has seen [m/s] and what moved at it.
  [[nodiscard]] double largestSpeedSeen() const { return largest_speed_; }
  /// Notes that something fed energy in (a mesh moved): the next reading is not
  /// checked for energy growth, and the history starts again after it.
  void noteEnergyFed() { energy_fed_ = true; }
  /// Whether energy was fed in since the last call (and forgets it).
  [[nodiscard]] bool takeEnergyFed() { return std::exchange(energy_fed_, false); }

 private:
  void warnOnce(const std::string& check, const std::string& message);

  bool energy_seen_ = false;
  bool energy_fed_ = false;    ///< a mesh moved since the last reading
  double energy_min_ = 0.0;    ///< smallest total energy since the reset [J]
  double energy_scale_ = 0.0;  ///< largest kinetic + elastic energy since the reset [J]
  double largest_speed_ = 0.0;
  std::vector<std::string> warned_checks_;
  std::vector<std::string> warnings_;
};

}  // namespace demlink::core
