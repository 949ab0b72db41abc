#pragma once
/// Translation of RigidBody declarations (proto/demlink/v1/coupling.proto). A rigid body is
/// a mesh under prescribed motion like a MOVING facet body; in a co-simulation its client
/// moves it at every sample (core::CoupledMotion), in a headless run it keeps its initial
/// twist. The geometry (box, STL file, triangle list or STL bytes) is given in the body's
/// own frame; reference_point in that frame is the point whose world position is `position`
/// and about which the wrench is reported.
#include <filesystem>
#include <string>

#include "demlink/core/walls/coupled_motion.hpp"
#include "demlink/server/scene/translate_mesh_body.hpp"
#include "demlink/v1/coupling.pb.h"

namespace demlink::server {

/// Checks one RigidBody and describes its body (named `name`, at its initial pose with its
/// initial twist) for buildMeshBody. Throws core::InputError naming
/// `fieldPrefix + ".<field>"`, e.g. ".material", ".box.size[0]", ".stl_file", ".stl_data",
/// ".orientation", ".motion".
[[nodiscard]] MeshBodyDeclaration translateRigidBody(const v1::RigidBody& body, const std::string& name,
                                                     const MaterialResolver& resolveMaterial,
                                                     const FileScope& files,
                                                     const std::string& fieldPrefix);

/// The engine's motion mode of a declaration (MOTION_UNSPECIFIED: PREDICTED). Throws
/// core::InputError naming `fieldPrefix + ".motion"` for an unknown value.
[[nodiscard]] core::MotionMode rigidBodyMotion(const v1::RigidBody& body, const std::string& fieldPrefix);

}  // namespace demlink::server
