/// The seconds -> steps rule: whole steps, 0 as off or refused, shorter than half a step
/// and too many steps refused, off-grid times rounded with a warning or refused when strict.
#include <gtest/gtest.h>

#include <limits>

#include "demlink/core/base/input_error.hpp"
#include "demlink/core/step/interval_steps.hpp"

namespace demlink::core {
namespace {

/// The InputError's message for intervalSteps(...), or "" if it converts.
std::string errorOf(double seconds, double dt, const IntervalRule& rule = {}) {
  try {
    (void)intervalSteps("box.output.vtk_interval", seconds, dt, rule);
  } catch (const InputError& error) {
    EXPECT_EQ(error.field(), "box.output.vtk_interval");
    EXPECT_EQ(error.value(), formatValue(seconds));
    return error.what();
  }
  return {};
}

TEST(IntervalSteps, WholeMultipleConvertsWithoutWarning) {
  const IntervalSteps s = intervalSteps("f", 0.003, 1e-5);
  EXPECT_EQ(s.steps, 300u);
  EXPECT_TRUE(s.warning.empty()) << s.warning;
  EXPECT_EQ(intervalSteps("f", 1e-5, 1e-5).steps, 1u);
}

TEST(IntervalSteps, ZeroIsOffOrRefusedAsTheFieldSays) {
  EXPECT_EQ(intervalSteps("f", 0.0, 1e-5).steps, 0u);
  IntervalRule refused;
  refused.zero = ZeroInterval::Refused;
  EXPECT_NE(errorOf(0.0, 1e-5, refused).find("must be > 0"), std::string::npos);
  EXPECT_EQ(intervalSteps("f", 2e-5, 1e-5, refused).steps, 2u);
}

TEST(IntervalSteps, NegativeOrNotFiniteIsRefused) {
  EXPECT_NE(errorOf(-1e-3, 1e-5).find("must be >= 0"), std::string::npos);
  EXPECT_NE(errorOf(std::numeric_limits<double>::quiet_NaN(), 1e-5).find("finite"), std::string::npos);
  EXPECT_NE(errorOf(std::numeric_limits<double>::infinity(), 1e-5).find("finite"), std::string::npos);
  EXPECT_THROW((void)intervalSteps("f", 1.0, 0.0), InputError) << "the time step must be > 0";
}

TEST(IntervalSteps, ShorterThanHalfAStepIsRefusedNeverOneStep) {
  const std::string message = errorOf(4e-6, 1e-5);
  EXPECT_NE(message.find("shorter than half a time step (1e-05 s)"), std::string::npos) << message;
  const IntervalSteps up = intervalSteps("f", 6e-6, 1e-5);  // 0.6 steps round up to 1
  EXPECT_EQ(up.steps, 1u);
  EXPECT_FALSE(up.warning.empty());
}

TEST(IntervalSteps, OffGridIsRoundedWithAWarningOrRefusedWhenStrict) {
  const IntervalSteps s = intervalSteps("view.communication_interval", 0.000124, 1e-5);
  EXPECT_EQ(s.steps, 12u);
  EXPECT_EQ(s.warning,
            "view.communication_interval = 0.000124 s is not a multiple of the time step 1e-05 s; rounded to 12 "
            "steps = 0.00012 s");
  IntervalRule strict;
  strict.strict = true;
  const std::string message = errorOf(0.000124, 1e-5, strict);
  EXPECT_NE(message.find("not a whole multiple of the time step 1e-05 s"), std::string::npos) << message;
  EXPECT_NE(message.find("nearest: 12 steps"), std::string::npos) << message;
  EXPECT_EQ(intervalSteps("f", 0.00012, 1e-5, strict).steps, 12u) << "on the grid: strict accepts it";
  // Within 1e-6 dt of the grid counts as on it (decimal times are rarely exact in binary).
  EXPECT_TRUE(intervalSteps("f", 0.1, 1.0 / 3.0 * 1e-3).warning.empty());
}

TEST(IntervalSteps, TooManyStepsIsRefusedAtTheCap) {
  const std::string message = errorOf(1e11, 1e-5);
  EXPECT_NE(message.find("1e+16 time steps of 1e-05 s; at most 1000000000000000"), std::string::npos) << message;
  EXPECT_NE(errorOf(1e-3, 1e-220).find("1e+217 time steps"), std::string::npos) << "a tiny but valid time step";
  IntervalRule capped;
  capped.max_steps = 100'000'000;
  capped.max_steps_why = "per exchange";
  EXPECT_EQ(intervalSteps("f", 1000.0, 1e-5, capped).steps, 100'000'000u) << "the cap itself is allowed";
  const std::string over = errorOf(1000.01, 1e-5, capped);
  EXPECT_NE(over.find("1e+08 time steps of 1e-05 s; at most 100000000 per exchange"), std::string::npos) << over;
}

}  // namespace
}  // namespace demlink::core
