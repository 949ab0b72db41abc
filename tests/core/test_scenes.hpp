#pragma once
/// Small scenes shared by the physics tests: one place that says how a test
/// world is put together, so each test reads as its physics.
#include <cmath>
#include <functional>
#include <numbers>

#include "demlink/core/world.hpp"

namespace demlink::core::test {

inline Material testMaterial(double restitution, double friction = 0.0, double rolling = 0.0) {
  Material m;
  m.name = "test";
  m.density = 2500.0;
  m.youngs_modulus = 1.0e7;
  m.poisson_ratio = 0.3;
  m.restitution = restitution;
  m.sliding_friction = friction;
  m.rolling_friction = rolling;
  return m;
}

inline double sphereMass(double radius, double density) {
  return 4.0 / 3.0 * std::numbers::pi * radius * radius * radius * density;
}

/// Settings without gravity and with a time step of `stepsPerContact` per
/// Hertz contact at `speed` for two spheres of `radius` (or sphere on a wall).
inline SimulationSettings fineSettings(double dt, double speed, ContactModel model = ContactModel::HertzMindlin) {
  SimulationSettings s;
  s.time_step = dt;
  s.gravity = Vec3::Zero();
  s.contact_model = model;
  s.max_impact_velocity = speed;
  return s;
}

/// Steps the world until `done` returns true or maxSteps pass; returns the steps taken.
inline std::uint64_t stepUntil(World& world, const std::function<bool()>& done, std::uint64_t maxSteps) {
  std::uint64_t n = 0;
  while (n < maxSteps && !done()) {
    world.step();
    ++n;
  }
  return n;
}

}  // namespace demlink::core::test
