#include "demlink/core/step/integrator.hpp"

#include "demlink/core/step/parallel.hpp"

namespace demlink::core {

void kick(ParticleArrays& p, const Vec3& gravity, double h, ThreadPool* pool) {
  parallelChunks(pool, p.size(), [&](std::size_t begin, std::size_t end) {
    for (std::size_t i = begin; i < end; ++i) {
      p.velocity[i] += (p.force[i] * p.inv_mass[i] + gravity) * h;
      p.angular_velocity[i] += p.torque[i] * (p.inv_inertia[i] * h);
    }
  });
}

void drift(ParticleArrays& p, double dt, ThreadPool* pool) {
  parallelChunks(pool, p.size(), [&](std::size_t begin, std::size_t end) {
    for (std::size_t i = begin; i < end; ++i) p.position[i] += p.velocity[i] * dt;
  });
}

namespace {

/// kick(h) kKicks times, then drift(dt), in one pass; with kClear, force and torque are
/// zeroed after their last read (ForcesAfterKick::kCleared).
template <int kKicks, bool kClear>
void kicksAndDrift(ParticleArrays& p, const Vec3& gravity, double h, double dt, ThreadPool* pool) {
  parallelChunks(pool, p.size(), [&](std::size_t begin, std::size_t end) {
    for (std::size_t i = begin; i < end; ++i) {
      // Each kick written as kick() writes it: the same expression, the same rounding.
      for (int k = 0; k < kKicks; ++k) {
        p.velocity[i] += (p.force[i] * p.inv_mass[i] + gravity) * h;
        p.angular_velocity[i] += p.torque[i] * (p.inv_inertia[i] * h);
      }
      if constexpr (kClear) {
        p.force[i].setZero();
        p.torque[i].setZero();
      }
      p.position[i] += p.velocity[i] * dt;
    }
  });
}

/// Runs pass.operator()<kClear>() with kClear = (after == ForcesAfterKick::kCleared): each
/// kick pass compiled with and without the clearing, no test per particle.
template <class Pass>
void withForcesAfter(ForcesAfterKick after, const Pass& pass) {
  if (after == ForcesAfterKick::kCleared) {
    pass.template operator()<true>();
  } else {
    pass.template operator()<false>();
  }
}

}  // namespace

void kickAndDrift(ParticleArrays& p, const Vec3& gravity, double h, double dt, ThreadPool* pool,
                  ForcesAfterKick after) {
  withForcesAfter(after, [&]<bool kClear>() { kicksAndDrift<1, kClear>(p, gravity, h, dt, pool); });
}

void kickTwiceAndDrift(ParticleArrays& p, const Vec3& gravity, double h, double dt, ThreadPool* pool,
                       ForcesAfterKick after) {
  withForcesAfter(after, [&]<bool kClear>() { kicksAndDrift<2, kClear>(p, gravity, h, dt, pool); });
}

void explicitEulerStep(ParticleArrays& p, const Vec3& gravity, double dt, ThreadPool* pool) {
  drift(p, dt, pool);
  kick(p, gravity, dt, pool);
}

}  // namespace demlink::core
