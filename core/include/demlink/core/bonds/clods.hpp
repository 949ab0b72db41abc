#pragma once
/// Clods: groups of touching spheres that a bond rule (bond_set.hpp, BondRule::groups)
/// joins with parallel bonds, e.g. the lumps of a cohesive soil in a settled bed.
///
/// A clod starts at a seed sphere and grows breadth-first through touching neighbours
/// (surface gap at most `gap`, the bond rule's gap tolerance, so every member is joined
/// to the seed by a chain of pairs the rule bonds) whose centres lie within `radius` of
/// the seed's centre. Seeds are taken in a seeded random order among the spheres not yet
/// in a clod, and clods are grown until `fraction` of the spheres belong to one (the
/// last clod stops at that count). A seed without a free touching neighbour makes no clod.
///
/// Why grown from seeds over the contact network: clods of about one radius that are
/// connected by construction, so their bonds hold each clod together and no bond joins
/// two clods; the seeded order makes the clods depend only on the positions and the seed.
#include <cstdint>
#include <vector>

#include "demlink/core/particles/particle_arrays.hpp"

namespace demlink::core {

struct ClodSpec {
  double fraction = 0.0;   ///< of the candidate spheres put into clods [-], in [0, 1]
  double radius = 0.0;     ///< largest distance of a member's centre from its seed's [m], > 0
  double gap = 0.0;        ///< largest surface gap of touching spheres [m], >= 0
  std::uint64_t seed = 0;  ///< of the seed order
};

/// Clod number (from 1) of each particle slot; 0: in no clod (or not a candidate).
/// Only slots with candidate[slot] != 0 are grouped.
[[nodiscard]] std::vector<std::uint32_t> formClods(const ParticleArrays& particles, const std::vector<char>& candidate,
                                                   const ClodSpec& spec);

}  // namespace demlink::core
