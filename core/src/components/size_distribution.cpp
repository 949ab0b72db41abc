/// Radius distributions (definitions and moments in size_distribution.hpp).
///
/// Moments are written as finite sums over binomial terms in t = (r - r_min) / L,
/// L = r_max - r_min, so a narrow interval far from zero does not cancel
/// (E[r^k] = sum_j C(k, j) r_min^(k-j) L^j E[t^j]).
#include "demlink/core/components/size_distribution.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <numeric>

#include "demlink/core/base/input_error.hpp"

namespace demlink::core {
namespace {

double binomial(int n, int k) {
  double b = 1.0;
  for (int j = 1; j <= k; ++j) b = b * static_cast<double>(n - k + j) / static_cast<double>(j);
  return b;
}

double standardNormalPdf(double x) { return std::exp(-0.5 * x * x) / std::sqrt(2.0 * std::numbers::pi); }

/// E[Z^j] for j = 0..k of a standard normal truncated to [alpha, beta].
std::vector<double> truncatedStandardMoments(double alpha, double beta, int k) {
  const double z = standardNormalCdf(beta) - standardNormalCdf(alpha);
  const double pa = standardNormalPdf(alpha);
  const double pb = standardNormalPdf(beta);
  std::vector<double> m{1.0};
  for (int j = 1; j <= k; ++j) {
    const double previous = j >= 2 ? m[m.size() - 2] : 0.0;
    m.push_back((j - 1) * previous + (std::pow(alpha, j - 1) * pa - std::pow(beta, j - 1) * pb) / z);
  }
  return m;
}

void requireBounds(const std::string& prefix, double rMin, double rMax) {
  requirePositive(prefix + ".r_min", rMin);
  requireFinite(prefix + ".r_max", rMax);
  if (rMax < rMin) {
    throw InputError(prefix + ".r_max", formatValue(rMax), "must be >= r_min = " + formatValue(rMin));
  }
}

}  // namespace

double standardNormalCdf(double x) { return 0.5 * std::erfc(-x / std::numbers::sqrt2); }

SizeDistribution SizeDistribution::fixed(double radius) {
  SizeDistribution d;
  d.kind = Kind::Fixed;
  d.radius = radius;
  return d;
}

SizeDistribution SizeDistribution::uniform(double rMin, double rMax) {
  SizeDistribution d;
  d.kind = Kind::Uniform;
  d.r_min = rMin;
  d.r_max = rMax;
  return d;
}

SizeDistribution SizeDistribution::linear(double rMin, double rMax, double weightAtMin, double weightAtMax) {
  SizeDistribution d = uniform(rMin, rMax);
  d.kind = Kind::Linear;
  d.weight_at_min = weightAtMin;
  d.weight_at_max = weightAtMax;
  return d;
}

SizeDistribution SizeDistribution::normal(double mean, double std, double rMin, double rMax) {
  SizeDistribution d = uniform(rMin, rMax);
  d.kind = Kind::Normal;
  d.mean = mean;
  d.std = std;
  return d;
}

SizeDistribution SizeDistribution::discrete(std::vector<double> radii, std::vector<double> weights) {
  SizeDistribution d;
  d.kind = Kind::Discrete;
  d.radii = std::move(radii);
  d.weights = std::move(weights);
  return d;
}

void SizeDistribution::validate(const std::string& prefix) const {
  switch (kind) {
    case Kind::Fixed: requirePositive(prefix + ".radius", radius); return;
    case Kind::Uniform: requireBounds(prefix, r_min, r_max); return;
    case Kind::Linear: {
      requireBounds(prefix, r_min, r_max);
      requireNonNegative(prefix + ".weight_at_min", weight_at_min);
      requireNonNegative(prefix + ".weight_at_max", weight_at_max);
      if (weight_at_min + weight_at_max <= 0.0) {
        throw InputError(prefix + ".weight_at_max", formatValue(weight_at_max),
                         "weight_at_min and weight_at_max are both zero");
      }
      return;
    }
    case Kind::Normal: {
      requireBounds(prefix, r_min, r_max);
      if (!(r_max > r_min)) {
        throw InputError(prefix + ".r_max", formatValue(r_max),
                         "must exceed r_min = " + formatValue(r_min) + " for a truncated normal");
      }
      requireFinite(prefix + ".mean", mean);
      requirePositive(prefix + ".std", std);
      const double mass = standardNormalCdf((r_max - mean) / std) - standardNormalCdf((r_min - mean) / std);
      if (!(mass >= kMinNormalMass)) {
        throw InputError(prefix + ".mean", formatValue(mean),
                         "the interval [r_min, r_max] holds only " + formatValue(mass) +
                             " of the normal's probability (at least " + formatValue(kMinNormalMass) +
                             " needed); move the mean or widen std or the interval");
      }
      return;
    }
    case Kind::Discrete: {
      if (radii.empty()) throw InputError(prefix + ".radii", "[]", "at least one radius is required");
      if (weights.size() != radii.size()) {
        throw InputError(prefix + ".weights", std::to_string(weights.size()) + " values",
                         "needs one weight per radius (" + std::to_string(radii.size()) + ")");
      }
      double total = 0.0;
      for (std::size_t k = 0; k < radii.size(); ++k) {
        requirePositive(prefix + ".radii[" + std::to_string(k) + "]", radii[k]);
        requireNonNegative(prefix + ".weights[" + std::to_string(k) + "]", weights[k]);
        total += weights[k];
      }
      if (!(total > 0.0)) throw InputError(prefix + ".weights", "all zero", "at least one weight must be > 0");
      return;
    }
  }
  throw InputError(prefix, std::to_string(static_cast<int>(kind)), "unknown size distribution kind");
}

double SizeDistribution::sample(Random& rng) const {
  switch (kind) {
    case Kind::Fixed: return radius;
    case Kind::Uniform: return rng.uniform(r_min, r_max);
    case Kind::Linear: {
      // CDF in t: (w0 t + (w1 - w0) t^2 / 2) / ((w0 + w1) / 2) = u; the root in [0, 1]
      // written without cancellation: t = 2c / (w0 + sqrt(w0^2 (1 - u) + w1^2 u)).
      const double u = rng.uniform();
      const double w0 = weight_at_min;
      const double w1 = weight_at_max;
      const double c = u * 0.5 * (w0 + w1);
      const double denominator = w0 + std::sqrt(w0 * w0 * (1.0 - u) + w1 * w1 * u);
      const double t = denominator > 0.0 ? std::clamp(2.0 * c / denominator, 0.0, 1.0) : 0.0;
      return r_min + (r_max - r_min) * t;
    }
    case Kind::Normal: {
      // Acceptance >= kMinNormalMass (validated): the cap is never reached in practice.
      for (int attempt = 0; attempt < 1000000; ++attempt) {
        const double r = rng.normal(mean, std);
        if (r >= r_min && r <= r_max) return r;
      }
      return std::clamp(mean, r_min, r_max);
    }
    case Kind::Discrete: {
      const double total = std::accumulate(weights.begin(), weights.end(), 0.0);
      const double x = rng.uniform() * total;
      double cumulative = 0.0;
      std::size_t last = 0;
      for (std::size_t k = 0; k < radii.size(); ++k) {
        if (weights[k] <= 0.0) continue;
        cumulative += weights[k];
        last = k;
        if (x < cumulative) return radii[k];
      }
      return radii[last];
    }
  }
  return radius;
}

double SizeDistribution::minRadius() const {
  switch (kind) {
    case Kind::Fixed: return radius;
    case Kind::Discrete: {
      double r = 0.0;
      for (std::size_t k = 0; k < radii.size(); ++k) {
        if (weights[k] > 0.0) r = r > 0.0 ? std::min(r, radii[k]) : radii[k];
      }
      return r;
    }
    default: return r_min;
  }
}

double SizeDistribution::maxRadius() const {
  switch (kind) {
    case Kind::Fixed: return radius;
    case Kind::Discrete: {
      double r = 0.0;
      for (std::size_t k = 0; k < radii.size(); ++k) {
        if (weights[k] > 0.0) r = std::max(r, radii[k]);
      }
      return r;
    }
    default: return r_max;
  }
}

double SizeDistribution::moment(int k) const {
  const double length = r_max - r_min;
  switch (kind) {
    case Kind::Fixed: return std::pow(radius, k);
    case Kind::Uniform: {
      double sum = 0.0;
      for (int j = 0; j <= k; ++j) sum += binomial(k, j) * std::pow(r_min, k - j) * std::pow(length, j) / (j + 1);
      return sum;
    }
    case Kind::Linear: {
      // E[t^j] = 2 / (w0 + w1) (w0 / (j + 1) + (w1 - w0) / (j + 2)).
      const double w0 = weight_at_min;
      const double w1 = weight_at_max;
      double sum = 0.0;
      for (int j = 0; j <= k; ++j) {
        const double tj = 2.0 / (w0 + w1) * (w0 / (j + 1) + (w1 - w0) / (j + 2));
        sum += binomial(k, j) * std::pow(r_min, k - j) * std::pow(length, j) * tj;
      }
      return sum;
    }
    case Kind::Normal: {
      const std::vector<double> m = truncatedStandardMoments((r_min - mean) / std, (r_max - mean) / std, k);
      double sum = 0.0;
      for (int j = 0; j <= k; ++j) {
        sum += binomial(k, j) * std::pow(mean, k - j) * std::pow(std, j) * m[static_cast<std::size_t>(j)];
      }
      return sum;
    }
    case Kind::Discrete: {
      double total = 0.0;
      double sum = 0.0;
      for (std::size_t n = 0; n < radii.size(); ++n) {
        total += weights[n];
        sum += weights[n] * std::pow(radii[n], k);
      }
      return sum / total;
    }
  }
  return 0.0;
}

double SizeDistribution::radiusVariance() const {
  const double m1 = moment(1);
  return std::max(0.0, moment(2) - m1 * m1);
}

double SizeDistribution::meanVolume() const { return 4.0 / 3.0 * std::numbers::pi * moment(3); }

}  // namespace demlink::core
