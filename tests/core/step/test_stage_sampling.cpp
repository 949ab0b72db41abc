/// Sampled stage timing: the weights make an unbiased estimate of every step's cost, and
/// a stage that runs every N steps is neither over- nor under-counted. Costs are given,
/// not measured, so the checks are exact or statistical, never timed.
#include <gtest/gtest.h>

#include <cstdint>

#include "demlink/core/step/stage_sampling.hpp"

namespace demlink::core {
namespace {

constexpr std::uint64_t kSteps = 1'000'000;

TEST(StageSampling, TheFirstStepsAreAllTimedAtWeightOne) {
  for (std::uint64_t step = 0; step < kStageTimingStride; ++step) EXPECT_EQ(stageTimingWeight(step), 1u) << step;
}

// A cost of 1 s every step sums to the number of steps within 3 %, from about one step
// in kStageTimingStride.
TEST(StageSampling, WeightsSumToTheStepsFromOneStepInTheStride) {
  std::uint64_t estimate = 0;
  std::uint64_t timed = 0;
  for (std::uint64_t step = 0; step < kSteps; ++step) {
    const std::uint64_t w = stageTimingWeight(step);
    estimate += w;
    timed += w > 0 ? 1 : 0;
  }
  EXPECT_NEAR(static_cast<double>(estimate) / kSteps, 1.0, 0.03);  // binomial: 0.8 % standard deviation
  EXPECT_NEAR(static_cast<double>(timed) * kStageTimingStride / kSteps, 1.0, 0.03);
}

// A stage that runs every 100th step (the watchdog's default): a fixed sampling period
// would see it on every sample or on none (a period of 50 reports 50 × too much); the
// hash sees it in about 1 % of the samples. Expected ~156 samples, so 30 % is over
// three standard deviations; the same for a stage that runs every 64th step.
TEST(StageSampling, APeriodicStageIsNotAliased) {
  for (const std::uint64_t period : {std::uint64_t{100}, kStageTimingStride}) {
    std::uint64_t estimate = 0;
    for (std::uint64_t step = 0; step < kSteps; ++step) {
      if (step % period == 0) estimate += stageTimingWeight(step);
    }
    EXPECT_NEAR(static_cast<double>(estimate) / static_cast<double>(kSteps / period), 1.0, 0.3) << period;
  }
}

}  // namespace
}  // namespace demlink::core
