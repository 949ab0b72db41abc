/// Mesh declarations -> core::MeshBody (contract in translate_mesh_body.hpp).
///
/// buildMeshBody takes an STL file through core::MeshBody::fromStl, which keeps the reader's
/// warnings (dropped degenerate triangles) for the compile report; a mesh already in memory
/// (box, triangle list, STL bytes) is shifted to the reference point the same way. Either
/// way the body's local vertices are (geometry - reference_point), its pose is (position,
/// orientation), so every declaration follows one placement rule.
#include "demlink/server/scene/translate_mesh_body.hpp"

#include <algorithm>
#include <array>
#include <bit>
#include <map>
#include <utility>

#include "demlink/core/base/input_error.hpp"

namespace demlink::server {

using core::InputError;
using core::Vec3;

core::MeshBody buildMeshBody(const MeshBodyDeclaration& declaration, const std::string& fieldPrefix) {
  core::MeshBody body = [&] {
    if (declaration.stl_file.empty()) {
      std::vector<Vec3> vertices = declaration.mesh.vertices;
      for (Vec3& v : vertices) v -= declaration.reference_point;
      return core::MeshBody(declaration.name, std::move(vertices), declaration.mesh.triangles, declaration.material);
    }
    try {
      return core::MeshBody::fromStl(declaration.name, declaration.stl_file.string(), declaration.reference_point,
                                     declaration.material);
    } catch (const InputError& e) {
      throw e.as(fieldPrefix + ".stl_file");
    }
  }();
  body.setPose(declaration.position, declaration.orientation);
  body.setVelocity(declaration.linear_velocity, declaration.angular_velocity);
  body.setRigid(declaration.rigid);
  try {
    body.setSpeedLimit(declaration.max_speed);
    body.setCollisionWindow(declaration.active_from, declaration.active_until);
  } catch (const InputError& e) {
    throw e.within(fieldPrefix);
  }
  return body;
}

std::filesystem::path stlFileOf(const std::string& file, const FileScope& files,
                                const std::string& field) {
  return resolveExistingSceneFile(file, files, field, "an STL file path is required");
}

MeshBodyDeclaration translateMeshBody(const v1::MeshBody& mesh, const std::string& name,
                                      std::uint32_t materialIndex, const FileScope& files,
                                      const std::string& fieldPrefix) {
  MeshBodyDeclaration out;
  out.name = name;
  out.material = materialIndex;
  out.stl_file = stlFileOf(mesh.stl_file(), files, fieldPrefix + ".stl_file");
  readPlacement(mesh, fieldPrefix, OmittedPosition::Origin, out);
  readTwist(mesh, fieldPrefix, out);
  out.rigid = mesh.rigid();
  return out;
}

BoxGeometry boxGeometry(const v1::FacetBox& box, const std::string& fieldPrefix) {
  if (!box.has_size()) throw InputError(fieldPrefix + ".size", "(missing)", "a box needs its edge lengths");
  const Vec3 size = toVec3(box.size());
  for (int k = 0; k < 3; ++k) core::requirePositive(fieldPrefix + ".size[" + std::to_string(k) + "]", size[k]);
  BoxGeometry out;
  out.mesh = core::axisAlignedBoxMesh(-0.5 * size, 0.5 * size);
  if (box.open_top()) {
    std::erase_if(out.mesh.triangles, [&](const std::array<std::uint32_t, 3>& t) {
      const auto& v = out.mesh.vertices;
      return v[t[0]].z() > 0.0 && v[t[1]].z() > 0.0 && v[t[2]].z() > 0.0;
    });
  }
  out.centre = toFiniteVec3(box.centre(), fieldPrefix + ".centre");
  if (box.has_orientation()) out.orientation = toUnitQuat(box.orientation(), fieldPrefix + ".orientation");
  return out;
}

core::TriangleMesh mergeTriangleList(const v1::FacetTriangles& list, const std::string& fieldPrefix) {
  const std::string prefix = fieldPrefix + ".triangles";
  if (list.triangles_size() == 0) throw InputError(prefix, "[]", "at least one triangle is required");
  Vec3 lo = Vec3::Constant(std::numeric_limits<double>::infinity());
  Vec3 hi = -lo;
  for (int t = 0; t < list.triangles_size(); ++t) {
    const v1::FacetTriangle& tri = list.triangles(t);
    const std::string path = prefix + "[" + std::to_string(t) + "]";
    const std::array<std::pair<const char*, const v1::Vector3*>, 3> corners{
        {{"a", &tri.a()}, {"b", &tri.b()}, {"c", &tri.c()}}};
    for (const auto& [label, corner] : corners) {
      const Vec3 v = toFiniteVec3(*corner, path + "." + label);
      lo = lo.cwiseMin(v);
      hi = hi.cwiseMax(v);
    }
  }
  const double minArea = 1.0e-12 * (hi - lo).squaredNorm();
  core::TriangleMesh mesh;
  // Key: the corner's bit pattern (exact coincidence, as in the STL reader).
  std::map<std::array<std::uint64_t, 3>, std::uint32_t> index;
  const auto vertexOf = [&](const Vec3& v) {
    const std::array<std::uint64_t, 3> key{std::bit_cast<std::uint64_t>(v.x() + 0.0),
                                           std::bit_cast<std::uint64_t>(v.y() + 0.0),
                                           std::bit_cast<std::uint64_t>(v.z() + 0.0)};
    const auto [it, inserted] = index.emplace(key, static_cast<std::uint32_t>(mesh.vertices.size()));
    if (inserted) mesh.vertices.push_back(v);
    return it->second;
  };
  for (int t = 0; t < list.triangles_size(); ++t) {
    const v1::FacetTriangle& tri = list.triangles(t);
    const Vec3 a = toVec3(tri.a());
    const Vec3 b = toVec3(tri.b());
    const Vec3 c = toVec3(tri.c());
    const double area = 0.5 * (b - a).cross(c - a).norm();
    const std::array<std::uint32_t, 3> ids{vertexOf(a), vertexOf(b), vertexOf(c)};
    if (ids[0] == ids[1] || ids[1] == ids[2] || ids[0] == ids[2] || !(area > minArea)) {
      throw InputError(prefix + "[" + std::to_string(t) + "]", "area " + core::formatValue(area) + " m^2",
                       "degenerate triangle (repeated corner or zero area): it has no normal");
    }
    mesh.triangles.push_back(ids);
  }
  return mesh;
}

}  // namespace demlink::server
