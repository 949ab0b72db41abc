/// RigidBody -> MeshBodyDeclaration (contract in translate_rigid_body.hpp).
///
/// Every geometry is given in the body's own frame: a box is built there around box.centre
/// with box.orientation, STL bytes are parsed here, an STL file is read by buildMeshBody,
/// a triangle list gets the facet translator's vertex merging. buildMeshBody then expresses
/// it relative to reference_point and places it at (position, orientation), the rule facet
/// bodies follow too.
#include "demlink/server/scene/translate_rigid_body.hpp"

#include <utility>

#include "demlink/core/base/input_error.hpp"
#include "demlink/core/geometry/stl_reader.hpp"

namespace demlink::server {
namespace {

using core::InputError;

/// The geometry in the body's own frame.
void readGeometry(const v1::RigidBody& body, const FileScope& files, const std::string& prefix,
                  MeshBodyDeclaration& out) {
  switch (body.geometry_case()) {
    case v1::RigidBody::kBox: {
      BoxGeometry box = boxGeometry(body.box(), prefix + ".box");
      for (core::Vec3& v : box.mesh.vertices) v = box.centre + box.orientation * v;
      out.mesh = std::move(box.mesh);
      return;
    }
    case v1::RigidBody::kStlFile:
      out.stl_file = stlFileOf(body.stl_file(), files, prefix + ".stl_file");
      return;
    case v1::RigidBody::kTriangles: out.mesh = mergeTriangleList(body.triangles(), prefix + ".triangles"); return;
    case v1::RigidBody::kStlData: {
      const std::string field = prefix + ".stl_data";
      if (body.stl_data().empty()) throw InputError(field, "(0 bytes)", "the STL content is empty");
      try {
        core::StlMesh stl = core::parseStl(body.stl_data(), field);
        out.mesh.vertices = std::move(stl.vertices);
        out.mesh.triangles = std::move(stl.triangles);
      } catch (const InputError& e) {
        throw e.as(field);
      }
      return;
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

MeshBodyDeclaration translateRigidBody(const v1::RigidBody& body, const std::string& name,
                                       const MaterialResolver& resolveMaterial,
                                       const FileScope& files, const std::string& fieldPrefix) {
  MeshBodyDeclaration out;
  out.name = name;
  out.material = resolveMaterial(body.material(), fieldPrefix + ".material");
  (void)rigidBodyMotion(body, fieldPrefix);
  readGeometry(body, files, fieldPrefix, out);
  readPlacement(body, fieldPrefix, OmittedPosition::ReferencePoint, out);
  readTwist(body, fieldPrefix, out);
  if (body.has_max_speed()) out.max_speed = body.max_speed();
  out.rigid = body.rigid();
  return out;
}

}  // namespace demlink::server
