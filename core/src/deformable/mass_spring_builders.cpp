/// Lattice, STL and explicit sources of a mass-spring body (mass_spring_builders.hpp).
#include "mass_spring_builders.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <utility>

#include "demlink/core/base/input_error.hpp"
#include "demlink/core/geometry/stl_reader.hpp"

namespace demlink::core {
namespace {

using Triangle = std::array<std::uint32_t, 3>;

std::string vecText(const Vec3& v) {
  return "(" + formatValue(v.x()) + ", " + formatValue(v.y()) + ", " + formatValue(v.z()) + ")";
}

void requireFiniteVec(const std::string& field, const Vec3& v) {
  if (!v.allFinite()) throw InputError(field, vecText(v), "must be finite");
}

/// Resolves rest lengths (< 0: the initial distance) and checks every spring.
void resolveSprings(std::vector<SpringSpec>& springs, const std::vector<Vec3>& nodes, const std::string& prefix) {
  for (std::size_t s = 0; s < springs.size(); ++s) {
    SpringSpec& spring = springs[s];
    const std::string field = prefix + ".springs[" + std::to_string(s) + "]";
    for (const std::uint32_t node : {spring.a, spring.b}) {
      if (node >= nodes.size()) {
        throw InputError(field, std::to_string(node),
                         "node index out of range (the body has " + std::to_string(nodes.size()) + " nodes)");
      }
    }
    if (spring.a == spring.b) throw InputError(field, std::to_string(spring.a), "a spring joins two distinct nodes");
    requireNonNegative(field + ".stiffness", spring.stiffness);
    requireNonNegative(field + ".damping", spring.damping);
    requireFinite(field + ".rest_length", spring.rest_length);
    if (spring.rest_length < 0.0) {
      spring.rest_length = (nodes[spring.b] - nodes[spring.a]).norm();
      if (!(spring.rest_length > 0.0)) {
        throw InputError(field, std::to_string(spring.a) + ", " + std::to_string(spring.b),
                         "its nodes coincide: give a positive rest_length");
      }
    } else if (spring.rest_length == 0.0) {
      throw InputError(field + ".rest_length", "0", "must be positive (or negative: the initial distance)");
    }
  }
}

/// A box subdivided at node_spacing: structural springs along the axes, shear springs
/// across every cell face's diagonals, bending springs over two cells; triangles on
/// the outer faces (a sheet: one layer, normal along the thin axis).
MassSpringTopology buildLattice(const MassSpringSpec& spec, const std::string& prefix) {
  const MassSpringSpec::Box& box = *spec.box;
  requireFiniteVec(prefix + ".box.lo", box.lo);
  requireFiniteVec(prefix + ".box.hi", box.hi);
  requirePositive(prefix + ".box.node_spacing", box.node_spacing);
  std::array<std::size_t, 3> n{};
  std::array<double, 3> step{};
  int thinAxes = 0;
  double nodeCount = 1.0;
  for (int a = 0; a < 3; ++a) {
    const double extent = box.hi[a] - box.lo[a];
    if (!(extent > 0.0)) {
      throw InputError(prefix + ".box.hi", vecText(box.hi),
                       "must exceed box.lo " + vecText(box.lo) + " in every direction");
    }
    if (extent < box.node_spacing) {
      n[a] = 1;
      ++thinAxes;
    } else {
      const double cells = std::max(1.0, std::round(extent / box.node_spacing));
      if (cells > static_cast<double>(kMaxMassSpringNodes)) {
        throw InputError(prefix + ".box.node_spacing", formatValue(box.node_spacing),
                         "more than " + std::to_string(kMaxMassSpringNodes) + " nodes");
      }
      n[a] = static_cast<std::size_t>(cells) + 1;
      step[a] = extent / cells;
    }
    nodeCount *= static_cast<double>(n[a]);
  }
  if (thinAxes > 1) {
    throw InputError(prefix + ".box.node_spacing", formatValue(box.node_spacing),
                     "the box is thinner than node_spacing in more than one direction (a lattice needs a surface)");
  }
  if (nodeCount > static_cast<double>(kMaxMassSpringNodes)) {
    throw InputError(prefix + ".box.node_spacing", formatValue(box.node_spacing),
                     "gives " + formatValue(nodeCount) + " nodes, more than the " +
                         std::to_string(kMaxMassSpringNodes) + " a mass-spring body may have");
  }
  requirePositive(prefix + ".stiffness", spec.stiffness);
  requireNonNegative(prefix + ".damping", spec.damping);
  requireNonNegative(prefix + ".shear_factor", spec.shear_factor);
  requireNonNegative(prefix + ".bending_factor", spec.bending_factor);

  MassSpringTopology out;
  const auto id = [&](std::size_t i, std::size_t j, std::size_t k) {
    return static_cast<std::uint32_t>(i + n[0] * (j + n[1] * k));
  };
  out.nodes.reserve(n[0] * n[1] * n[2]);
  for (std::size_t k = 0; k < n[2]; ++k) {
    for (std::size_t j = 0; j < n[1]; ++j) {
      for (std::size_t i = 0; i < n[0]; ++i) {
        Vec3 x;
        const std::array<std::size_t, 3> index{i, j, k};
        for (int a = 0; a < 3; ++a) {
          x[a] = n[a] == 1 ? 0.5 * (box.lo[a] + box.hi[a]) : box.lo[a] + static_cast<double>(index[a]) * step[a];
        }
        out.nodes.push_back(x);
      }
    }
  }
  const auto addSpring = [&](std::uint32_t a, std::uint32_t b, double factor) {
    out.springs.push_back({a, b, spec.stiffness * factor, spec.damping * factor, -1.0});
  };
  const auto forEachNode = [&](auto&& visit) {
    for (std::size_t k = 0; k < n[2]; ++k) {
      for (std::size_t j = 0; j < n[1]; ++j) {
        for (std::size_t i = 0; i < n[0]; ++i) visit(std::array<std::size_t, 3>{i, j, k});
      }
    }
  };
  const auto at = [&](std::array<std::size_t, 3> c) { return id(c[0], c[1], c[2]); };
  const auto shifted = [](std::array<std::size_t, 3> c, int axis, std::size_t by) {
    c[static_cast<std::size_t>(axis)] += by;
    return c;
  };
  forEachNode([&](std::array<std::size_t, 3> c) {
    for (int a = 0; a < 3; ++a) {
      if (c[a] + 1 < n[a]) addSpring(at(c), at(shifted(c, a, 1)), 1.0);
    }
  });
  if (spec.shear_factor > 0.0) {
    forEachNode([&](std::array<std::size_t, 3> c) {
      for (int a = 0; a < 3; ++a) {
        const int b = (a + 1) % 3;
        if (c[a] + 1 >= n[a] || c[b] + 1 >= n[b]) continue;
        addSpring(at(c), at(shifted(shifted(c, a, 1), b, 1)), spec.shear_factor);
        addSpring(at(shifted(c, a, 1)), at(shifted(c, b, 1)), spec.shear_factor);
      }
    });
  }
  if (spec.bending_factor > 0.0) {
    forEachNode([&](std::array<std::size_t, 3> c) {
      for (int a = 0; a < 3; ++a) {
        if (c[a] + 2 < n[a]) addSpring(at(c), at(shifted(c, a, 2)), spec.bending_factor);
      }
    });
  }
  // Outer faces: the face normal to axis a at index `layer`, quads over the axes b, c
  // with e_b x e_c = e_a, counter-clockwise seen from outside.
  const auto addFace = [&](int a, std::size_t layer, bool outwardPositive) {
    const int b = (a + 1) % 3;
    const int c = (a + 2) % 3;
    for (std::size_t v = 0; v + 1 < n[c]; ++v) {
      for (std::size_t u = 0; u + 1 < n[b]; ++u) {
        std::array<std::size_t, 3> base{};
        base[a] = layer;
        base[b] = u;
        base[c] = v;
        const std::uint32_t p00 = at(base);
        const std::uint32_t p10 = at(shifted(base, b, 1));
        const std::uint32_t p11 = at(shifted(shifted(base, b, 1), c, 1));
        const std::uint32_t p01 = at(shifted(base, c, 1));
        if (outwardPositive) {
          out.triangles.push_back({p00, p10, p11});
          out.triangles.push_back({p00, p11, p01});
        } else {
          out.triangles.push_back({p00, p11, p10});
          out.triangles.push_back({p00, p01, p11});
        }
      }
    }
  };
  for (int a = 0; a < 3; ++a) {
    if (n[a] == 1) {
      addFace(a, 0, true);  // a sheet: one layer, both sides
    } else if (thinAxes == 0) {
      addFace(a, 0, false);
      addFace(a, n[a] - 1, true);
    }
  }
  return out;
}

/// An STL surface: nodes = its distinct vertices, one structural spring per distinct edge.
MassSpringTopology buildFromStl(const MassSpringSpec& spec, const std::string& prefix) {
  requirePositive(prefix + ".stiffness", spec.stiffness);
  requireNonNegative(prefix + ".damping", spec.damping);
  StlMesh mesh;
  try {
    mesh = readStl(spec.stl_path);
  } catch (const InputError& error) {
    throw error.as(prefix + ".stl_path");
  }
  if (mesh.vertices.size() > kMaxMassSpringNodes) {
    throw InputError(prefix + ".stl_path", spec.stl_path,
                     std::to_string(mesh.vertices.size()) + " vertices, more than the " +
                         std::to_string(kMaxMassSpringNodes) + " nodes a mass-spring body may have");
  }
  MassSpringTopology out;
  out.nodes = std::move(mesh.vertices);
  out.triangles = std::move(mesh.triangles);
  std::map<std::pair<std::uint32_t, std::uint32_t>, bool> seen;
  for (const Triangle& tri : out.triangles) {
    for (int e = 0; e < 3; ++e) {
      const auto edge = std::minmax(tri[e], tri[(e + 1) % 3]);
      if (seen.emplace(edge, true).second) {
        out.springs.push_back({edge.first, edge.second, spec.stiffness, spec.damping, -1.0});
      }
    }
  }
  return out;
}

MassSpringTopology buildExplicit(const MassSpringSpec& spec, const std::string& prefix) {
  if (spec.nodes.size() > kMaxMassSpringNodes) {
    throw InputError(prefix + ".nodes", std::to_string(spec.nodes.size()) + " nodes",
                     "more than the " + std::to_string(kMaxMassSpringNodes) + " a mass-spring body may have");
  }
  for (std::size_t k = 0; k < spec.nodes.size(); ++k) {
    requireFiniteVec(prefix + ".nodes[" + std::to_string(k) + "]", spec.nodes[k]);
  }
  if (spec.springs.empty()) throw InputError(prefix + ".springs", "[]", "explicit nodes need at least one spring");
  return {spec.nodes, spec.springs, spec.triangles};
}

}  // namespace

MassSpringTopology buildMassSpringTopology(const MassSpringSpec& spec, const std::string& fieldPrefix) {
  const int sources = (spec.box ? 1 : 0) + (spec.stl_path.empty() ? 0 : 1) + (spec.nodes.empty() ? 0 : 1);
  if (sources != 1) {
    throw InputError(fieldPrefix, std::to_string(sources) + " sources",
                     "give exactly one of box, stl_path or nodes (with springs)");
  }
  if (spec.nodes.empty() && (!spec.springs.empty() || !spec.triangles.empty())) {
    throw InputError(fieldPrefix + ".springs", std::to_string(spec.springs.size()) + " springs",
                     "explicit springs and triangles need explicit nodes");
  }
  MassSpringTopology out = spec.box                ? buildLattice(spec, fieldPrefix)
                           : !spec.stl_path.empty() ? buildFromStl(spec, fieldPrefix)
                                                    : buildExplicit(spec, fieldPrefix);
  resolveSprings(out.springs, out.nodes, fieldPrefix);
  return out;
}

double MassSpringSpec::Box::nodeCount() const {
  double count = 1.0;
  for (int a = 0; a < 3; ++a) {
    const double extent = hi[a] - lo[a];
    if (!(node_spacing > 0.0) || !std::isfinite(extent / node_spacing)) return std::numeric_limits<double>::infinity();
    // buildLattice's rule: a thin axis is one layer, else round(extent / spacing) cells
    // (a box it refuses for other reasons counts as one layer there).
    count *= !(extent >= node_spacing) ? 1.0 : std::max(1.0, std::round(extent / node_spacing)) + 1.0;
  }
  return count;
}

}  // namespace demlink::core
