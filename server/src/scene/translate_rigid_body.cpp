/// RigidBody -> core::MeshBody (contract in translate_rigid_body.hpp).
///
/// Every geometry is first brought into one triangle mesh in the body's own frame (a box
/// is built around box.centre with box.orientation, an STL file or STL bytes are parsed
/// by the engine's reader, a triangle list gets the facet translator's vertex merging),
/// then expressed relative to reference_point and placed at (position, orientation). So
/// the four geometries follow one placement rule, the same one facet bodies use.
#include "demlink/server/scene/translate_rigid_body.hpp"

#include <system_error>
#include <utility>

#include "demlink/core/input_error.hpp"
#include "demlink/core/walls/stl_reader.hpp"

namespace demlink::server {
namespace {

using core::InputError;
using core::Vec3;

Vec3 toVec3(const v1::Vector3& v) { return {v.x(), v.y(), v.z()}; }

Vec3 finiteVector(const v1::Vector3& v, const std::string& field) {
  const Vec3 out = toVec3(v);
  for (int k = 0; k < 3; ++k) core::requireFinite(field + "[" + std::to_string(k) + "]", out[k]);
  return out;
}

core::Quat toQuat(const v1::Quaternion& q, const std::string& field) {
  const core::Quat quat(q.w(), q.x(), q.y(), q.z());
  for (int k = 0; k < 4; ++k) core::requireFinite(field, quat.coeffs()[k]);
  if (!(quat.norm() > 0.0)) throw InputError(field, "(0, 0, 0, 0)", "must be a non-zero quaternion");
  return quat.normalized();
}

core::TriangleMesh fromStl(core::StlMesh stl) {
  core::TriangleMesh mesh;
  mesh.vertices = std::move(stl.vertices);
  mesh.triangles = std::move(stl.triangles);
  return mesh;
}

/// The geometry in the body's own frame.
core::TriangleMesh geometryOf(const v1::RigidBody& body, const std::filesystem::path& sceneDirectory,
                              const std::string& prefix) {
  switch (body.geometry_case()) {
    case v1::RigidBody::kBox: {
      const std::string field = prefix + ".box";
      core::TriangleMesh mesh = facetBoxMesh(body.box(), field);
      const Vec3 centre = finiteVector(body.box().centre(), field + ".centre");
      const core::Quat rotation = body.box().has_orientation()
                                      ? toQuat(body.box().orientation(), field + ".orientation")
                                      : core::Quat::Identity();
      for (Vec3& v : mesh.vertices) v = centre + rotation * v;
      return mesh;
    }
    case v1::RigidBody::kStlFile: {
      const std::string field = prefix + ".stl_file";
      if (body.stl_file().empty()) throw InputError(field, "\"\"", "an STL file path is required");
      std::filesystem::path path(body.stl_file());
      if (!path.is_absolute() && !sceneDirectory.empty()) path = sceneDirectory / path;
      std::error_code ec;
      if (!std::filesystem::is_regular_file(path, ec)) {
        throw InputError(field, "\"" + body.stl_file() + "\"", "file not found (looked for " + path.string() + ")");
      }
      try {
        return fromStl(core::readStl(path.string()));
      } catch (const InputError& e) {
        throw InputError(field, e.value(), e.what());
      }
    }
    case v1::RigidBody::kTriangles: return mergeTriangleList(body.triangles(), prefix + ".triangles");
    case v1::RigidBody::kStlData: {
      const std::string field = prefix + ".stl_data";
      if (body.stl_data().empty()) throw InputError(field, "(0 bytes)", "the STL content is empty");
      try {
        return fromStl(core::parseStl(body.stl_data(), field));
      } catch (const InputError& e) {
        throw InputError(field, e.value(), e.what());
      }
    }
    case v1::RigidBody::GEOMETRY_NOT_SET: break;
  }
  throw InputError(prefix, "(no geometry)", "one of box, stl_file, triangles or stl_data is required");
}

}  // namespace

core::MotionMode rigidBodyMotion(const v1::RigidBody& body, const std::string& fieldPrefix) {
  switch (body.motion()) {
    case v1::RigidBody::MOTION_UNSPECIFIED:
    case v1::RigidBody::PREDICTED: return core::MotionMode::Predicted;
    case v1::RigidBody::LAGGED: return core::MotionMode::Lagged;
    default:
      throw InputError(fieldPrefix + ".motion", std::to_string(body.motion()), "unknown motion (PREDICTED or LAGGED)");
  }
}

core::MeshBody translateRigidBody(const v1::RigidBody& body, const std::string& name,
                                  const MaterialResolver& resolveMaterial,
                                  const std::filesystem::path& sceneDirectory, const std::string& fieldPrefix) {
  const std::string& prefix = fieldPrefix;
  const std::uint32_t material = resolveMaterial(body.material(), prefix + ".material");
  (void)rigidBodyMotion(body, prefix);
  core::TriangleMesh mesh = geometryOf(body, sceneDirectory, prefix);
  const Vec3 reference = finiteVector(body.reference_point(), prefix + ".reference_point");
  const Vec3 position = body.has_position() ? finiteVector(body.position(), prefix + ".position") : reference;
  const core::Quat orientation =
      body.has_orientation() ? toQuat(body.orientation(), prefix + ".orientation") : core::Quat::Identity();
  const Vec3 linear = finiteVector(body.linear_velocity(), prefix + ".linear_velocity");
  const Vec3 angular = finiteVector(body.angular_velocity(), prefix + ".angular_velocity");
  for (Vec3& v : mesh.vertices) v -= reference;
  core::MeshBody out(name, std::move(mesh.vertices), std::move(mesh.triangles), material);
  out.setPose(position, orientation);
  out.setVelocity(linear, angular);
  return out;
}

}  // namespace demlink::server
