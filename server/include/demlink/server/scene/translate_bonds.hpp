#pragma once
/// Scene compiler, parallel bonds: parallel_bonds declarations -> core::BondRule added to
/// the world (core/bonds/bond_set.hpp).
///
/// Why a pass of its own, after every other component: a rule's region may ride on a
/// mesh body, and its materials must be the scene's; its bonds are made while the world
/// runs, so the order of the particle sets does not matter.
#include "demlink/core/world.hpp"
#include "demlink/server/scene/translate_mesh_body.hpp"
#include "demlink/v1/scene.pb.h"

namespace demlink::server {

/// Adds a bond rule for every parallel_bonds declaration, in declaration order. Throws
/// core::InputError naming the field, e.g. "components[4].parallel_bonds.tensile_strength"
/// = -1: must be > 0, or "components[4].parallel_bonds.materials[1]" = "sand": unknown material.
void addParallelBonds(const v1::Scene& scene, const MaterialResolver& resolveMaterial, core::World& world);

}  // namespace demlink::server
