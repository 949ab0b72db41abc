#pragma once
/// Per-stage wall time by sampling (World::setStageTiming): timing every stage call of
/// every step costs two clock reads per call, ~12 % of a small bed's step; timing a
/// sample of steps and weighting each by the steps it stands for gives an unbiased
/// estimate for a fraction of that.
///
/// Which steps: all of the first kStageTimingStride (weight 1), so a short run has
/// figures too; after them a step is timed with probability 1 / kStageTimingStride
/// (weight kStageTimingStride), chosen by a hash of its number. A hash, not a fixed
/// period, so a stage that runs every N steps (the watchdog, neighbour rebuilds) is
/// neither always nor never in the sample; and no state, so a restored run samples
/// the same steps.
#include <cstdint>

namespace demlink::core {

/// Mean number of steps between two timed steps after the first ones [-].
inline constexpr std::uint64_t kStageTimingStride = 64;

/// The number of steps step `step` stands for in the sampled stage timing; 0: its
/// stages are not timed.
[[nodiscard]] std::uint64_t stageTimingWeight(std::uint64_t step);

}  // namespace demlink::core
