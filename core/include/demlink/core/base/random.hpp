#pragma once
/// A small deterministic random number generator for scene generation (sources,
/// pits, lattices): xoshiro256** seeded through splitmix64, with our own
/// transforms to uniform and normal variates.
///
/// Why not <random>: std::mt19937_64's raw sequence is specified, but every
/// std:: distribution (uniform_real_distribution, normal_distribution) is
/// implementation-defined, so the same seed gives different scenes with
/// libstdc++, libc++ and MSVC. Here every transform is plain IEEE arithmetic:
///   - uniform(): the top 53 bits of a 64-bit output times 2^-53, exact;
///   - normal(): Marsaglia's polar method (no trigonometry), with a natural
///     logarithm computed by our own series (logPortable) instead of std::log,
///     whose last bit may differ between C libraries. std::sqrt is correctly
///     rounded by IEEE 754, so it is used as is.
/// The output stream is therefore bit-identical on every conforming platform
/// (as long as the compiler does not fuse multiply-adds, which the x86-64
/// baseline cannot).
///
/// Algorithms: splitmix64 (Steele, Lea, Flood 2014) and xoshiro256** (Blackman,
/// Vigna 2018), both public-domain reference algorithms, written out here.
#include <bit>
#include <cmath>
#include <cstdint>
#include <numbers>

#include "demlink/core/base/math_types.hpp"

namespace demlink::core {

/// Natural logarithm of x > 0 using only IEEE-exact operations (frexp, +, *, /):
/// x = m 2^e with m in [sqrt(1/2), sqrt(2)), ln x = e ln2 + 2 atanh(s),
/// s = (m - 1) / (m + 1), |s| < 0.1716, atanh by its odd series to s^27
/// (truncation error < 1e-20 relative). Accurate to a few ulp; same bits everywhere.
[[nodiscard]] inline double logPortable(double x) {
  int exponent = 0;
  double m = std::frexp(x, &exponent);  // m in [0.5, 1)
  if (m < 0.70710678118654752440) {
    m *= 2.0;
    --exponent;
  }
  const double s = (m - 1.0) / (m + 1.0);
  const double s2 = s * s;
  double series = 0.0;
  for (int k = 27; k >= 3; k -= 2) series = (series + 1.0 / k) * s2;
  const double atanhTimes2 = 2.0 * s * (1.0 + series);
  // ln 2 split in a high part with trailing zero bits (exact product with e) and a low part.
  constexpr double kLn2Hi = 6.93147180369123816490e-01;
  constexpr double kLn2Lo = 1.90821492927058770002e-10;
  const double e = static_cast<double>(exponent);
  return e * kLn2Hi + (atanhTimes2 + e * kLn2Lo);
}

/// Everything a Random's future output depends on, for checkpoints.
struct RandomState {
  std::uint64_t words[4] = {};  ///< xoshiro256** state; never all zero
  double spare = 0.0;           ///< second normal variate of the last pair
  bool has_spare = false;
};

/// xoshiro256** with splitmix64 seeding. Copyable: a copy continues the same stream.
class Random {
 public:
  /// Any seed (including 0) gives a valid, distinct state.
  explicit Random(std::uint64_t seed) {
    std::uint64_t x = seed;
    for (std::uint64_t& word : state_) word = splitMix64(x);
  }

  /// Next raw 64-bit output.
  std::uint64_t next() {
    const std::uint64_t result = std::rotl(state_[1] * 5u, 7) * 9u;
    const std::uint64_t t = state_[1] << 17;
    state_[2] ^= state_[0];
    state_[3] ^= state_[1];
    state_[1] ^= state_[2];
    state_[0] ^= state_[3];
    state_[2] ^= t;
    state_[3] = std::rotl(state_[3], 45);
    return result;
  }

  /// Uniform in [0, 1): a multiple of 2^-53.
  double uniform() { return static_cast<double>(next() >> 11) * 0x1.0p-53; }

  /// Uniform in [lo, hi) (hi itself for lo == hi).
  double uniform(double lo, double hi) { return lo + (hi - lo) * uniform(); }

  /// Uniform integer in [0, n) for n >= 1 (rejection, no modulo bias).
  std::uint64_t below(std::uint64_t n) {
    const std::uint64_t limit = (0 - n) % n;  // 2^64 mod n
    for (;;) {
      const std::uint64_t r = next();
      if (r >= limit) return r % n;
    }
  }

  /// Standard normal variate (mean 0, variance 1), Marsaglia's polar method;
  /// pairs are produced together and the second is returned by the next call.
  double normal() {
    if (has_spare_) {
      has_spare_ = false;
      return spare_;
    }
    for (;;) {
      const double u = 2.0 * uniform() - 1.0;
      const double v = 2.0 * uniform() - 1.0;
      const double s = u * u + v * v;
      if (s >= 1.0 || s == 0.0) continue;
      const double factor = std::sqrt(-2.0 * logPortable(s) / s);
      spare_ = v * factor;
      has_spare_ = true;
      return u * factor;
    }
  }

  /// Normal variate with the given mean and standard deviation.
  double normal(double mean, double stddev) { return mean + stddev * normal(); }

  /// The full generator state (a generator set to it continues the same stream).
  [[nodiscard]] RandomState state() const {
    RandomState s;
    for (int k = 0; k < 4; ++k) s.words[k] = state_[k];
    s.spare = spare_;
    s.has_spare = has_spare_;
    return s;
  }
  /// Restores a state from state(). An all-zero word set is not a xoshiro state
  /// (the generator would output zeros forever); the caller must reject it.
  void setState(const RandomState& s) {
    for (int k = 0; k < 4; ++k) state_[k] = s.words[k];
    spare_ = s.spare;
    has_spare_ = s.has_spare;
  }

 private:
  static std::uint64_t splitMix64(std::uint64_t& x) {
    x += 0x9E3779B97F4A7C15ull;
    std::uint64_t z = x;
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    return z ^ (z >> 31);
  }

  std::uint64_t state_[4] = {};
  double spare_ = 0.0;
  bool has_spare_ = false;
};

/// A uniformly distributed rotation (Shoemake's subgroup algorithm). Uses std::sin
/// and std::cos, so the last bit may differ between C libraries.
inline Quat uniformRotation(Random& rng) {
  const double u1 = rng.uniform();
  const double a = 2.0 * std::numbers::pi * rng.uniform();
  const double b = 2.0 * std::numbers::pi * rng.uniform();
  const double s1 = std::sqrt(1.0 - u1);
  const double s2 = std::sqrt(u1);
  return Quat(s2 * std::cos(b), s1 * std::sin(a), s1 * std::cos(a), s2 * std::sin(b));
}

}  // namespace demlink::core
