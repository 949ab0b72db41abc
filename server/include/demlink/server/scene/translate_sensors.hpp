#pragma once
/// Scene compiler, removal and measurement components: particle_sink, region_sensor,
/// flow_sensor and tracker declarations -> core::ParticleSink, RegionSensor, FlowSensor,
/// ParticleTracker added to the world.
///
/// Why a pass of its own, after every other component: regions attach to mesh bodies
/// and trackers follow them by component name, so all mesh bodies must be in the world
/// first (a sensor may be declared before the body it rides on).
#include "demlink/core/world.hpp"
#include "demlink/v1/scene.pb.h"

namespace demlink::server {

/// Adds every sink, sensor and tracker of the scene to the world, in declaration order.
/// Mesh bodies are found by component name among world.meshes(). Throws core::InputError
/// naming the field, e.g. "components[5].region_sensor.region.attached_to" = "bucket":
/// unknown mesh body, or "components[6].flow_sensor.surface.disc.normal" = (0, 0, 0).
void addSensorComponents(const v1::Scene& scene, core::World& world);

}  // namespace demlink::server
