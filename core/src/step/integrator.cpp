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

/// Zeroes force and torque of slot i when `kClear` (ForcesAfterKick::kCleared).
template <bool kClear>
inline void afterKick(ParticleArrays& p, std::size_t i) {
  if constexpr (kClear) {
    p.force[i].setZero();
    p.torque[i].setZero();
  }
}

template <bool kClear>
void kickAndDriftPass(ParticleArrays& p, const Vec3& gravity, double h, double dt, ThreadPool* pool) {
  parallelChunks(pool, p.size(), [&](std::size_t begin, std::size_t end) {
    for (std::size_t i = begin; i < end; ++i) {
      p.velocity[i] += (p.force[i] * p.inv_mass[i] + gravity) * h;
      p.angular_velocity[i] += p.torque[i] * (p.inv_inertia[i] * h);
      afterKick<kClear>(p, i);
      p.position[i] += p.velocity[i] * dt;
    }
  });
}

template <bool kClear>
void kickTwiceAndDriftPass(ParticleArrays& p, const Vec3& gravity, double h, double dt, ThreadPool* pool) {
  parallelChunks(pool, p.size(), [&](std::size_t begin, std::size_t end) {
    for (std::size_t i = begin; i < end; ++i) {
      // Written as kick() and kickAndDrift() write it, twice: the same expression, the same rounding.
      p.velocity[i] += (p.force[i] * p.inv_mass[i] + gravity) * h;
      p.angular_velocity[i] += p.torque[i] * (p.inv_inertia[i] * h);
      p.velocity[i] += (p.force[i] * p.inv_mass[i] + gravity) * h;
      p.angular_velocity[i] += p.torque[i] * (p.inv_inertia[i] * h);
      afterKick<kClear>(p, i);
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
  withForcesAfter(after, [&]<bool kClear>() { kickAndDriftPass<kClear>(p, gravity, h, dt, pool); });
}

void kickTwiceAndDrift(ParticleArrays& p, const Vec3& gravity, double h, double dt, ThreadPool* pool,
                       ForcesAfterKick after) {
  withForcesAfter(after, [&]<bool kClear>() { kickTwiceAndDriftPass<kClear>(p, gravity, h, dt, pool); });
}

void explicitEulerStep(ParticleArrays& p, const Vec3& gravity, double dt, ThreadPool* pool) {
  drift(p, dt, pool);
  kick(p, gravity, dt, pool);
}

}  // namespace demlink::core
