#include "demlink/core/particles/particle_arrays.hpp"

#include <numbers>

namespace demlink::core {
namespace {

template <class T>
void permuteColumn(std::vector<T>& column, std::span<const std::uint32_t> oldSlotOfNew) {
  std::vector<T> reordered(oldSlotOfNew.size());
  for (std::size_t k = 0; k < oldSlotOfNew.size(); ++k) reordered[k] = column[oldSlotOfNew[k]];
  column.swap(reordered);
}

}  // namespace

void ParticleArrays::append(const ParticleSpec& spec, double density, std::uint64_t stableId) {
  // Sphere mass is 4/3 pi R^3 rho (the solver paper's table 3 prints 3/4, a typo).
  const double m = 4.0 / 3.0 * std::numbers::pi * spec.radius * spec.radius * spec.radius * density;
  position.push_back(spec.position);
  velocity.push_back(spec.velocity);
  angular_velocity.push_back(spec.angular_velocity);
  force.push_back(Vec3::Zero());
  torque.push_back(Vec3::Zero());
  radius.push_back(spec.radius);
  mass.push_back(m);
  inv_mass.push_back(1.0 / m);
  inv_inertia.push_back(1.0 / (0.4 * m * spec.radius * spec.radius));
  material.push_back(spec.material);
  id.push_back(stableId);
  clump_id.push_back(0);
}

void ParticleArrays::permute(std::span<const std::uint32_t> oldSlotOfNew) {
  forEachColumn([&](const char* /*name*/, auto& column) { permuteColumn(column, oldSlotOfNew); });
}

void ParticleArrays::reserve(std::size_t n) {
  forEachColumn([&](const char* /*name*/, auto& column) { column.reserve(n); });
}

}  // namespace demlink::core
