#include "demlink/core/step/stage_sampling.hpp"

namespace demlink::core {

std::uint64_t stageTimingWeight(std::uint64_t step) {
  if (step < kStageTimingStride) return 1;
  // splitmix64's finaliser: every bit of the step number moves every bit of the hash.
  std::uint64_t z = step + 0x9E3779B97F4A7C15ULL;
  z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ULL;
  z = (z ^ (z >> 27)) * 0x94D049BB133111EBULL;
  z ^= z >> 31;
  return z % kStageTimingStride == 0 ? kStageTimingStride : 0;
}

}  // namespace demlink::core
