/// The calibration's fit on functions whose minimum is known: a nonlinear response with
/// scatter (one parameter), two coupled responses with scatter (two), three (three), and
/// the uncertainty's propagation against its closed forms.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>

#include "calibration_fit.hpp"

namespace demlink::calibrate {
namespace {

/// Deterministic scatter in [-1, 1] from the parameters: the same point gives the same
/// value (as a scene with fixed seeds does), nearby points unrelated ones.
double scatter(const std::vector<double>& p, int salt) {
  std::uint64_t h = 1469598103934665603ull + static_cast<std::uint64_t>(salt);
  for (double v : p) {
    h ^= static_cast<std::uint64_t>(std::llround(v * 1e9));
    h *= 1099511628211ull;
    h ^= h >> 29;
  }
  return static_cast<double>(h % 20001) / 10000.0 - 1.0;
}

TEST(CalibrationFit, RecoversOneParameterOfASaturatingResponseWithScatter) {
  // An angle that grows with friction and saturates, with 2 % scatter.
  auto angle = [](double mu) { return 40.0 * std::atan(2.0 * mu) * 180.0 / M_PI / 90.0; };
  const double truth = 0.55;
  const Evaluate evaluate = [&](const std::vector<double>& p) {
    return std::vector<double>{angle(p[0]) * (1.0 + 0.02 * scatter(p, 1))};
  };
  const FitResult fit = fitParameters({{0.1, 1.2}}, {angle(truth)}, evaluate);
  EXPECT_NEAR(fit.parameters[0], truth, 0.04);
  EXPECT_FALSE(fit.at_bound[0]);
  EXPECT_EQ(fit.evaluations.size(), 5u + 3u + 3u) << "5 design points and two rounds of centre and axial points";
  const double slope = 40.0 * 2.0 / (1.0 + 4.0 * truth * truth) * 180.0 / M_PI / 90.0;
  EXPECT_NEAR(fit.slopes[0][0], slope, 0.2 * slope);
}

TEST(CalibrationFit, RecoversTwoCoupledParametersWithScatter) {
  auto respond = [](const std::vector<double>& p) {
    return std::vector<double>{20.0 + 15.0 * p[0] + 40.0 * p[1] - 6.0 * p[0] * p[0],
                               0.12 - 0.05 * p[0] - 0.2 * p[1] + 0.1 * p[1] * p[1]};
  };
  const std::vector<double> truth{0.5, 0.1};
  const Evaluate evaluate = [&](const std::vector<double>& p) {
    std::vector<double> r = respond(p);
    r[0] *= 1.0 + 0.01 * scatter(p, 1);
    r[1] *= 1.0 + 0.01 * scatter(p, 2);
    return r;
  };
  const FitResult fit = fitParameters({{0.2, 1.0}, {0.0, 0.3}}, respond(truth), evaluate);
  EXPECT_NEAR(fit.parameters[0], truth[0], 0.06);
  EXPECT_NEAR(fit.parameters[1], truth[1], 0.02);
}

TEST(CalibrationFit, RecoversThreeParametersOfQuadraticResponsesExactly) {
  auto respond = [](const std::vector<double>& p) {
    return std::vector<double>{1.0 + p[0] + 0.5 * p[1] * p[1], 2.0 + p[1] - 0.3 * p[0] * p[2], 3.0 + 2.0 * p[2]};
  };
  const std::vector<double> truth{0.3, 0.7, 0.45};
  const FitResult fit = fitParameters({{0.0, 1.0}, {0.0, 1.0}, {0.0, 1.0}}, respond(truth), respond);
  for (std::size_t j = 0; j < 3; ++j) EXPECT_NEAR(fit.parameters[j], truth[j], 0.01) << j;
  EXPECT_EQ(fit.evaluations.front().parameters.size(), 3u);
}

TEST(CalibrationFit, ATargetOutsideTheBoundsEndsOnTheBound) {
  const Evaluate evaluate = [](const std::vector<double>& p) { return std::vector<double>{1.0 + p[0]}; };
  const FitResult fit = fitParameters({{0.0, 1.0}}, {3.0}, evaluate);
  EXPECT_NEAR(fit.parameters[0], 1.0, 1e-9);
  EXPECT_TRUE(fit.at_bound[0]);
}

TEST(CalibrationFit, UncertaintyIsScatterOverSlopeAndNaNWhenNotDetermined) {
  EXPECT_DOUBLE_EQ(parameterUncertainty({{-3.0}}, {0.6})[0], 0.2);
  const std::vector<double> diagonal = parameterUncertainty({{2.0, 0.0}, {0.0, 0.5}}, {0.1, 0.1});
  EXPECT_NEAR(diagonal[0], 0.05, 1e-12);
  EXPECT_NEAR(diagonal[1], 0.2, 1e-12);
  // Two measurements that see only the sum of the parameters cannot tell them apart.
  const std::vector<double> degenerate = parameterUncertainty({{1.0, 1.0}, {2.0, 2.0}}, {0.1, 0.1});
  EXPECT_TRUE(std::isnan(degenerate[0]));
  EXPECT_TRUE(std::isnan(degenerate[1]));
}

TEST(CalibrationFit, MisfitIsTheSumOfSquaredRelativeMisfits) {
  EXPECT_NEAR(relativeMisfit({11.0, 0.09}, {10.0, 0.1}), 0.01 + 0.01, 1e-15);
}

}  // namespace
}  // namespace demlink::calibrate
