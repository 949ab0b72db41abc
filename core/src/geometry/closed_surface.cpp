/// Closed-surface check (closed_surface.hpp): every directed edge (a -> b) of every
/// triangle is listed with its undirected key (min, max); after sorting, each key must
/// occur exactly twice, once in each direction. O(T log T), deterministic.
#include "demlink/core/geometry/closed_surface.hpp"

#include <algorithm>
#include <cstdint>
#include <sstream>
#include <vector>

#include "demlink/core/base/input_error.hpp"

namespace demlink::core {
namespace {

struct DirectedEdge {
  std::uint32_t lo;
  std::uint32_t hi;
  bool forward;  ///< the triangle runs lo -> hi
  std::uint32_t triangle;
};

std::string pointText(const Vec3& p) {
  std::ostringstream os;
  os << "(" << formatValue(p.x()) << ", " << formatValue(p.y()) << ", " << formatValue(p.z()) << ")";
  return os.str();
}

}  // namespace

void requireClosedSurface(const StlMesh& mesh, const std::string& field) {
  std::vector<DirectedEdge> edges;
  edges.reserve(mesh.triangles.size() * 3);
  for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
    const auto& tri = mesh.triangles[t];
    for (std::size_t k = 0; k < 3; ++k) {
      const std::uint32_t a = tri[k];
      const std::uint32_t b = tri[(k + 1) % 3];
      edges.push_back({std::min(a, b), std::max(a, b), a < b, static_cast<std::uint32_t>(t)});
    }
  }
  std::sort(edges.begin(), edges.end(), [](const DirectedEdge& x, const DirectedEdge& y) {
    if (x.lo != y.lo) return x.lo < y.lo;
    if (x.hi != y.hi) return x.hi < y.hi;
    return x.triangle < y.triangle;
  });
  std::size_t open = 0;
  std::size_t nonManifold = 0;
  std::size_t flipped = 0;
  std::string first;
  for (std::size_t begin = 0; begin < edges.size();) {
    std::size_t end = begin + 1;
    while (end < edges.size() && edges[end].lo == edges[begin].lo && edges[end].hi == edges[begin].hi) ++end;
    const std::size_t count = end - begin;
    const std::string edgeText = "edge " + pointText(mesh.vertices[edges[begin].lo]) + " - " +
                                 pointText(mesh.vertices[edges[begin].hi]);
    if (count == 1) {
      ++open;
      if (first.empty()) {
        first = edgeText + " belongs to one triangle only (" + std::to_string(edges[begin].triangle) +
                ", 0-based after dropping degenerate ones): the surface is open";
      }
    } else if (count > 2) {
      ++nonManifold;
      if (first.empty()) {
        first = edgeText + " is shared by " + std::to_string(count) + " triangles: the surface is not a manifold";
      }
    } else if (edges[begin].forward == edges[begin + 1].forward) {
      ++flipped;
      if (first.empty()) {
        first = edgeText + ": triangles " + std::to_string(edges[begin].triangle) + " and " +
                std::to_string(edges[begin + 1].triangle) +
                " run through it in the same direction, so one of them is flipped (inconsistent orientation)";
      }
    }
    begin = end;
  }
  if (open + nonManifold + flipped == 0) return;
  throw InputError(field,
                   std::to_string(open) + " open, " + std::to_string(nonManifold) + " non-manifold, " +
                       std::to_string(flipped) + " inconsistently oriented edges",
                   "not a closed, consistently oriented surface: " + first);
}

}  // namespace demlink::core
