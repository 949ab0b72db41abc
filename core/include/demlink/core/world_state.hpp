#pragma once
/// What evolves while a world runs, apart from the particles, the contact lists
/// and the bodies: the clock, the frame's motion now, gravity now, the skin in
/// force, the current bounds and the counters. The user's choices stay in
/// SimulationSettings, which World never changes after construction; a
/// co-simulation that changes the frame motion or gravity between intervals
/// changes this state (World::setFrameMotion, World::setGravity).
#include <cstdint>

#include "demlink/core/base/math_types.hpp"
#include "demlink/core/simulation_settings.hpp"
#include "demlink/core/step/frame_motion.hpp"

namespace demlink::core {

/// Particles removed (at the domain bounds, by a sink). A clump counts once, with
/// its whole mass.
struct RemovalTally {
  std::uint64_t count = 0;
  double mass = 0.0;  ///< [kg]
};

struct WorldState {
  /// Starts from what the user chose.
  explicit WorldState(const SimulationSettings& settings)
      : gravity(settings.gravity), neighbour_skin(settings.neighbour_skin) {
    setFrame(settings.frame);
    if (settings.bounds) bounds = *settings.bounds;
  }

  /// Replaces the frame motion (and whether the frame moves at all).
  void setFrame(const FrameMotion& motion) {
    frame = motion;
    frame_moving = !motion.isInertial();
  }

  std::uint64_t step_count = 0;  ///< steps taken; time = step_count * time_step [s]
  Vec3 gravity;                  ///< gravity in force [m/s^2], frame coordinates
  /// The frame's motion now; its angular_velocity advances by
  /// angular_acceleration * dt every step (stage moving_frame).
  FrameMotion frame;
  bool frame_moving = false;  ///< frame is not inertial: fictitious forces apply
  /// Verlet-list skin in force [m]: the user's, or the default chosen at initialize().
  double neighbour_skin = 0.0;
  /// The domain box now (growing bounds: as of the last bounds pass); meaningful
  /// only when the settings have bounds.
  DomainBounds bounds;
  RemovalTally removed_at_bounds;
  std::uint64_t next_particle_id = 1;
  std::uint64_t next_clump_id = 1;
};

}  // namespace demlink::core
