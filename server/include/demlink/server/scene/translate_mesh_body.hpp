#pragma once
/// One path from a mesh declaration to the engine's rigid mesh.
///
/// Three declarations describe a core::MeshBody: mesh_body (an STL file, scene.proto),
/// facet_body (box, STL file or triangles with a role, facets.proto) and rigid_body (box,
/// STL file, triangles or STL bytes moved by a client, coupling.proto). Each translator is
/// a thin adapter that checks its own message and fills a MeshBodyDeclaration; buildMeshBody
/// is the one place that loads the geometry, expresses it relative to the reference point,
/// places it at its pose with its twist and sets its collision window. The geometry sources
/// the schemas share (STL file, FacetBox, FacetTriangles) and the pose fields, which carry the
/// same names in all three messages, are read by the helpers below.
#include <cstdint>
#include <filesystem>
#include <functional>
#include <limits>
#include <string>

#include "demlink/core/base/math_types.hpp"
#include "demlink/core/walls/mesh_body.hpp"
#include "demlink/server/scene/proto_convert.hpp"
#include "demlink/v1/facets.pb.h"
#include "demlink/v1/scene.pb.h"

namespace demlink::server {

/// Resolves a material name to a world index; throws core::InputError naming `field`.
using MaterialResolver = std::function<std::uint32_t(const std::string& name, const std::string& field)>;

/// A rigid triangle-mesh body as declared, translated out of protobuf and validated. The
/// geometry is either `stl_file` (read by buildMeshBody) or, when that is empty, `mesh`.
/// Vectors are in the world frame unless stated.
struct MeshBodyDeclaration {
  std::string name;                                  ///< component name
  std::filesystem::path stl_file;                    ///< resolved against the scene file's directory
  core::TriangleMesh mesh;                           ///< when no stl_file: the geometry in the body's frame [m]
  std::uint32_t material = 0;                        ///< index into the world's materials
  core::Vec3 position = core::Vec3::Zero();          ///< world position of reference_point [m]
  core::Quat orientation = core::Quat::Identity();   ///< body frame -> world frame, unit [-]
  core::Vec3 linear_velocity = core::Vec3::Zero();   ///< of reference_point [m/s]
  core::Vec3 angular_velocity = core::Vec3::Zero();  ///< [rad/s]
  core::Vec3 reference_point = core::Vec3::Zero();   ///< in the body's frame [m]
  double active_from = -std::numeric_limits<double>::infinity();  ///< collision window start [s]
  double active_until = std::numeric_limits<double>::infinity();  ///< collision window end [s]
  bool rigid = false;      ///< the particle alone sets the contact stiffness (core::Material::rigid)
  double max_speed = 0.0;  ///< declared largest speed of a point of the body [m/s] (rigid bodies); 0: none
};

/// The engine body of a declaration. Throws core::InputError naming
/// `fieldPrefix + ".stl_file"` when the STL file cannot be read and
/// `fieldPrefix + ".active_from"` / `".active_until"` for a bad collision window.
[[nodiscard]] core::MeshBody buildMeshBody(const MeshBodyDeclaration& declaration, const std::string& fieldPrefix);

/// Translates one MeshBody declaration (material resolved to `materialIndex`; an omitted
/// position is the origin). Throws core::InputError naming `fieldPrefix + ".<field>"` for
/// an empty stl_file, a missing file, non-finite vectors or a zero quaternion.
[[nodiscard]] MeshBodyDeclaration translateMeshBody(const v1::MeshBody& mesh, const std::string& name,
                                                    std::uint32_t materialIndex,
                                                    const FileScope& files,
                                                    const std::string& fieldPrefix);

/// An STL file declared as `file`, resolved and present. Throws core::InputError naming
/// `field` for an empty path or a missing file.
[[nodiscard]] std::filesystem::path stlFileOf(const std::string& file, const FileScope& files,
                                              const std::string& field);

/// A FacetBox: its closed (or open-top) mesh in the box frame, vertices relative to the
/// centre, and where that frame sits.
struct BoxGeometry {
  core::TriangleMesh mesh;
  core::Vec3 centre = core::Vec3::Zero();          ///< [m]
  core::Quat orientation = core::Quat::Identity();  ///< box frame -> enclosing frame, unit [-]
};

/// Reads a FacetBox. Throws core::InputError naming `fieldPrefix + ".size"` / `".size[k]"`,
/// `".centre[k]"` or `".orientation"`.
[[nodiscard]] BoxGeometry boxGeometry(const v1::FacetBox& box, const std::string& fieldPrefix);

/// Vertices and index triples of a triangle list with exactly coinciding corners
/// merged (order of first use, as the STL reader does). Throws core::InputError
/// naming `fieldPrefix + ".triangles[k]"` for a non-finite corner or a degenerate
/// triangle (a repeated corner, or area below 1e-12 x bounding-box diagonal^2).
[[nodiscard]] core::TriangleMesh mergeTriangleList(const v1::FacetTriangles& list, const std::string& fieldPrefix);

/// What an omitted position means: the origin (mesh_body) or the reference point, so that the
/// body stays where its geometry puts it (facet_body, rigid_body).
enum class OmittedPosition { Origin, ReferencePoint };

/// Reads reference_point, position and orientation (omitted: identity), named as in all three
/// schemas. Throws core::InputError naming `fieldPrefix + ".<field>"`.
template <class Declared>
void readPlacement(const Declared& declared, const std::string& fieldPrefix, OmittedPosition omitted,
                   MeshBodyDeclaration& out) {
  out.reference_point = toFiniteVec3(declared.reference_point(), fieldPrefix + ".reference_point");
  if (declared.has_position()) {
    out.position = toFiniteVec3(declared.position(), fieldPrefix + ".position");
  } else {
    out.position = omitted == OmittedPosition::Origin ? core::Vec3::Zero() : out.reference_point;
  }
  if (declared.has_orientation()) out.orientation = toUnitQuat(declared.orientation(), fieldPrefix + ".orientation");
}

/// Reads linear_velocity and angular_velocity (omitted: zero). Throws core::InputError naming
/// `fieldPrefix + ".<field>[k]"`.
template <class Declared>
void readTwist(const Declared& declared, const std::string& fieldPrefix, MeshBodyDeclaration& out) {
  out.linear_velocity = toFiniteVec3(declared.linear_velocity(), fieldPrefix + ".linear_velocity");
  out.angular_velocity = toFiniteVec3(declared.angular_velocity(), fieldPrefix + ".angular_velocity");
}

}  // namespace demlink::server
