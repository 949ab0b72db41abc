#include "demlink/core/contact/pair_kernel.hpp"

#include "demlink/core/contact/contact_stage.hpp"

namespace demlink::core {

PairKernel choosePairKernel([[maybe_unused]] bool portableAsked) {
#if DEMLINK_AVX2_FMA_PAIR_KERNEL
  if (!portableAsked && __builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma")) return PairKernel::kAvx2Fma;
#endif
  return PairKernel::kPortable;
}

std::string_view pairKernelName(PairKernel kernel) {
  return kernel == PairKernel::kAvx2Fma ? "avx2_fma" : "portable";
}

}  // namespace demlink::core
