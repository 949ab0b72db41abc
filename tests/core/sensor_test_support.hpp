#pragma once
/// Helpers for the sink, sensor and tracker tests: a fixed-algorithm random generator
/// (splitmix64, so sets are identical with every standard library) and a world with
/// one material and no gravity.
#include <cstdint>

#include "test_scenes.hpp"

namespace demlink::core::test {

/// splitmix64 with a uniform double in [lo, hi) from the top 53 bits.
class SplitMix {
 public:
  explicit SplitMix(std::uint64_t seed) : state_(seed) {}
  std::uint64_t next() {
    std::uint64_t z = (state_ += 0x9E3779B97F4A7C15ull);
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    return z ^ (z >> 31);
  }
  double uniform(double lo, double hi) {
    return lo + (hi - lo) * static_cast<double>(next() >> 11) * 0x1.0p-53;
  }
  Vec3 vector(double lo, double hi) { return {uniform(lo, hi), uniform(lo, hi), uniform(lo, hi)}; }

 private:
  std::uint64_t state_;
};

/// Time step 1e-5 s, gravity as given (default none).
inline SimulationSettings sensorSettings(const Vec3& gravity = Vec3::Zero()) {
  SimulationSettings s;
  s.time_step = 1.0e-5;
  s.gravity = gravity;
  s.max_impact_velocity = 3.0;
  // These scenes test bookkeeping, not restitution: a loose restitution tolerance keeps
  // the step they were written for inside the limit (docs/physics.md "Critical time step").
  s.restitution_tolerance = 0.2;
  return s;
}

inline std::uint64_t addSphere(World& world, const Vec3& position, double radius, const Vec3& velocity = Vec3::Zero()) {
  ParticleSpec p;
  p.position = position;
  p.radius = radius;
  p.velocity = velocity;
  return world.addParticle(p);
}

/// Slot of the particle with stable id `id`, or size() if absent.
inline std::size_t slotOf(const World& world, std::uint64_t id) {
  const auto& ids = world.particles().id;
  std::size_t k = 0;
  while (k < ids.size() && ids[k] != id) ++k;
  return k;
}

}  // namespace demlink::core::test
