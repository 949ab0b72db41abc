#pragma once
/// Spheres on a regular cubic lattice, with optional radius spread and jitter.
///
/// Determinism: the generator is std::mt19937_64 (whose output sequence the C++
/// standard fixes) and the mapping to [0, 1) is our own (the top 53 bits times
/// 2^-53), not std::uniform_real_distribution, whose algorithm differs between
/// standard libraries. So a seed gives bit-identical spheres everywhere. Draws per
/// sphere, in lattice order (x fastest, then y, then z): the radius (only when
/// radius_max is set), then the x, y and z jitter (only when jitter > 0).
#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "demlink/core/base/math_types.hpp"
#include "demlink/core/particles/particle_arrays.hpp"

namespace demlink::server {

/// Largest number of spheres one lattice may declare (a guard against typos
/// that would exhaust memory).
inline constexpr std::uint64_t kMaxLatticeParticles = 20'000'000;

struct LatticeSpec {
  double radius = 0.0;                                  ///< [m]
  std::optional<double> radius_max;                     ///< [m]; set: radii uniform in [radius, radius_max]
  core::Vec3 origin = core::Vec3::Zero();               ///< centre of sphere (0, 0, 0) [m]
  double spacing = 0.0;                                 ///< lattice constant [m]
  std::array<std::uint32_t, 3> counts{0, 0, 0};         ///< spheres along x, y, z [-]
  double jitter = 0.0;                                  ///< max offset per coordinate [m]
  std::uint64_t seed = 0;                               ///< random seed [-]
  core::Vec3 velocity = core::Vec3::Zero();             ///< initial velocity [m/s]
  std::uint32_t material = 0;                           ///< material index

  /// Throws core::InputError naming `fieldPrefix + ".<field>"`; also refuses a
  /// spacing that would let neighbouring spheres overlap
  /// (spacing <= 2 (radius_max + jitter)) and more than kMaxLatticeParticles.
  void validate(const std::string& fieldPrefix) const;

  /// "nx x ny x nz", the counts as errors show them.
  [[nodiscard]] std::string countText() const;

  /// Number of spheres (may wrap around for counts that fail validate()).
  [[nodiscard]] std::uint64_t count() const {
    return std::uint64_t{counts[0]} * counts[1] * counts[2];
  }
};

/// The spheres of a validated lattice, in lattice order.
[[nodiscard]] std::vector<core::ParticleSpec> generateLattice(const LatticeSpec& spec);

}  // namespace demlink::server
