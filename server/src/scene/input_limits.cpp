/// Input limits (contract in input_limits.hpp).
#include "demlink/server/scene/input_limits.hpp"

#include <sys/resource.h>
#include <unistd.h>

#include <algorithm>
#include <limits>

#include <spdlog/fmt/fmt.h>

#include "demlink/core/components/sampled_component.hpp"
#include "demlink/core/base/input_error.hpp"
#include "demlink/core/base/log_text.hpp"
#include "demlink/core/world.hpp"

namespace demlink::server {

std::uint64_t particleMemoryBudget() {
  std::uint64_t limit = std::numeric_limits<std::uint64_t>::max();
  const long pages = sysconf(_SC_PHYS_PAGES);
  const long pageSize = sysconf(_SC_PAGE_SIZE);
  if (pages > 0 && pageSize > 0) limit = static_cast<std::uint64_t>(pages) * static_cast<std::uint64_t>(pageSize);
  rlimit addressSpace{};
  if (getrlimit(RLIMIT_AS, &addressSpace) == 0 && addressSpace.rlim_cur != RLIM_INFINITY) {
    limit = std::min<std::uint64_t>(limit, addressSpace.rlim_cur);
  }
  return limit / 2;
}

void requireParticleMemory(const std::string& field, const std::string& value, std::uint64_t particles) {
  const std::uint64_t budget = particleMemoryBudget();
  const std::uint64_t most = budget / kBytesPerParticle;
  if (particles > most) {
    throw core::InputError(
        field, value,
        fmt::format("{} spheres in the scene would need about {:.3g} GB at {} bytes each; this machine allows {} "
                    "({:.3g} GB: half of its memory or address-space limit)",
                    particles, static_cast<double>(particles) * kBytesPerParticle * 1e-9, kBytesPerParticle, most,
                    static_cast<double>(budget) * 1e-9));
  }
}

void requireOutputFileCount(const core::World& world) {
  std::size_t files = 0;
  for (const auto& component : world.components()) {
    const auto* sampled = dynamic_cast<const core::SampledComponent*>(component.get());
    if (sampled == nullptr || ++files <= kMaxFileComponents) continue;
    throw core::InputError(sampled->fieldPrefix(), core::quotedLogText(sampled->name()),
                           fmt::format("more than {} sensors, sinks and trackers in one scene (each keeps a CSV file "
                                       "open while the simulation runs)",
                                       kMaxFileComponents));
  }
}

}  // namespace demlink::server
