/// FacetBody -> core::MeshBody (contract in translate_facets.hpp).
///
/// Roles map onto the engine's one rigid-mesh type: FIXED is a mesh with zero
/// twist, MOVING one with a prescribed twist, NON_COLLIDING one whose collision
/// window is empty (the world skips it in the neighbour and contact stages but
/// still advances its pose, so a sensor or source region attached to it moves).
/// A box is built around its centre (the reference point); a triangle list gets
/// the STL reader's vertex merging so shared edges are recognised by the contact
/// code, and a triangle list equals the same geometry read from an STL file.
#include "demlink/server/scene/translate_facets.hpp"

#include <bit>
#include <cmath>
#include <limits>
#include <map>

#include "demlink/core/input_error.hpp"
#include "demlink/server/scene/scene_translator.hpp"

namespace demlink::server {
namespace {

using core::InputError;
using core::Vec3;

Vec3 toVec3(const v1::Vector3& v) { return {v.x(), v.y(), v.z()}; }

void requireFiniteVector(const std::string& field, const Vec3& v) {
  for (int k = 0; k < 3; ++k) core::requireFinite(field + "[" + std::to_string(k) + "]", v[k]);
}

core::Quat toQuat(const v1::Quaternion& q, const std::string& field) {
  const core::Quat quat(q.w(), q.x(), q.y(), q.z());
  for (int k = 0; k < 4; ++k) core::requireFinite(field, quat.coeffs()[k]);
  if (!(quat.norm() > 0.0)) throw InputError(field, "(0, 0, 0, 0)", "must be a non-zero quaternion");
  return quat.normalized();
}

enum class Role { Fixed, Moving, NonColliding };

Role toRole(const v1::FacetBody& facet, const std::string& prefix) {
  switch (facet.role()) {
    case v1::FacetBody::ROLE_UNSPECIFIED:
    case v1::FacetBody::FIXED: return Role::Fixed;
    case v1::FacetBody::MOVING: return Role::Moving;
    case v1::FacetBody::NON_COLLIDING: return Role::NonColliding;
    default:
      throw InputError(prefix + ".role", std::to_string(facet.role()),
                       "unknown role (FIXED, MOVING or NON_COLLIDING)");
  }
}

}  // namespace

/// The box's mesh relative to its centre; the top face (+z, box frame) left out if open.
core::TriangleMesh facetBoxMesh(const v1::FacetBox& box, const std::string& prefix) {
  if (!box.has_size()) throw InputError(prefix + ".size", "(missing)", "a box needs its edge lengths");
  const Vec3 size = toVec3(box.size());
  for (int k = 0; k < 3; ++k) core::requirePositive(prefix + ".size[" + std::to_string(k) + "]", size[k]);
  core::TriangleMesh mesh = core::axisAlignedBoxMesh(-0.5 * size, 0.5 * size);
  if (box.open_top()) {
    std::erase_if(mesh.triangles, [&](const std::array<std::uint32_t, 3>& t) {
      return mesh.vertices[t[0]].z() > 0.0 && mesh.vertices[t[1]].z() > 0.0 && mesh.vertices[t[2]].z() > 0.0;
    });
  }
  return mesh;
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
      const Vec3 v = toVec3(*corner);
      requireFiniteVector(path + "." + label, v);
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

core::MeshBody translateFacetBody(const v1::FacetBody& facet, const std::string& name,
                                  const MaterialResolver& resolveMaterial,
                                  const std::filesystem::path& sceneDirectory, const std::string& fieldPrefix) {
  const std::string& prefix = fieldPrefix;
  const Role role = toRole(facet, prefix);
  std::uint32_t material = 0;
  if (role != Role::NonColliding || !facet.material().empty()) {
    material = resolveMaterial(facet.material(), prefix + ".material");
  }
  if (role == Role::Fixed) {
    if (facet.has_linear_velocity()) {
      throw InputError(prefix + ".linear_velocity", "(given)", "a FIXED body does not move (use role MOVING)");
    }
    if (facet.has_angular_velocity()) {
      throw InputError(prefix + ".angular_velocity", "(given)", "a FIXED body does not move (use role MOVING)");
    }
  }
  if (role == Role::NonColliding) {
    if (facet.has_active_from()) {
      throw InputError(prefix + ".active_from", core::formatValue(facet.active_from()),
                       "a NON_COLLIDING body never collides; use FIXED or MOVING with a collision window");
    }
    if (facet.has_active_until()) {
      throw InputError(prefix + ".active_until", core::formatValue(facet.active_until()),
                       "a NON_COLLIDING body never collides; use FIXED or MOVING with a collision window");
    }
  }

  core::MeshBody body = [&]() -> core::MeshBody {
    switch (facet.geometry_case()) {
      case v1::FacetBody::kBox: {
        for (const auto& [given, field] : {std::pair{facet.has_reference_point(), "reference_point"},
                                           std::pair{facet.has_position(), "position"},
                                           std::pair{facet.has_orientation(), "orientation"}}) {
          if (given) {
            throw InputError(prefix + "." + field, "(given)",
                             "a box is placed by box.centre and box.orientation");
          }
        }
        const v1::FacetBox& box = facet.box();
        core::TriangleMesh mesh = facetBoxMesh(box, prefix + ".box");
        const Vec3 centre = toVec3(box.centre());
        requireFiniteVector(prefix + ".box.centre", centre);
        const core::Quat orientation =
            box.has_orientation() ? toQuat(box.orientation(), prefix + ".box.orientation") : core::Quat::Identity();
        core::MeshBody out(name, std::move(mesh.vertices), std::move(mesh.triangles), material);
        out.setPose(centre, orientation);
        return out;
      }
      case v1::FacetBody::kStlFile: {
        // Same checks and loading as a mesh_body (the field names coincide).
        v1::MeshBody asMesh;
        asMesh.set_stl_file(facet.stl_file());
        *asMesh.mutable_reference_point() = facet.reference_point();
        *asMesh.mutable_position() = facet.has_position() ? facet.position() : facet.reference_point();
        if (facet.has_orientation()) *asMesh.mutable_orientation() = facet.orientation();
        const MeshBodyDeclaration d = translateMeshBody(asMesh, name, material, sceneDirectory, prefix);
        core::MeshBody out = [&] {
          try {
            return core::MeshBody::fromStl(name, d.stl_file.string(), d.reference_point, material);
          } catch (const InputError& e) {
            throw InputError(prefix + ".stl_file", e.value(), e.what());
          }
        }();
        out.setPose(d.position, d.orientation);
        return out;
      }
      case v1::FacetBody::kTriangles: {
        core::TriangleMesh mesh = mergeTriangleList(facet.triangles(), prefix + ".triangles");
        const Vec3 reference = toVec3(facet.reference_point());
        requireFiniteVector(prefix + ".reference_point", reference);
        const Vec3 position = facet.has_position() ? toVec3(facet.position()) : reference;
        requireFiniteVector(prefix + ".position", position);
        const core::Quat orientation =
            facet.has_orientation() ? toQuat(facet.orientation(), prefix + ".orientation") : core::Quat::Identity();
        for (Vec3& v : mesh.vertices) v -= reference;
        core::MeshBody out(name, std::move(mesh.vertices), std::move(mesh.triangles), material);
        out.setPose(position, orientation);
        return out;
      }
      case v1::FacetBody::GEOMETRY_NOT_SET: break;
    }
    throw InputError(prefix, "(no geometry)", "one of box, stl_file or triangles is required");
  }();

  if (role != Role::Fixed) {
    const Vec3 linear = toVec3(facet.linear_velocity());
    const Vec3 angular = toVec3(facet.angular_velocity());
    requireFiniteVector(prefix + ".linear_velocity", linear);
    requireFiniteVector(prefix + ".angular_velocity", angular);
    body.setVelocity(linear, angular);
  }
  if (role == Role::NonColliding) {
    const double never = std::numeric_limits<double>::infinity();
    body.setCollisionWindow(never, never);
  } else {
    const double from = facet.has_active_from() ? facet.active_from() : -std::numeric_limits<double>::infinity();
    const double until = facet.has_active_until() ? facet.active_until() : std::numeric_limits<double>::infinity();
    try {
      body.setCollisionWindow(from, until);
    } catch (const InputError& e) {
      throw InputError(prefix + "." + e.field(), e.value(), e.what());
    }
  }
  return body;
}

}  // namespace demlink::server
