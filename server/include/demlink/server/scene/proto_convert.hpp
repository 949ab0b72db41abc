#pragma once
/// Conversions between the schema's geometry messages (proto/demlink/v1/geometry.proto) and
/// the engine's math types, with the declaration checks every translator shares: finite
/// vectors named per component ("<field>[k]"), non-zero quaternions, and file paths relative
/// to the scene file's directory.
#include <filesystem>
#include <string>

#include "demlink/core/math_types.hpp"
#include "demlink/v1/geometry.pb.h"

namespace demlink::server {

/// The vector as given (no checks).
[[nodiscard]] core::Vec3 toVec3(const v1::Vector3& v);

/// The quaternion (w, x, y, z) as given, neither checked nor normalised.
[[nodiscard]] core::Quat toQuat(const v1::Quaternion& q);

/// Throws core::InputError naming `field + "[k]"` for the first non-finite component k.
void requireFiniteVec3(const std::string& field, const core::Vec3& v);

/// The vector of a declaration, every component finite (see requireFiniteVec3).
[[nodiscard]] core::Vec3 toFiniteVec3(const v1::Vector3& v, const std::string& field);

/// The rotation of a declaration: finite and non-zero, returned normalised. Throws
/// core::InputError naming `field`.
[[nodiscard]] core::Quat toUnitQuat(const v1::Quaternion& q, const std::string& field);

/// Writes an engine vector into a message.
void setVec3(v1::Vector3& out, const core::Vec3& v);

/// Writes an engine quaternion into a message (w, x, y, z as stored).
void setQuat(v1::Quaternion& out, const core::Quat& q);

/// A path from a scene: relative paths are relative to `sceneDirectory` (when not empty).
[[nodiscard]] std::filesystem::path resolveScenePath(const std::string& path,
                                                     const std::filesystem::path& sceneDirectory);

/// resolveScenePath for a file that must exist. Throws core::InputError naming `field`
/// for an empty path (reason `emptyReason`) or when no regular file is there.
[[nodiscard]] std::filesystem::path resolveExistingSceneFile(
    const std::string& path, const std::filesystem::path& sceneDirectory, const std::string& field,
    const std::string& emptyReason = "a file path is required");

}  // namespace demlink::server
