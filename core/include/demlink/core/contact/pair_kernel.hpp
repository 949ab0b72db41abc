#pragma once
/// Which build of the particle-particle contact loop a world runs. The loop is compiled
/// twice: portably (the x86-64 baseline, SSE2) and, on x86-64, for processors with AVX2
/// and FMA, whose fused multiply-adds save ~8 % of a settled 5,000-particle step
/// (docs/benchmarks.md; AVX2 without FMA saved nothing). The processor is asked at run
/// time, so one binary serves both.
///
/// A fused multiply-add rounds once where the portable loop rounds twice, so the two
/// builds differ by round-off: a run is bit-identical to another only on the same
/// kernel. SimulationSettings::portable_kernel asks for the portable one everywhere
/// (results that are bit-identical across processors).
#include <string_view>

namespace demlink::core {

enum class PairKernel { kPortable, kAvx2Fma };

/// kAvx2Fma when it was built and this processor has AVX2 and FMA, unless `portableAsked`.
[[nodiscard]] PairKernel choosePairKernel(bool portableAsked);
/// "portable" or "avx2_fma" (the compile report and run log print it).
[[nodiscard]] std::string_view pairKernelName(PairKernel kernel);

}  // namespace demlink::core
