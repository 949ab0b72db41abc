#pragma once
/// Small scenes shared by the physics tests: one place that says how a test
/// world is put together, so each test reads as its physics.
#include <cmath>
#include <functional>
#include <numbers>
#include <optional>
#include <random>
#include <set>
#include <utility>

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
  // The physics tests measure restitution themselves at steps chosen before the
  // restitution limit existed; tests of the limit set the tolerance back.
  s.restitution_tolerance = 0.2;
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

/// A floor plane z = 0 of material `material` and one sphere of `radius` whose
/// lowest point is `gap` above it, moving at `velocity`.
inline void addFloorAndSphere(World& world, std::uint32_t material, double radius, const Vec3& velocity,
                              double gap) {
  world.addPlane({"floor", Vec3::Zero(), Vec3::UnitZ(), material});
  ParticleSpec s;
  s.radius = radius;
  s.position = Vec3(0.0, 0.0, radius + gap);
  s.velocity = velocity;
  world.addParticle(s);
}

/// Two equal spheres on the x axis, `gap` apart, approaching head-on at relative
/// speed `speed` (each moving at speed/2), of materials `materialA` (at -x) and `materialB`.
inline void addHeadOnPair(World& world, double radius, double speed, double gap, std::uint32_t materialA = 0,
                          std::uint32_t materialB = 0) {
  ParticleSpec a;
  a.radius = radius;
  a.material = materialA;
  a.position = Vec3(-radius - 0.5 * gap, 0.0, 0.0);
  a.velocity = Vec3(0.5 * speed, 0.0, 0.0);
  ParticleSpec b = a;
  b.position = -a.position;
  b.velocity = -a.velocity;
  b.material = materialB;
  world.addParticle(a);
  world.addParticle(b);
}

/// Relative tolerance on a delivered coefficient of restitution in an engine
/// impact (the calibration itself is exact to 1e-6; the time step costs the rest).
inline constexpr double kRestitutionTolerance = 0.01;

/// Runs a head-on impact of two spheres of `radius` (addHeadOnPair, 2 um gap,
/// materials `materialA`, `materialB`) in `world`, whose materials are added,
/// until they are 4 um apart again. Returns the rebound-to-impact speed ratio,
/// or nullopt if they have not separated after maxSteps.
inline std::optional<double> headOnRebound(World& world, double radius, double speed, std::uint64_t maxSteps,
                                           std::uint32_t materialA = 0, std::uint32_t materialB = 0) {
  addHeadOnPair(world, radius, speed, 2e-6, materialA, materialB);
  world.initialize();
  const ParticleArrays& p = world.particles();
  const auto steps =
      stepUntil(world, [&] { return (p.position[1] - p.position[0]).norm() > 2.0 * radius + 4e-6; }, maxSteps);
  if (steps >= maxSteps) return std::nullopt;
  return std::abs(p.velocity[1].x() - p.velocity[0].x()) / speed;
}

/// A 0.03 m square box (frictionless side planes) with 294 spheres of radius
/// 1.6-2.0 mm on a loose lattice above the floor; the floor is added by the caller
/// (plane or mesh) with the returned grain material.
inline std::uint32_t addBoxedLattice(World& world) {
  const auto grains = world.addMaterial(testMaterial(0.3, 0.5));
  Material smooth = testMaterial(0.3, 0.0);
  smooth.name = "smooth_wall";
  const auto walls = world.addMaterial(smooth);
  constexpr double kBox = 0.03;
  world.addPlane({"x0", Vec3::Zero(), Vec3::UnitX(), walls});
  world.addPlane({"x1", Vec3::Constant(kBox), -Vec3::UnitX(), walls});
  world.addPlane({"y0", Vec3::Zero(), Vec3::UnitY(), walls});
  world.addPlane({"y1", Vec3::Constant(kBox), -Vec3::UnitY(), walls});
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (int layer = 0; layer < 6; ++layer) {
    for (int ix = 0; ix < 7; ++ix) {
      for (int iy = 0; iy < 7; ++iy) {
        ParticleSpec p;
        p.radius = 0.0018 + 0.0002 * u(rng);
        p.position = Vec3(0.0025 + ix * 0.0042, 0.0025 + iy * 0.0042, 0.003 + layer * 0.0045);
        world.addParticle(p);
      }
    }
  }
  return grains;
}

/// Particle pairs (by id, lower first) whose spheres overlap, as found through
/// the world's neighbour list.
inline std::set<std::pair<std::uint64_t, std::uint64_t>> listedContacts(const World& world) {
  std::set<std::pair<std::uint64_t, std::uint64_t>> contacts;
  const ParticleArrays& p = world.particles();
  const auto offsets = world.neighbourList().offsets();
  const auto partners = world.neighbourList().partners();
  for (std::size_t i = 0; i < p.size(); ++i) {
    for (std::uint32_t k = offsets[i]; k < offsets[i + 1]; ++k) {
      const std::uint32_t j = partners[k];
      if ((p.position[j] - p.position[i]).norm() < p.radius[i] + p.radius[j]) {
        contacts.emplace(std::min(p.id[i], p.id[j]), std::max(p.id[i], p.id[j]));
      }
    }
  }
  return contacts;
}

}  // namespace demlink::core::test
