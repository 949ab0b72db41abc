/// Protobuf <-> engine conversions (contract in proto_convert.hpp).
#include "demlink/server/scene/proto_convert.hpp"

#include <system_error>

#include "demlink/core/input_error.hpp"

namespace demlink::server {

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
  const core::Quat quat = toQuat(q);
  for (int k = 0; k < 4; ++k) core::requireFinite(field, quat.coeffs()[k]);
  if (!(quat.norm() > 0.0)) throw core::InputError(field, "(0, 0, 0, 0)", "must be a non-zero quaternion");
  return quat.normalized();
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

std::filesystem::path resolveScenePath(const std::string& path, const std::filesystem::path& sceneDirectory) {
  const std::filesystem::path p(path);
  return p.is_absolute() || sceneDirectory.empty() ? p : sceneDirectory / p;
}

std::filesystem::path resolveExistingSceneFile(const std::string& path, const std::filesystem::path& sceneDirectory,
                                               const std::string& field, const std::string& emptyReason) {
  if (path.empty()) throw core::InputError(field, "\"\"", emptyReason);
  const std::filesystem::path resolved = resolveScenePath(path, sceneDirectory);
  std::error_code ec;
  if (!std::filesystem::is_regular_file(resolved, ec)) {
    throw core::InputError(field, "\"" + path + "\"", "file not found (looked for " + resolved.string() + ")");
  }
  return resolved;
}

}  // namespace demlink::server
