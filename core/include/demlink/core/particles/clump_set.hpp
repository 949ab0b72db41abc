#pragma once
/// A world's rigid clumps: the templates they are made from and the live bodies,
/// with the removal's scratch (a clump is removed whole when any member is).
#include <vector>

#include "demlink/core/particles/clump_body.hpp"
#include "demlink/core/particles/clump_template.hpp"

namespace demlink::core {

struct ClumpSet {
  std::vector<ClumpTemplate> templates;
  std::vector<ClumpBody> bodies;  ///< live clumps (order changes when clumps are removed)
  std::vector<char> removal_flags;  ///< scratch of World::removeParticlesIf
};

}  // namespace demlink::core
