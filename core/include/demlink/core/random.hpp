#pragma once
/// A small fixed-algorithm random generator (SplitMix64) and the transforms the
/// engine needs. std:: distributions are implementation-defined, so scenes would
/// not reproduce across standard libraries; these transforms are our own.
#include <cmath>
#include <cstdint>
#include <numbers>

#include "demlink/core/math_types.hpp"

namespace demlink::core {

/// SplitMix64 (Steele, Lea, Flood 2014): 64-bit state, full period, fast.
class SplitMix64 {
 public:
  explicit SplitMix64(std::uint64_t seed) : state_(seed) {}
  std::uint64_t next() {
    std::uint64_t z = (state_ += 0x9e3779b97f4a7c15ULL);
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
    return z ^ (z >> 31);
  }
  /// Uniform in [0, 1) from the top 53 bits.
  double unit() { return static_cast<double>(next() >> 11) * 0x1.0p-53; }

 private:
  std::uint64_t state_;
};

/// A uniformly distributed rotation (Shoemake's subgroup algorithm).
inline Quat uniformRotation(SplitMix64& rng) {
  const double u1 = rng.unit();
  const double a = 2.0 * std::numbers::pi * rng.unit();
  const double b = 2.0 * std::numbers::pi * rng.unit();
  const double s1 = std::sqrt(1.0 - u1);
  const double s2 = std::sqrt(u1);
  return Quat(s2 * std::cos(b), s1 * std::sin(a), s1 * std::cos(a), s2 * std::sin(b));
}

}  // namespace demlink::core
