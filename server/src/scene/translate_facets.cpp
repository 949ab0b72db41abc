/// FacetBody -> MeshBodyDeclaration (contract in translate_facets.hpp).
///
/// Roles map onto the engine's one rigid-mesh type: FIXED is a mesh with zero
/// twist, MOVING one with a prescribed twist, NON_COLLIDING one whose collision
/// window is empty (the world skips it in the neighbour and contact stages but
/// still advances its pose, so a sensor or source region attached to it moves).
/// A box is built around its centre (the reference point); a triangle list gets
/// the STL reader's vertex merging so shared edges are recognised by the contact
/// code, and a triangle list equals the same geometry read from an STL file.
#include "demlink/server/scene/translate_facets.hpp"

#include <limits>

#include "demlink/core/base/input_error.hpp"

namespace demlink::server {
namespace {

using core::InputError;

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

/// The geometry and the pose it is placed at.
void readGeometry(const v1::FacetBody& facet, const FileScope& files, const std::string& prefix,
                  MeshBodyDeclaration& out) {
  switch (facet.geometry_case()) {
    case v1::FacetBody::kBox: {
      for (const auto& [given, field] : {std::pair{facet.has_reference_point(), "reference_point"},
                                         std::pair{facet.has_position(), "position"},
                                         std::pair{facet.has_orientation(), "orientation"}}) {
        if (given) {
          throw InputError(prefix + "." + field, "(given)", "a box is placed by box.centre and box.orientation");
        }
      }
      BoxGeometry box = boxGeometry(facet.box(), prefix + ".box");
      out.mesh = std::move(box.mesh);
      out.position = box.centre;
      out.orientation = box.orientation;
      return;
    }
    case v1::FacetBody::kStlFile:
      out.stl_file = stlFileOf(facet.stl_file(), files, prefix + ".stl_file");
      readPlacement(facet, prefix, OmittedPosition::ReferencePoint, out);
      return;
    case v1::FacetBody::kTriangles:
      out.mesh = mergeTriangleList(facet.triangles(), prefix + ".triangles");
      readPlacement(facet, prefix, OmittedPosition::ReferencePoint, out);
      return;
    case v1::FacetBody::GEOMETRY_NOT_SET: break;
  }
  throw InputError(prefix, "(no geometry)", "one of box, stl_file or triangles is required");
}

}  // namespace

MeshBodyDeclaration translateFacetBody(const v1::FacetBody& facet, const std::string& name,
                                       const MaterialResolver& resolveMaterial,
                                       const FileScope& files, const std::string& fieldPrefix) {
  const std::string& prefix = fieldPrefix;
  const Role role = toRole(facet, prefix);
  MeshBodyDeclaration out;
  out.name = name;
  if (role != Role::NonColliding || !facet.material().empty()) {
    out.material = resolveMaterial(facet.material(), prefix + ".material");
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
  readGeometry(facet, files, prefix, out);
  if (role != Role::Fixed) readTwist(facet, prefix, out);
  out.rigid = facet.rigid();
  if (role == Role::NonColliding) {
    out.active_from = out.active_until = std::numeric_limits<double>::infinity();
  } else {
    if (facet.has_active_from()) out.active_from = facet.active_from();
    if (facet.has_active_until()) out.active_until = facet.active_until();
  }
  return out;
}

}  // namespace demlink::server
