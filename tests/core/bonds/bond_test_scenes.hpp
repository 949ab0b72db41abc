#pragma once
/// Small bonded scenes shared by the parallel-bond tests: spheres of one soft material
/// (their Hertz contact never limits the step), no gravity unless a test sets it, and
/// one bond rule that bonds everything within its gap tolerance at the first step.
#include <cmath>
#include <numbers>

#include "demlink/core/world.hpp"

namespace demlink::core::test {

inline constexpr double kBondRadius = 1.0e-3;     ///< sphere radius [m]
inline constexpr double kBondDensity = 2500.0;    ///< [kg/m^3]
inline constexpr double kBondGap = 1.0e-5;        ///< surface gap of bonded neighbours [m]: they never touch

inline Material bondedMaterial() {
  Material m;
  m.name = "rock";
  m.density = kBondDensity;
  m.youngs_modulus = 1.0e7;
  m.poisson_ratio = 0.3;
  m.restitution = 0.5;
  return m;
}

inline SimulationSettings bondSettings(double dt) {
  SimulationSettings s;
  s.time_step = dt;
  s.gravity = Vec3::Zero();
  s.max_impact_velocity = 0.1;
  s.restitution_tolerance = 0.2;
  return s;
}

inline ParallelBondProperties bondProperties(double kn = 1.0e11, double ks = 1.0e11) {
  ParallelBondProperties p;
  p.radius_multiplier = 1.0;
  p.normal_stiffness_per_area = kn;
  p.shear_stiffness_per_area = ks;
  p.tensile_strength = 1.0e30;  // unbreakable unless a test sets it
  p.shear_strength = 1.0e30;
  p.gap_tolerance = 2.0 * kBondGap;
  return p;
}

/// A rule named "cement" bonding every pair within the gap tolerance at step 0.
inline BondRule everywhere(const ParallelBondProperties& properties) {
  BondRule rule;
  rule.name = "cement";
  rule.properties = properties;
  return rule;
}

inline double sphereMassOf(double radius) { return 4.0 / 3.0 * std::numbers::pi * std::pow(radius, 3) * kBondDensity; }

/// Adds a sphere of kBondRadius at x with velocity v.
inline std::uint64_t addSphere(World& world, const Vec3& x, const Vec3& v = Vec3::Zero(),
                               const Vec3& spin = Vec3::Zero()) {
  ParticleSpec s;
  s.radius = kBondRadius;
  s.position = x;
  s.velocity = v;
  s.angular_velocity = spin;
  return world.addParticle(s);
}

/// Slot of the particle with stable id `id`.
inline std::size_t slotOf(const World& world, std::uint64_t id) {
  const ParticleArrays& p = world.particles();
  for (std::size_t i = 0; i < p.size(); ++i) {
    if (p.id[i] == id) return i;
  }
  return p.size();
}

}  // namespace demlink::core::test
