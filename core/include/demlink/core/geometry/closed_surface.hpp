#pragma once
/// Whether a triangle mesh bounds a solid: every edge shared by exactly two triangles
/// that run through it in opposite directions.
///
/// Why: a volume, centre of mass or inside test of a mesh is meaningful only for a closed,
/// consistently oriented surface. An open edge (one triangle), a non-manifold edge (three
/// or more) or two neighbours with opposite vertex order would silently give garbage
/// (the divergence theorem counts a flipped triangle with the wrong sign), so they are
/// refused, naming the edge.
#include <string>

#include "demlink/core/geometry/stl_reader.hpp"

namespace demlink::core {

/// Throws InputError (field `field`, the value naming the first bad edge by its two end
/// points and how many edges are bad) when the mesh is not a closed, consistently
/// oriented surface. Vertices must already be merged (readStl does).
void requireClosedSurface(const StlMesh& mesh, const std::string& field);

}  // namespace demlink::core
