#pragma once
/// A rigid STL body as declared in a scene, translated out of protobuf and
/// validated; the translator then loads the STL and hands a core::MeshBody at
/// this pose and twist to the world. All vectors are in
/// the world frame unless stated.
#include <cstdint>
#include <filesystem>
#include <string>

#include "demlink/core/math_types.hpp"

namespace demlink::server {

struct MeshBodyDeclaration {
  std::string name;                                  ///< component name
  std::filesystem::path stl_file;                    ///< resolved against the scene file's directory
  std::uint32_t material = 0;                        ///< index into the world's materials
  core::Vec3 position = core::Vec3::Zero();          ///< world position of reference_point [m]
  core::Quat orientation = core::Quat::Identity();   ///< STL frame -> world frame, unit [-]
  core::Vec3 linear_velocity = core::Vec3::Zero();   ///< of reference_point [m/s]
  core::Vec3 angular_velocity = core::Vec3::Zero();  ///< [rad/s]
  core::Vec3 reference_point = core::Vec3::Zero();   ///< in the STL's frame [m]
};

}  // namespace demlink::server
