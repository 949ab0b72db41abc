/// Lattice generation (see particle_lattice.hpp for the determinism contract).
///
/// Overlap rule: two neighbouring lattice points are `spacing` apart and each
/// coordinate moves by at most `jitter`, so centres stay at least
/// spacing - 2 jitter apart; with radii <= radius_max no two spheres touch when
///   spacing > 2 (radius_max + jitter).
#include "demlink/server/scene/particle_lattice.hpp"

#include <random>

#include "demlink/core/base/input_error.hpp"

namespace demlink::server {
namespace {

/// Uniform in [0, 1) from the top 53 bits: exactly representable doubles, the
/// same on every platform.
double unitUniform(std::mt19937_64& rng) {
  return static_cast<double>(rng() >> 11) * 0x1.0p-53;
}

double uniform(std::mt19937_64& rng, double lo, double hi) {
  return lo + (hi - lo) * unitUniform(rng);
}

}  // namespace

std::string LatticeSpec::countText() const {
  return std::to_string(counts[0]) + " x " + std::to_string(counts[1]) + " x " + std::to_string(counts[2]);
}

void LatticeSpec::validate(const std::string& fieldPrefix) const {
  core::requirePositive(fieldPrefix + ".radius", radius);
  if (radius_max) {
    core::requireFinite(fieldPrefix + ".radius_max", *radius_max);
    if (*radius_max < radius) {
      throw core::InputError(fieldPrefix + ".radius_max", core::formatValue(*radius_max),
                             "must be >= radius = " + core::formatValue(radius));
    }
  }
  for (int k = 0; k < 3; ++k) {
    core::requireFinite(fieldPrefix + ".origin[" + std::to_string(k) + "]", origin[k]);
    core::requireFinite(fieldPrefix + ".velocity[" + std::to_string(k) + "]", velocity[k]);
  }
  core::requireNonNegative(fieldPrefix + ".jitter", jitter);
  core::requirePositive(fieldPrefix + ".spacing", spacing);
  const double largest = radius_max.value_or(radius);
  if (!(spacing > 2.0 * (largest + jitter))) {
    throw core::InputError(fieldPrefix + ".spacing", core::formatValue(spacing),
                           "must exceed 2 (radius_max + jitter) = " + core::formatValue(2.0 * (largest + jitter)) +
                               " m, or neighbouring spheres could overlap");
  }
  static constexpr const char* kAxis[3] = {"nx", "ny", "nz"};
  double total = 1.0;
  for (int k = 0; k < 3; ++k) {
    if (counts[k] == 0) throw core::InputError(fieldPrefix + ".counts." + kAxis[k], "0", "must be >= 1");
    total *= counts[k];
  }
  if (total > static_cast<double>(kMaxLatticeParticles)) {
    throw core::InputError(fieldPrefix + ".counts", countText(),
                           "more than " + std::to_string(kMaxLatticeParticles) + " spheres in one lattice");
  }
}

std::vector<core::ParticleSpec> generateLattice(const LatticeSpec& spec) {
  std::mt19937_64 rng(spec.seed);
  std::vector<core::ParticleSpec> spheres;
  spheres.reserve(spec.count());
  for (std::uint32_t iz = 0; iz < spec.counts[2]; ++iz) {
    for (std::uint32_t iy = 0; iy < spec.counts[1]; ++iy) {
      for (std::uint32_t ix = 0; ix < spec.counts[0]; ++ix) {
        core::ParticleSpec sphere;
        sphere.radius = spec.radius_max ? uniform(rng, spec.radius, *spec.radius_max) : spec.radius;
        const core::Vec3 index(static_cast<double>(ix), static_cast<double>(iy), static_cast<double>(iz));
        sphere.position = spec.origin + spec.spacing * index;
        if (spec.jitter > 0.0) {
          for (int k = 0; k < 3; ++k) sphere.position[k] += uniform(rng, -spec.jitter, spec.jitter);
        }
        sphere.velocity = spec.velocity;
        sphere.material = spec.material;
        spheres.push_back(sphere);
      }
    }
  }
  return spheres;
}

}  // namespace demlink::server
