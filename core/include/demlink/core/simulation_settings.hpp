#pragma once
/// Scene-wide settings: the speed/accuracy knobs a user chooses (time step,
/// contact law, integrator, skin) and the world's extent. All SI. They are what
/// the user chose and stay fixed once the world is built; what evolves while it
/// runs (the frame's angular velocity, gravity set by a co-simulation, the
/// defaulted skin, the current bounds) is in WorldState (world_state.hpp).
#include <cstdint>
#include <optional>
#include <string>

#include "demlink/core/contact/contact_model.hpp"
#include "demlink/core/base/math_types.hpp"
#include "demlink/core/step/frame_motion.hpp"
#include "demlink/core/step/watchdog.hpp"

namespace demlink::core {

/// The thread cap when the machine does not tell its hardware threads [-].
inline constexpr std::uint32_t kMaxThreadsUnknownHardware = 64;
/// Largest SimulationSettings::threads: this machine's hardware threads [-].
[[nodiscard]] std::uint32_t maxThreads();

/// Axis-aligned box outside which particles are removed (and counted).
/// Fixed: [lower, upper] is the box. Growing: [lower, upper] is the initial box; it
/// expands to contain every particle's sphere, but never beyond [limit_lower,
/// limit_upper], and particles whose centre leaves the limit box are removed.
struct DomainBounds {
  Vec3 lower = Vec3::Zero();  ///< [m]
  Vec3 upper = Vec3::Zero();  ///< [m]
  bool growing = false;
  Vec3 limit_lower = Vec3::Zero();  ///< growing only [m]
  Vec3 limit_upper = Vec3::Zero();  ///< growing only [m]
};

struct SimulationSettings {
  double time_step = 1.0e-5;                      ///< [s]
  Vec3 gravity = Vec3(0.0, 0.0, -9.81);           ///< initial gravity [m/s^2], frame coordinates
  ContactModel contact_model = ContactModel::HertzMindlin;
  IntegratorKind integrator = IntegratorKind::VelocityVerlet;
  /// Verlet-list skin [m]; 0 chooses half the smallest particle radius (the
  /// skin in force is WorldState::neighbour_skin).
  double neighbour_skin = 0.0;
  /// Largest expected impact speed [m/s]; sets the contact-duration limit on the
  /// time step and the linear law's matched stiffness.
  double max_impact_velocity = 2.0;
  /// Linear law only: normal stiffness [N/m]; 0 derives it from Hertz (see
  /// ContactPairTable) at the mean radius and max_impact_velocity.
  double linear_normal_stiffness = 0.0;
  /// Largest error of the delivered restitution the time-step limit allows, over
  /// every contact-onset phase: relative for e >= 0.1, tolerance * 0.1 absolute
  /// below (critical_time_step.hpp). In (0, 1).
  double restitution_tolerance = 0.01;
  /// Accept a time step above the critical limit (a warning instead of an error).
  bool allow_unsafe_time_step = false;
  std::optional<DomainBounds> bounds;
  /// Initial motion of the frame (the "room" of the docs); default inertial. The
  /// world runs a copy (WorldState::frame) that World::setFrameMotion replaces.
  /// Planes and meshes are at rest in the frame unless moved.
  FrameMotion frame;
  /// Threads for the force, integration and skin-check loops (ThreadPool). Results
  /// are deterministic for a fixed thread count; 1 runs everything serially. At most
  /// maxThreads(): more threads than cores only slow the step down.
  std::uint32_t threads = 1;
  /// How `threads: 0` (auto) was resolved (chooseAutoThreads); empty when given.
  std::string threads_choice;
  /// The run-time watchdog's period, checks and policies (step/watchdog.hpp).
  WatchdogSettings watchdog;
  /// Run the portable pair loop even on a processor with AVX2 and FMA: results
  /// bit-identical across processors, for ~8 % of the step (pair_kernel.hpp).
  bool portable_kernel = false;
  /// Re-sort particle slots by grid cell every this many neighbour builds (0: never).
  std::uint32_t sort_every_builds = 16;

  /// Throws InputError naming `fieldPrefix + ".<field>"`.
  void validate(const std::string& fieldPrefix) const;
};

}  // namespace demlink::core
