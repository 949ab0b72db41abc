#pragma once
/// Translation of the domain and frame settings in a SimulationBox: the bounds
/// mode (fixed or growing up to a limit box) and the frame's motion
/// (acceleration, rotation). See docs/frame_and_facets.md.
#include <string>

#include "demlink/core/simulation_settings.hpp"
#include "demlink/v1/scene.pb.h"

namespace demlink::server {

/// Sets settings.bounds (mode and limit box; lower/upper are already set by the
/// caller) and settings.frame from `box`. Throws core::InputError naming
/// `prefix + ".bounds.<field>"` or `prefix + ".frame.<field>"`.
void translateFrame(const v1::SimulationBox& box, const std::string& prefix, core::SimulationSettings& settings);

}  // namespace demlink::server
