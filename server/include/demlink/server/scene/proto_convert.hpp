#pragma once
/// Conversions between the schema's geometry messages (proto/demlink/v1/geometry.proto) and
/// the engine's math types, with the declaration checks every translator shares: finite
/// vectors named per component ("<field>[k]"), non-zero quaternions, and the files a scene
/// may name (FileScope).
#include <filesystem>
#include <string>
#include <vector>

#include "demlink/core/base/math_types.hpp"
#include "demlink/v1/geometry.pb.h"
#include "demlink/v1/scene.pb.h"

namespace demlink::server {

/// The scene path of the `index`-th component, "components[index]": how every error names a
/// field of a scene (a co-simulation shows the component's name instead, nameDeclaredField).
[[nodiscard]] std::string componentPath(int index);

/// A declaration's kind as the schema names it ("rigid_body"); "kind" when none is set.
[[nodiscard]] std::string componentKindName(v1::ComponentDeclaration::KindCase kind);

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

/// Where the files a scene or a client names may be. Relative paths are relative to
/// `anchor`; unless `anywhere`, a path is made canonical (symlinks and ".." resolved) and
/// must then lie under one of `roots` (none: every path is refused with `no_root_reason`).
struct FileScope {
  std::filesystem::path anchor;
  std::vector<std::filesystem::path> roots;
  bool anywhere = true;
  std::string roots_name = "the scene file's folder";  ///< how errors call the roots
  std::string no_root_reason = "no file may be named here";

  /// Any path, relative ones as given (library callers that trust their scene).
  FileScope() = default;
  /// A scene file's folder: the anchor and the only root. An empty folder: FileScope().
  FileScope(const std::filesystem::path& sceneDirectory);  // NOLINT(google-explicit-constructor): a folder is a scope
};

/// A path from a scene, checked against `scope`: the file (canonical when the scope has
/// roots). Throws core::InputError naming `field` (the path escaped and truncated) when
/// the path is empty (reason `emptyReason`), lies outside the scope's roots, does not
/// exist or is not a regular file (a device, folder or pipe).
[[nodiscard]] std::filesystem::path resolveExistingSceneFile(const std::string& path, const FileScope& scope,
                                                             const std::string& field,
                                                             const std::string& emptyReason = "a file path is required");

}  // namespace demlink::server
