/// Random generator and radius distributions: sample moments against the exact
/// moments, truncation bounds, the linear pdf's shape, validation field names.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <vector>

#include "demlink/core/base/input_error.hpp"
#include "demlink/core/base/random.hpp"
#include "demlink/core/components/size_distribution.hpp"

namespace demlink::core {
namespace {

constexpr int kSamples = 200000;

TEST(Random, PortableLogMatchesStdLog) {
  Random rng(7);
  for (int n = 0; n < 20000; ++n) {
    const double x = std::ldexp(rng.uniform() + 1.0e-300, static_cast<int>(rng.below(200)) - 100);
    EXPECT_NEAR(logPortable(x), std::log(x), 4.0e-16 * std::max(1.0, std::abs(std::log(x)))) << x;
  }
  EXPECT_EQ(logPortable(1.0), 0.0);
}

TEST(Random, SameSeedSameStreamOtherSeedOtherStream) {
  Random a(123);
  Random b(123);
  Random c(124);
  int differ = 0;
  for (int n = 0; n < 1000; ++n) {
    const std::uint64_t x = a.next();
    EXPECT_EQ(x, b.next());
    differ += x != c.next() ? 1 : 0;
  }
  EXPECT_EQ(differ, 1000);
}

TEST(Random, UniformAndNormalMoments) {
  Random rng(2024);
  double su = 0.0, suu = 0.0, sn = 0.0, snn = 0.0;
  for (int n = 0; n < kSamples; ++n) {
    const double u = rng.uniform();
    ASSERT_GE(u, 0.0);
    ASSERT_LT(u, 1.0);
    su += u;
    suu += u * u;
    const double z = rng.normal();
    sn += z;
    snn += z * z;
  }
  const double count = kSamples;
  // Standard errors: uniform mean sqrt(1/12/N), variance ~ sqrt((1/80 - 1/144)/N);
  // normal mean sqrt(1/N), variance sqrt(2/N). Tolerance 5 standard errors.
  const double mu = su / count;
  EXPECT_NEAR(mu, 0.5, 5.0 * std::sqrt(1.0 / 12.0 / count));
  EXPECT_NEAR(suu / count - mu * mu, 1.0 / 12.0, 5.0 * std::sqrt((1.0 / 80.0 - 1.0 / 144.0) / count));
  const double mz = sn / count;
  EXPECT_NEAR(mz, 0.0, 5.0 / std::sqrt(count));
  EXPECT_NEAR(snn / count - mz * mz, 1.0, 5.0 * std::sqrt(2.0 / count));
}

/// Draws kSamples radii and compares mean, variance and E[r^3] with the exact
/// moments within 5 standard errors (themselves from the exact 4th and 6th moments).
void expectMomentsMatch(const SizeDistribution& d, std::uint64_t seed) {
  d.validate("sizes");
  Random rng(seed);
  double s1 = 0.0, s2 = 0.0, s3 = 0.0;
  double lo = 1.0e300, hi = -1.0e300;
  for (int n = 0; n < kSamples; ++n) {
    const double r = d.sample(rng);
    s1 += r;
    s2 += r * r;
    s3 += r * r * r;
    lo = std::min(lo, r);
    hi = std::max(hi, r);
  }
  const double count = kSamples;
  const double m1 = d.moment(1), m2 = d.moment(2), m3 = d.moment(3), m4 = d.moment(4), m6 = d.moment(6);
  const double var = d.radiusVariance();
  const double central4 = m4 - 4.0 * m1 * m3 + 6.0 * m1 * m1 * m2 - 3.0 * m1 * m1 * m1 * m1;
  const double mean = s1 / count;
  EXPECT_NEAR(mean, m1, 5.0 * std::sqrt(var / count) + 1e-10 * m1);
  EXPECT_NEAR(s2 / count - mean * mean, var, 5.0 * std::sqrt(std::max(0.0, central4 - var * var) / count) + 1e-10 * m2);
  EXPECT_NEAR(s3 / count, m3, 5.0 * std::sqrt(std::max(0.0, m6 - m3 * m3) / count) + 1e-10 * m3);
  EXPECT_GE(lo, d.minRadius());
  EXPECT_LE(hi, d.maxRadius());
  EXPECT_NEAR(d.meanVolume(), 4.0 / 3.0 * std::numbers::pi * m3, 1e-15);
}

TEST(SizeDistribution, FixedUniformDiscreteMoments) {
  expectMomentsMatch(SizeDistribution::fixed(0.2), 1);
  const SizeDistribution u = SizeDistribution::uniform(0.15, 0.24);
  EXPECT_NEAR(u.meanRadius(), 0.195, 1e-15);
  EXPECT_NEAR(u.radiusVariance(), 0.09 * 0.09 / 12.0, 1e-15);
  expectMomentsMatch(u, 2);
  const SizeDistribution d = SizeDistribution::discrete({0.1, 0.2, 0.3}, {1.0, 0.0, 3.0});
  EXPECT_NEAR(d.meanRadius(), 0.25, 1e-15);
  EXPECT_EQ(d.minRadius(), 0.1);
  expectMomentsMatch(d, 3);
}

TEST(SizeDistribution, LinearMomentsAndShape) {
  // Increasing, decreasing to zero weight, and the paper's interval.
  for (const auto& [w0, w1] : std::vector<std::pair<double, double>>{{1.0, 3.0}, {2.0, 0.0}, {1.0, 1.0}}) {
    const SizeDistribution d = SizeDistribution::linear(0.15, 0.24, w0, w1);
    // Exact mean of the linear pdf, written independently: E[t] = (w0 + 2 w1) / (3 (w0 + w1)).
    EXPECT_NEAR(d.meanRadius(), 0.15 + 0.09 * (w0 + 2.0 * w1) / (3.0 * (w0 + w1)), 1e-15);
    expectMomentsMatch(d, 4);
    // Fraction below the midpoint: F(1/2) = (3 w0 + w1) / (4 (w0 + w1)).
    Random rng(5);
    int below = 0;
    for (int n = 0; n < kSamples; ++n) below += d.sample(rng) < 0.195 ? 1 : 0;
    const double p = (3.0 * w0 + w1) / (4.0 * (w0 + w1));
    EXPECT_NEAR(below / static_cast<double>(kSamples), p, 5.0 * std::sqrt(p * (1.0 - p) / kSamples) + 1e-12);
  }
}

TEST(SizeDistribution, TruncatedNormalMomentsAgreeWithQuadratureAndSamples) {
  for (const SizeDistribution& d : {SizeDistribution::normal(0.2, 0.03, 0.15, 0.24),
                                    SizeDistribution::normal(0.1, 0.05, 0.15, 0.24)}) {
    // Simpson quadrature of r^k exp(-(r - mu)^2 / (2 s^2)) over [r_min, r_max].
    const int n = 2000;
    const double h = (d.r_max - d.r_min) / n;
    double z = 0.0, first = 0.0, third = 0.0;
    for (int k = 0; k <= n; ++k) {
      const double r = d.r_min + k * h;
      const double w = (k == 0 || k == n ? 1.0 : (k % 2 == 1 ? 4.0 : 2.0)) * std::exp(-0.5 * std::pow((r - d.mean) / d.std, 2));
      z += w;
      first += w * r;
      third += w * r * r * r;
    }
    EXPECT_NEAR(d.moment(1), first / z, 1e-12);
    EXPECT_NEAR(d.moment(3), third / z, 1e-12);
    expectMomentsMatch(d, 6);
  }
}

TEST(SizeDistribution, BadInputNamesTheField) {
  auto fieldOf = [](const SizeDistribution& d) {
    try {
      d.validate("s");
    } catch (const InputError& e) {
      return e.field();
    }
    return std::string("(accepted)");
  };
  EXPECT_EQ(fieldOf(SizeDistribution::fixed(0.0)), "s.radius");
  EXPECT_EQ(fieldOf(SizeDistribution::uniform(0.0, 0.1)), "s.r_min");
  EXPECT_EQ(fieldOf(SizeDistribution::uniform(0.2, 0.1)), "s.r_max");
  EXPECT_EQ(fieldOf(SizeDistribution::linear(0.1, 0.2, -1.0, 1.0)), "s.weight_at_min");
  EXPECT_EQ(fieldOf(SizeDistribution::linear(0.1, 0.2, 0.0, 0.0)), "s.weight_at_max");
  EXPECT_EQ(fieldOf(SizeDistribution::normal(0.15, 0.0, 0.1, 0.2)), "s.std");
  EXPECT_EQ(fieldOf(SizeDistribution::normal(0.15, 0.01, 0.2, 0.2)), "s.r_max");
  EXPECT_EQ(fieldOf(SizeDistribution::normal(1.0, 0.01, 0.1, 0.2)), "s.mean");
  EXPECT_EQ(fieldOf(SizeDistribution::discrete({}, {})), "s.radii");
  EXPECT_EQ(fieldOf(SizeDistribution::discrete({0.1}, {1.0, 2.0})), "s.weights");
  EXPECT_EQ(fieldOf(SizeDistribution::discrete({0.1, -0.1}, {1.0, 2.0})), "s.radii[1]");
  EXPECT_EQ(fieldOf(SizeDistribution::discrete({0.1, 0.2}, {0.0, 0.0})), "s.weights");
  EXPECT_EQ(fieldOf(SizeDistribution::uniform(0.1, 0.2)), "(accepted)");
}

}  // namespace
}  // namespace demlink::core
