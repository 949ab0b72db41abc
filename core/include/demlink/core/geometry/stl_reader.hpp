#pragma once
/// Reading and writing STL triangle meshes (ASCII and binary).
///
/// Why: walls, drums and tools are supplied as STL files. The contact code needs triangles
/// that *share* vertex indices (to reason about shared edges and vertices), whereas STL stores
/// every facet with its own copy of three coordinates, so the reader merges vertices whose
/// coordinates are bit-for-bit identical. Facet normals in the file are ignored: normals are
/// recomputed from the vertex order (right-hand rule), which is what STL defines as binding.
///
/// Format detection: a binary STL is an 80-byte header, a little-endian uint32 triangle count
/// and 50 bytes per triangle, so its size is exactly 84 + 50 * count. Binary files are allowed
/// to start with "solid", hence the size test decides first. Otherwise a file starting with
/// "solid" whose bytes are all text (no NUL/control bytes other than whitespace; UTF-8 is
/// fine) is parsed as ASCII; anything else is reported as a truncated or invalid binary file.
/// ASCII keywords are matched case-insensitively; several solids in one file are concatenated;
/// a missing final "endsolid" is only a warning. Facet normals must be numbers but may be
/// non-finite (they are ignored).
///
/// Degenerate triangles (a repeated vertex index after merging, or area below
/// 1e-12 * (bounding-box diagonal)^2) carry no surface; they are dropped and reported in
/// `warnings` (one line per triangle with its 0-based file index, at most 1000 lines plus a
/// summary line with the total). Vertices referenced only by dropped triangles are removed.
#include <array>
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "demlink/core/base/math_types.hpp"

namespace demlink::core {

/// A triangle mesh as read from an STL file, with merged vertices.
struct StlMesh {
  std::vector<Vec3> vertices;                           ///< unique vertices [file units]
  std::vector<std::array<std::uint32_t, 3>> triangles;  ///< indices into `vertices`
  std::vector<std::string> warnings;                    ///< e.g. dropped degenerate triangles
};

/// Relative area threshold: triangles with area < kStlDegenerateAreaFactor * diag^2 are dropped.
inline constexpr double kStlDegenerateAreaFactor = 1e-12;

/// Reads an ASCII or binary STL file. Vertex and triangle order follow the file (vertices in
/// order of first use). Throws InputError (field "stl:<path>" or "stl:<path>:line N" /
/// "stl:<path>:triangle N") for a missing, empty, truncated or malformed file, for non-finite
/// coordinates and when no non-degenerate triangle remains.
[[nodiscard]] StlMesh readStl(const std::string& path);

/// Parses STL content already in memory; `sourceName` is used in error fields in place of the
/// path. readStl() is a thin wrapper around this.
[[nodiscard]] StlMesh parseStl(std::string_view data, const std::string& sourceName);

/// Writes a binary STL (coordinates rounded to float, header not starting with "solid").
/// Throws InputError for an index out of range, a coordinate that is not finite or does not
/// fit in a float, or a file that cannot be written.
void writeStlBinary(const std::string& path, const std::vector<Vec3>& vertices,
                    const std::vector<std::array<std::uint32_t, 3>>& triangles);

/// Writes an ASCII STL with 17 significant digits (doubles round-trip exactly).
/// Same error handling as writeStlBinary (except the float range check).
void writeStlAscii(const std::string& path, const std::vector<Vec3>& vertices,
                   const std::vector<std::array<std::uint32_t, 3>>& triangles,
                   const std::string& solidName = "demlink");

}  // namespace demlink::core
