#pragma once
/// Reading Gmsh ASCII mesh files (.msh, formats 2.2 and 4.1) into a TetMesh.
///
/// Kept: element type 4 (4-node tetrahedron) or 11 (10-node tetrahedron), not both; type 2
/// (3-node) or 9 (6-node) triangles of the matching order as the given surface. Ignored:
/// points, lines and every other section ($Entities, $PhysicalNames, ...). Refused: binary
/// files, other volume or surface element types, nodes that are referenced but not defined,
/// flat tetrahedra. Nodes that no tetrahedron uses are dropped; the others keep their file
/// order. Tetrahedra with negative volume are turned over (corners 1 and 2 swapped).
#include <string>
#include <string_view>

#include "demlink/core/deformable/tet_mesh.hpp"

namespace demlink::core {

/// Reads `path`; InputError naming "msh:<path>:line <n>" and the reason.
[[nodiscard]] TetMesh readGmsh(const std::string& path);
/// Parses the text of a .msh file; `source` names it in errors.
[[nodiscard]] TetMesh parseGmsh(std::string_view text, const std::string& source);

}  // namespace demlink::core
