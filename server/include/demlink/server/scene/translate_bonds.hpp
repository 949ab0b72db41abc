#pragma once
/// Scene compiler, parallel bonds: parallel_bonds declarations -> core::BondRule added to
/// the world (core/bonds/bond_set.hpp).
///
/// Why a pass of its own, after every other component: a rule's region may ride on a
/// mesh body, and its materials must be the scene's; its bonds are made while the world
/// runs, so the order of the particle sets does not matter.
#include <cstdint>
#include <map>
#include <string>
#include <unordered_map>

#include "demlink/core/setup/pit_generator.hpp"
#include "demlink/core/world.hpp"
#include "demlink/server/scene/translate_mesh_body.hpp"
#include "demlink/v1/scene.pb.h"

namespace demlink::server {

/// The clods of the pit generators, by the name of the parallel_bonds component that
/// joins them (pit_generator.clod_bonds): particle id -> clod number, unique over pits.
using ClodGroups = std::map<std::string, std::unordered_map<std::uint64_t, std::uint32_t>>;

/// The gap tolerance of the parallel_bonds component `bondsName` that a pit's clods use
/// (the clods' "touching"); throws core::InputError naming `clodBondsField` when no
/// parallel_bonds component has that name, or the component's gap_tolerance field when
/// it is not finite and >= 0.
double clodBondGap(const v1::Scene& scene, const std::string& bondsName, const std::string& clodBondsField);

/// Records a pit's clods for the component named by its clod_bonds (ClodGroups), every
/// pit's clods numbered apart.
void addClodGroups(ClodGroups& groups, const std::string& bondsName, const core::PitReport& report);

/// Adds a bond rule for every parallel_bonds declaration, in declaration order; a
/// component some pit names as its clod_bonds bonds only within the clods of `clods`
/// (none when the pits made none). Throws core::InputError naming the field, e.g.
/// "components[4].parallel_bonds.tensile_strength" = -1: must be > 0, or
/// "components[4].parallel_bonds.materials[1]" = "sand": unknown material.
void addParallelBonds(const v1::Scene& scene, const MaterialResolver& resolveMaterial, core::World& world,
                      const ClodGroups& clods = {});

}  // namespace demlink::server
