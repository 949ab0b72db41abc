#pragma once
/// Particle radius distributions for sources and pit generators.
///
/// Why a closed set of kinds with exact moments: a source given in kg/s needs the
/// mean particle mass, and a pit generator needs the mean volume to know how much
/// material to rain; both are E[r^3] of the distribution, which every kind here has
/// in closed form (no sampling estimate, so the rate conversion is exact and
/// identical on every run).
///
/// Kinds (all radii in m):
///   Fixed     r = radius.
///   Uniform   r uniform in [r_min, r_max].
///   Linear    pdf varying linearly from weight_at_min at r_min to weight_at_max at
///             r_max: f(r) proportional to w_min + (w_max - w_min) t, t = (r - r_min)/(r_max - r_min).
///             This is our reading of the solver paper's "Linear Distribution"
///             (Table 5, radius in [0.15, 0.24] m); w_min = w_max is the uniform
///             case. Sampled by exact inversion of the quadratic CDF.
///   Normal    normal(mean, std) truncated to [r_min, r_max], sampled by rejection
///             from the untruncated normal; the interval must hold at least
///             kMinNormalMass of the untruncated probability.
///   Discrete  one of `radii` with probability proportional to `weights`.
#include <cstdint>
#include <string>
#include <vector>

#include "demlink/core/base/random.hpp"

namespace demlink::core {

/// Smallest probability mass of the untruncated normal inside [r_min, r_max].
inline constexpr double kMinNormalMass = 0.01;

struct SizeDistribution {
  enum class Kind : std::uint8_t { Fixed, Uniform, Linear, Normal, Discrete };

  Kind kind = Kind::Fixed;
  double radius = 0.0;          ///< Fixed [m]
  double r_min = 0.0;           ///< Uniform, Linear, Normal: lower bound [m]
  double r_max = 0.0;           ///< Uniform, Linear, Normal: upper bound [m]
  double weight_at_min = 1.0;   ///< Linear: relative pdf at r_min [-], >= 0
  double weight_at_max = 1.0;   ///< Linear: relative pdf at r_max [-], >= 0
  double mean = 0.0;            ///< Normal: mean of the untruncated normal [m]
  double std = 0.0;             ///< Normal: standard deviation of the untruncated normal [m]
  std::vector<double> radii;    ///< Discrete [m]
  std::vector<double> weights;  ///< Discrete: relative probabilities [-]

  [[nodiscard]] static SizeDistribution fixed(double radius);
  [[nodiscard]] static SizeDistribution uniform(double rMin, double rMax);
  [[nodiscard]] static SizeDistribution linear(double rMin, double rMax, double weightAtMin, double weightAtMax);
  [[nodiscard]] static SizeDistribution normal(double mean, double std, double rMin, double rMax);
  [[nodiscard]] static SizeDistribution discrete(std::vector<double> radii, std::vector<double> weights);

  /// Throws InputError naming `fieldPrefix + ".<field>"` (e.g. "....sizes.r_max").
  void validate(const std::string& fieldPrefix) const;

  /// One radius [m]. Requires a valid distribution.
  [[nodiscard]] double sample(Random& rng) const;
  /// Smallest and largest radius that can be drawn [m].
  [[nodiscard]] double minRadius() const;
  [[nodiscard]] double maxRadius() const;
  /// Raw moment E[r^k] [m^k], exact (closed form), k >= 0.
  [[nodiscard]] double moment(int k) const;
  [[nodiscard]] double meanRadius() const { return moment(1); }
  /// Var[r] [m^2].
  [[nodiscard]] double radiusVariance() const;
  /// Mean sphere volume 4/3 pi E[r^3] [m^3].
  [[nodiscard]] double meanVolume() const;
  /// Mean sphere mass [kg] for a density [kg/m^3].
  [[nodiscard]] double meanMass(double density) const { return density * meanVolume(); }
};

/// Standard normal cumulative distribution function (via std::erfc).
[[nodiscard]] double standardNormalCdf(double x);

}  // namespace demlink::core
