#pragma once
/// Translation of the "state" family (proto/demlink/v1/state.proto): a
/// ParticleSystem declaration becomes particles added to the world.
#include <filesystem>
#include <string>

#include "demlink/core/world.hpp"
#include "demlink/server/scene/proto_convert.hpp"
#include "demlink/v1/state.pb.h"

namespace demlink::server {

/// Adds the particle set of `system` to `world` (materials are resolved by name
/// among the world's materials, so call it after they are registered). Returns
/// the number of particles added. Throws core::InputError naming
/// `fieldPrefix + ".csv_file"` / `".checkpoint_file"` (or the file's line and
/// column, or the checkpoint's section) for a bad or missing file or an unknown material.
std::size_t addParticleSystem(const v1::ParticleSystem& system, const FileScope& files,
                              const std::string& fieldPrefix, core::World& world);

}  // namespace demlink::server
