#pragma once
/// Translation of FacetBody declarations (proto/demlink/v1/facets.proto) into
/// engine meshes: a box, an STL file or a triangle list becomes a core::MeshBody
/// placed at its pose, with its role (fixed, moving, non-colliding) and collision
/// window set. Kept out of scene_translator.cpp so the family's rules live in one
/// file; the STL path reuses translateMeshBody's checks.
#include <cstdint>
#include <filesystem>
#include <functional>
#include <string>

#include "demlink/core/walls/mesh_body.hpp"
#include "demlink/v1/facets.pb.h"

namespace demlink::server {

/// Resolves a material name to a world index; throws core::InputError naming `field`.
using MaterialResolver = std::function<std::uint32_t(const std::string& name, const std::string& field)>;

/// Builds the engine body of one FacetBody. Throws core::InputError naming
/// `fieldPrefix + ".<field>"`, e.g. ".box.size[1]", ".triangles.triangles[3]",
/// ".role", ".active_until", ".stl_file".
[[nodiscard]] core::MeshBody translateFacetBody(const v1::FacetBody& facet, const std::string& name,
                                                const MaterialResolver& resolveMaterial,
                                                const std::filesystem::path& sceneDirectory,
                                                const std::string& fieldPrefix);

/// The closed (or open-top) box of a FacetBox in its own frame: vertices relative to the
/// box centre, axis-aligned (the caller applies box.centre and box.orientation). Throws
/// core::InputError naming `fieldPrefix + ".size"` / `".size[k]"`.
[[nodiscard]] core::TriangleMesh facetBoxMesh(const v1::FacetBox& box, const std::string& fieldPrefix);

/// Vertices and index triples of a triangle list with exactly coinciding corners
/// merged (order of first use, as the STL reader does). Throws core::InputError
/// naming `fieldPrefix + ".triangles[k]"` for a non-finite corner or a degenerate
/// triangle (a repeated corner, or area below 1e-12 x bounding-box diagonal^2).
[[nodiscard]] core::TriangleMesh mergeTriangleList(const v1::FacetTriangles& list, const std::string& fieldPrefix);

}  // namespace demlink::server
