#include "demlink/core/integrator.hpp"

namespace demlink::core {

void kick(ParticleArrays& p, const Vec3& gravity, double h) {
  const std::size_t n = p.size();
  for (std::size_t i = 0; i < n; ++i) {
    p.velocity[i] += (p.force[i] * p.inv_mass[i] + gravity) * h;
    p.angular_velocity[i] += p.torque[i] * (p.inv_inertia[i] * h);
  }
}

void drift(ParticleArrays& p, double dt) {
  const std::size_t n = p.size();
  for (std::size_t i = 0; i < n; ++i) p.position[i] += p.velocity[i] * dt;
}

void explicitEulerStep(ParticleArrays& p, const Vec3& gravity, double dt) {
  drift(p, dt);
  kick(p, gravity, dt);
}

}  // namespace demlink::core
