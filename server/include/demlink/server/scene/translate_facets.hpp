#pragma once
/// Translation of FacetBody declarations (proto/demlink/v1/facets.proto): a box, an STL
/// file or a triangle list, with its role (fixed, moving, non-colliding) and collision
/// window, becomes a MeshBodyDeclaration for buildMeshBody (translate_mesh_body.hpp). Kept
/// out of scene_translator.cpp so the family's rules live in one file.
#include <filesystem>
#include <string>

#include "demlink/server/scene/translate_mesh_body.hpp"
#include "demlink/v1/facets.pb.h"

namespace demlink::server {

/// Checks one FacetBody and describes its body. Throws core::InputError naming
/// `fieldPrefix + ".<field>"`, e.g. ".box.size[1]", ".triangles.triangles[3]", ".role",
/// ".stl_file" (buildMeshBody names ".stl_file" for an unreadable STL and ".active_until"
/// for a window that ends before it starts).
[[nodiscard]] MeshBodyDeclaration translateFacetBody(const v1::FacetBody& facet, const std::string& name,
                                                     const MaterialResolver& resolveMaterial,
                                                     const FileScope& files,
                                                     const std::string& fieldPrefix);

}  // namespace demlink::server
