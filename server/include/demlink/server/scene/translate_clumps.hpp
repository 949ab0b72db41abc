#pragma once
/// Scene translation of clumps (clumps.proto): clump_template components become
/// core::ClumpTemplate, and a particle_lattice naming a clump_template places
/// clumps with seeded uniformly random orientations at its points.
#include <cstdint>
#include <string>

#include "demlink/core/world.hpp"
#include "demlink/v1/scene.pb.h"

namespace demlink::server {

/// Registers every clump_template component (named by the component) in
/// declaration order. Errors name "components[i].clump_template.<field>".
void addClumpTemplates(const v1::Scene& scene, core::World& world);

/// Places one clump per point of `lattice` (whose clump_template is set) in
/// material `material`. `prefix` is the lattice's field path.
void addClumpLattice(const v1::ParticleLattice& lattice, std::uint32_t material, const std::string& prefix,
                     core::World& world);

}  // namespace demlink::server
