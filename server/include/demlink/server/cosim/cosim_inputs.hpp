#pragma once
/// Checking and converting the inputs of a client's DataPackage (docs/cosim.md, "Faults").
///
/// Why every floating-point field is scanned by reflection: a NaN or infinity anywhere in
/// an input would poison the world silently (a mesh at NaN, gravity NaN), so the check must
/// not depend on someone remembering each field. The error names the field path, e.g.
/// "rigid_body_input.position.x", and the value.
#include <optional>

#include "demlink/core/walls/coupled_motion.hpp"
#include "demlink/core/step/frame_motion.hpp"
#include "demlink/server/cosim/cosim_compiler.hpp"
#include "demlink/v1/protocol.pb.h"

namespace demlink::server {

/// The input of `package` for `component`: present when the kind needs it (rigid_body),
/// absent or of the component's own kind otherwise, finite everywhere, a unit quaternion
/// (within 1e-6), a valid frame, and inside every bound the same field obeys in a
/// declaration (core/input_bounds.hpp: positions, speeds, spins, accelerations, gravity
/// times `timeStep`, source rates). Returns Error{INVALID_INPUT, fatal} naming the field.
[[nodiscard]] std::optional<v1::Error> checkInput(const CosimComponent& component, const v1::DataPackage& package,
                                                  double timeStep);

/// Pose and twist of a checked RigidBodyInput (omitted velocities zero; the quaternion as
/// sent, core::targetPose normalises it).
[[nodiscard]] core::RigidPose poseOf(const v1::RigidBodyInput& input);
[[nodiscard]] core::RigidTwist twistOf(const v1::RigidBodyInput& input);
/// Pose (quaternion normalised) and twist of a checked DeformableBodyInput.
[[nodiscard]] core::RigidPose poseOf(const v1::DeformableBodyInput& input);
[[nodiscard]] core::RigidTwist twistOf(const v1::DeformableBodyInput& input);
/// Applies a checked run-time input of a region sensor (region_sensor_input), particle
/// source (particle_source_input) or sink (particle_sink_input) to its engine component,
/// from the world's current step on; other packages are left alone.
void applyComponentInput(const CosimComponent& component, const v1::DataPackage& package, core::World& world);
/// The frame motion of a checked SimulationBox.Frame.
[[nodiscard]] core::FrameMotion frameOf(const v1::SimulationBox::Frame& frame);

}  // namespace demlink::server
