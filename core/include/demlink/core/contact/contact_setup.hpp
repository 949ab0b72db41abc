#pragma once
/// What the contact stage fixes at set-up: the material pairs mixed once (with the
/// user's overrides and the linear law's stiffness reference), the particles sources
/// will insert later (their materials and sizes join the pair table and the critical
/// time step), which optional passes the pairs need, and the build of the pair loop.
#include <cstdint>
#include <utility>
#include <vector>

#include "demlink/core/contact/contact_model.hpp"
#include "demlink/core/contact/contact_pair_table.hpp"
#include "demlink/core/contact/pair_kernel.hpp"

namespace demlink::core {

struct ContactSetup {
  ContactPairTable table;
  LinearStiffnessReference reference;
  std::vector<PairOverrideEntry> overrides;
  /// (material, smallest radius) of particles that sources will insert later.
  std::vector<std::pair<std::uint32_t, double>> future_particles;
  bool rolling = false;   ///< some pair has rolling friction
  bool cohesion = false;  ///< some pair has cohesion
  PairKernel kernel = PairKernel::kPortable;  ///< chosen at initialize()
};

}  // namespace demlink::core
