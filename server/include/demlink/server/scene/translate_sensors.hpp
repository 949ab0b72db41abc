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

/// A volume region's shape and placement.
struct TranslatedVolume {
  core::VolumeShape shape;
  core::RegionPlacement placement;
};

/// The region `volume` (`present`: the declaration has it; else an InputError naming
/// `prefix` as missing) with its box or sphere checked and its attachment resolved among
/// world.meshes(); errors name prefix + ".box.size", ".sphere.radius", ".attached_to", ...
TranslatedVolume toVolume(const v1::Volume& volume, bool present, const core::World& world, const std::string& prefix);

/// Adds every sink, sensor and tracker of the scene to the world, in declaration order.
/// Mesh bodies are found by component name among world.meshes(). Throws core::InputError
/// naming the field, e.g. "components[5].region_sensor.region.attached_to" = "bucket":
/// unknown mesh body, or "components[6].flow_sensor.surface.disc.normal" = (0, 0, 0).
void addSensorComponents(const v1::Scene& scene, core::World& world);

}  // namespace demlink::server
