/// Clods (contract in clods.hpp).
#include "demlink/core/bonds/clods.hpp"

#include <algorithm>
#include <cmath>
#include <cstddef>

#include "demlink/core/bonds/bond_set.hpp"
#include "demlink/core/base/random.hpp"

namespace demlink::core {

std::vector<std::uint32_t> formClods(const ParticleArrays& p, const std::vector<char>& candidate,
                                     const ClodSpec& spec) {
  std::vector<std::uint32_t> clodOf(p.size(), 0);
  std::vector<std::uint32_t> candidates;
  for (std::uint32_t i = 0; i < p.size(); ++i) {
    if (candidate[i] != 0) candidates.push_back(i);
  }
  const auto target = static_cast<std::size_t>(std::llround(spec.fraction * static_cast<double>(candidates.size())));
  if (target == 0) return clodOf;

  // Touching neighbours of each sphere, in id order (pairsWithinGap sorts by ids).
  std::vector<std::vector<std::uint32_t>> neighbours(p.size());
  for (const auto& [a, b] : pairsWithinGap(p, candidate, spec.gap)) {
    neighbours[a].push_back(b);
    neighbours[b].push_back(a);
  }
  // Seed order: a Fisher-Yates shuffle of the candidates in id order.
  std::sort(candidates.begin(), candidates.end(), [&](std::uint32_t a, std::uint32_t b) { return p.id[a] < p.id[b]; });
  Random random(spec.seed);
  for (std::size_t k = candidates.size(); k > 1; --k) {
    const auto j = static_cast<std::size_t>(random.uniform() * static_cast<double>(k));
    std::swap(candidates[k - 1], candidates[std::min(j, k - 1)]);
  }

  std::size_t grouped = 0;
  std::uint32_t clods = 0;
  std::vector<std::uint32_t> members;
  const double radius2 = spec.radius * spec.radius;
  for (const std::uint32_t seed : candidates) {
    if (grouped >= target) break;
    if (clodOf[seed] != 0) continue;
    const std::uint32_t clod = clods + 1;
    members.assign(1, seed);
    clodOf[seed] = clod;
    for (std::size_t next = 0; next < members.size() && grouped + members.size() < target; ++next) {
      for (const std::uint32_t j : neighbours[members[next]]) {
        if (clodOf[j] != 0 || (p.position[j] - p.position[seed]).squaredNorm() > radius2) continue;
        clodOf[j] = clod;
        members.push_back(j);
        if (grouped + members.size() >= target) break;
      }
    }
    if (members.size() < 2) {  // nothing to bond: the seed stays free
      clodOf[seed] = 0;
      continue;
    }
    clods = clod;
    grouped += members.size();
  }
  return clodOf;
}

}  // namespace demlink::core
