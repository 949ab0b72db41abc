#pragma once
/// Translation of the particle insertion components (sources.proto) into engine
/// objects: SingleParticle -> World::addParticle, ParticleSource -> core::ParticleSource
/// component, PitGenerator -> core::generatePit (runs the settling at translation).
/// Field paths in errors follow the schema, e.g.
/// "components[3].particle_source.sizes.uniform.r_max".
#include <cstdint>
#include <string>

#include "demlink/core/setup/pit_generator.hpp"
#include "demlink/core/components/size_distribution.hpp"
#include "demlink/core/particles/coarse_graining.hpp"
#include "demlink/core/world.hpp"
#include "demlink/v1/sources.pb.h"

namespace demlink::server {

/// Validated radius distribution; throws InputError naming `fieldPrefix + ".<kind>.<field>"`.
[[nodiscard]] core::SizeDistribution translateSizes(const v1::SizeDistribution& sizes, const std::string& fieldPrefix);

/// Adds the sphere (material already resolved).
void addSingleParticle(const v1::SingleParticle& particle, std::uint32_t material, const std::string& fieldPrefix,
                       core::World& world);

/// Adds a ParticleSource component named `name` and declares its smallest radius. With
/// coarse graining the source makes parcels: sizes x alpha, rate_particles_per_s / alpha^3
/// (rate_kg_per_s kept), so the mass flow is the grains'.
void addParticleSource(const v1::ParticleSource& source, const std::string& name, std::uint32_t material,
                       const core::CoarseGraining& coarse, const std::string& fieldPrefix, core::World& world);

/// The pit's specification, its fields checked (core::generatePit settles it and adds
/// its particles to the world).
core::PitSpec pitSpec(const v1::PitGenerator& pit, std::uint32_t material, const std::string& fieldPrefix,
                      const core::World& world);

}  // namespace demlink::server
