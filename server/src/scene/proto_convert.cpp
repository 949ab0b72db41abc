/// Protobuf <-> engine conversions (contract in proto_convert.hpp).
#include "demlink/server/scene/proto_convert.hpp"

#include <system_error>

#include <google/protobuf/descriptor.h>

#include "demlink/core/base/input_error.hpp"
#include "demlink/core/base/unit_quaternion.hpp"
#include "demlink/core/base/log_text.hpp"

namespace demlink::server {

std::string componentPath(int index) { return "components[" + std::to_string(index) + "]"; }

std::string componentKindName(v1::ComponentDeclaration::KindCase kind) {
  const google::protobuf::FieldDescriptor* field =
      v1::ComponentDeclaration::descriptor()->FindFieldByNumber(static_cast<int>(kind));
  return field != nullptr ? std::string(field->name()) : "kind";
}

core::Vec3 toVec3(const v1::Vector3& v) { return {v.x(), v.y(), v.z()}; }

core::Quat toQuat(const v1::Quaternion& q) { return {q.w(), q.x(), q.y(), q.z()}; }

void requireFiniteVec3(const std::string& field, const core::Vec3& v) {
  for (int k = 0; k < 3; ++k) core::requireFinite(field + "[" + std::to_string(k) + "]", v[k]);
}

core::Vec3 toFiniteVec3(const v1::Vector3& v, const std::string& field) {
  const core::Vec3 out = toVec3(v);
  requireFiniteVec3(field, out);
  return out;
}

core::Quat toUnitQuat(const v1::Quaternion& q, const std::string& field) {
  return core::requireUnitQuaternion(field, toQuat(q));
}

void setVec3(v1::Vector3& out, const core::Vec3& v) {
  out.set_x(v.x());
  out.set_y(v.y());
  out.set_z(v.z());
}

void setQuat(v1::Quaternion& out, const core::Quat& q) {
  out.set_w(q.w());
  out.set_x(q.x());
  out.set_y(q.y());
  out.set_z(q.z());
}

FileScope::FileScope(const std::filesystem::path& sceneDirectory) {
  if (sceneDirectory.empty()) return;
  anchor = sceneDirectory;
  roots = {sceneDirectory};
  anywhere = false;
}

namespace {

/// `path` lies in `root` or below (both canonical).
bool isUnder(const std::filesystem::path& path, const std::filesystem::path& root) {
  const std::filesystem::path relative = path.lexically_relative(root);
  return !relative.empty() && *relative.begin() != "..";
}

}  // namespace

std::filesystem::path resolveExistingSceneFile(const std::string& path, const FileScope& scope,
                                               const std::string& field, const std::string& emptyReason) {
  if (path.empty()) throw core::InputError(field, "\"\"", emptyReason);
  const std::string value = core::quotedLogText(path);
  const std::filesystem::path given(path);
  std::filesystem::path resolved = given.is_absolute() || scope.anchor.empty() ? given : scope.anchor / given;
  std::error_code ec;
  if (!scope.anywhere) {
    if (scope.roots.empty()) throw core::InputError(field, value, scope.no_root_reason);
    resolved = std::filesystem::weakly_canonical(resolved, ec);
    if (ec) throw core::InputError(field, value, "cannot be resolved: " + ec.message());
    bool inside = false;
    std::string rootList;
    for (const std::filesystem::path& root : scope.roots) {
      const std::filesystem::path canonicalRoot = std::filesystem::weakly_canonical(root, ec);
      if (ec) continue;
      inside = inside || isUnder(resolved, canonicalRoot);
      rootList += (rootList.empty() ? "" : ", ") + canonicalRoot.string();
    }
    if (!inside) {
      throw core::InputError(field, value,
                             "lies outside " + scope.roots_name + " (" + rootList +
                                 ") once symlinks and '..' are resolved; files may only come from there");
    }
  }
  const std::filesystem::file_status status = std::filesystem::status(resolved, ec);
  if (status.type() == std::filesystem::file_type::not_found || ec) {
    throw core::InputError(field, value, "file not found (looked for " + core::logText(resolved.string()) + ")");
  }
  if (!std::filesystem::is_regular_file(status)) {
    throw core::InputError(field, value,
                           "not a regular file (" + core::logText(resolved.string()) +
                               " is a folder, device, pipe or socket)");
  }
  return resolved;
}

}  // namespace demlink::server
