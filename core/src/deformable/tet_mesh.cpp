/// See tet_mesh.hpp.
#include "demlink/core/deformable/tet_mesh.hpp"

#include <algorithm>
#include <fstream>
#include <map>
#include <stdexcept>

#include "demlink/core/base/input_error.hpp"

namespace demlink::core {
namespace {

/// Outward faces of a positively oriented tetrahedron: corner triples, and for quadratic
/// elements the mid-edge nodes of the face's edges (a,b), (b,c), (c,a) in VTK numbering.
constexpr std::array<std::array<int, 6>, 4> kFaces = {{
    {0, 2, 1, 6, 5, 4},
    {0, 1, 3, 4, 8, 7},
    {0, 3, 2, 7, 9, 6},
    {1, 2, 3, 5, 9, 8},
}};

std::array<std::uint32_t, 3> sortedCorners(const std::uint32_t* f) {
  std::array<std::uint32_t, 3> key = {f[0], f[1], f[2]};
  std::sort(key.begin(), key.end());
  return key;
}

}  // namespace

std::vector<std::uint32_t> boundaryFaces(const TetMesh& mesh) {
  const std::size_t npt = mesh.nodesPerTet();
  const std::size_t npf = mesh.nodesPerFace();
  std::vector<std::pair<std::array<std::uint32_t, 3>, std::array<std::uint32_t, 6>>> all;
  all.reserve(mesh.tetCount() * 4);
  for (std::size_t e = 0; e < mesh.tetCount(); ++e) {
    const std::uint32_t* t = &mesh.tets[e * npt];
    for (const auto& f : kFaces) {
      std::array<std::uint32_t, 6> face{};
      for (std::size_t k = 0; k < npf; ++k) face[k] = t[f[k]];
      all.emplace_back(sortedCorners(face.data()), face);
    }
  }
  std::sort(all.begin(), all.end());
  std::vector<std::uint32_t> out;
  for (std::size_t i = 0; i < all.size();) {
    std::size_t j = i + 1;
    while (j < all.size() && all[j].first == all[i].first) ++j;
    if (j - i == 1)
      out.insert(out.end(), all[i].second.begin(), all[i].second.begin() + static_cast<long>(npf));
    i = j;
  }
  return out;
}

std::vector<std::array<std::uint32_t, 3>> surfaceTriangles(const TetMesh& mesh) {
  const std::size_t npf = mesh.nodesPerFace();
  std::vector<std::uint32_t> faces = boundaryFaces(mesh);
  if (!mesh.faces.empty()) {
    std::map<std::array<std::uint32_t, 3>, std::size_t> outward;
    for (std::size_t f = 0; f * npf < faces.size(); ++f) outward.emplace(sortedCorners(&faces[f * npf]), f);
    std::vector<std::uint32_t> given = mesh.faces;
    for (std::size_t f = 0; f * npf < given.size(); ++f) {
      const auto it = outward.find(sortedCorners(&given[f * npf]));
      if (it != outward.end()) {
        std::copy_n(faces.begin() + static_cast<long>(it->second * npf), npf,
                    given.begin() + static_cast<long>(f * npf));
      }
    }
    faces = std::move(given);
  }
  std::vector<std::array<std::uint32_t, 3>> out;
  for (std::size_t f = 0; f * npf < faces.size(); ++f) {
    const std::uint32_t* n = &faces[f * npf];
    if (npf == 3) {
      out.push_back({n[0], n[1], n[2]});
    } else {
      out.push_back({n[0], n[3], n[5]});
      out.push_back({n[3], n[1], n[4]});
      out.push_back({n[5], n[4], n[2]});
      out.push_back({n[3], n[4], n[5]});
    }
  }
  return out;
}

TetMesh boxTetMesh(const Vec3& lo, const Vec3& hi, int nx, int ny, int nz, int order) {
  if (nx < 1 || ny < 1 || nz < 1 || (order != 1 && order != 2)) {
    throw std::invalid_argument("boxTetMesh: cells must be >= 1 and order 1 or 2");
  }
  TetMesh mesh;
  mesh.order = order;
  const auto index = [&](int i, int j, int k) {
    return static_cast<std::uint32_t>((k * (ny + 1) + j) * (nx + 1) + i);
  };
  for (int k = 0; k <= nz; ++k) {
    for (int j = 0; j <= ny; ++j) {
      for (int i = 0; i <= nx; ++i) {
        mesh.nodes.emplace_back(lo.x() + (hi.x() - lo.x()) * i / nx, lo.y() + (hi.y() - lo.y()) * j / ny,
                                lo.z() + (hi.z() - lo.z()) * k / nz);
      }
    }
  }
  // Kuhn split of the unit cube: 6 tetrahedra along the diagonal (0,0,0)-(1,1,1), one per
  // permutation of the axes; every cell is cut the same way, so faces match between cells.
  constexpr std::array<std::array<int, 3>, 6> kPerms = {
      {{0, 1, 2}, {0, 2, 1}, {1, 0, 2}, {1, 2, 0}, {2, 0, 1}, {2, 1, 0}}};
  std::map<std::pair<std::uint32_t, std::uint32_t>, std::uint32_t> midNodes;
  const auto mid = [&](std::uint32_t a, std::uint32_t b) {
    const auto key = std::minmax(a, b);
    const auto [it, inserted] = midNodes.emplace(key, static_cast<std::uint32_t>(mesh.nodes.size()));
    if (inserted) mesh.nodes.push_back(0.5 * (mesh.nodes[a] + mesh.nodes[b]));
    return it->second;
  };
  for (int k = 0; k < nz; ++k) {
    for (int j = 0; j < ny; ++j) {
      for (int i = 0; i < nx; ++i) {
        for (const auto& p : kPerms) {
          std::array<int, 3> c = {i, j, k};
          std::array<std::uint32_t, 4> t{};
          t[0] = index(c[0], c[1], c[2]);
          for (int s = 0; s < 3; ++s) {
            ++c[static_cast<std::size_t>(p[static_cast<std::size_t>(s)])];
            t[static_cast<std::size_t>(s) + 1] = index(c[0], c[1], c[2]);
          }
          const Vec3& x0 = mesh.nodes[t[0]];
          if ((mesh.nodes[t[1]] - x0).cross(mesh.nodes[t[2]] - x0).dot(mesh.nodes[t[3]] - x0) < 0.0) {
            std::swap(t[1], t[2]);
          }
          mesh.tets.insert(mesh.tets.end(), t.begin(), t.end());
          if (order == 2) {
            const std::array<std::uint32_t, 6> m = {mid(t[0], t[1]), mid(t[1], t[2]), mid(t[0], t[2]),
                                                    mid(t[0], t[3]), mid(t[1], t[3]), mid(t[2], t[3])};
            mesh.tets.insert(mesh.tets.end(), m.begin(), m.end());
          }
        }
      }
    }
  }
  return mesh;
}

void writeGmsh(const std::string& path, const TetMesh& mesh, const std::string& version) {
  if (version != "2.2" && version != "4.1") throw InputError("gmsh version", version, "must be 2.2 or 4.1");
  std::ofstream out(path);
  if (!out) throw InputError("msh:" + path, path, "cannot be opened for writing");
  out.precision(17);
  const std::size_t npt = mesh.nodesPerTet();
  const std::size_t npf = mesh.nodesPerFace();
  const int tetType = mesh.order == 2 ? 11 : 4;
  const int triType = mesh.order == 2 ? 9 : 2;
  // VTK -> Gmsh node order: swap the mid-edge nodes of edges (1,3) and (2,3).
  const auto gmshNode = [&](const std::uint32_t* t, std::size_t k) {
    if (npt == 10 && k == 8) return t[9];
    if (npt == 10 && k == 9) return t[8];
    return t[k];
  };
  const std::size_t nFaces = mesh.faces.size() / npf;
  const std::size_t nTets = mesh.tetCount();
  out << "$MeshFormat\n" << version << " 0 8\n$EndMeshFormat\n";
  if (version == "2.2") {
    out << "$Nodes\n" << mesh.nodes.size() << "\n";
    for (std::size_t i = 0; i < mesh.nodes.size(); ++i) {
      out << i + 1 << ' ' << mesh.nodes[i].x() << ' ' << mesh.nodes[i].y() << ' ' << mesh.nodes[i].z()
          << "\n";
    }
    out << "$EndNodes\n$Elements\n" << nFaces + nTets << "\n";
    std::size_t tag = 1;
    for (std::size_t f = 0; f < nFaces; ++f) {
      out << tag++ << ' ' << triType << " 2 1 1";
      for (std::size_t k = 0; k < npf; ++k) out << ' ' << mesh.faces[f * npf + k] + 1;
      out << "\n";
    }
    for (std::size_t e = 0; e < nTets; ++e) {
      out << tag++ << ' ' << tetType << " 2 2 1";
      for (std::size_t k = 0; k < npt; ++k) out << ' ' << gmshNode(&mesh.tets[e * npt], k) + 1;
      out << "\n";
    }
    out << "$EndElements\n";
  } else {
    out << "$Nodes\n1 " << mesh.nodes.size() << " 1 " << mesh.nodes.size() << "\n3 1 0 " << mesh.nodes.size()
        << "\n";
    for (std::size_t i = 0; i < mesh.nodes.size(); ++i) out << i + 1 << "\n";
    for (const Vec3& x : mesh.nodes) out << x.x() << ' ' << x.y() << ' ' << x.z() << "\n";
    const std::size_t blocks = (nFaces > 0 ? 1 : 0) + 1;
    out << "$EndNodes\n$Elements\n" << blocks << ' ' << nFaces + nTets << " 1 " << nFaces + nTets << "\n";
    std::size_t tag = 1;
    if (nFaces > 0) {
      out << "2 1 " << triType << ' ' << nFaces << "\n";
      for (std::size_t f = 0; f < nFaces; ++f) {
        out << tag++;
        for (std::size_t k = 0; k < npf; ++k) out << ' ' << mesh.faces[f * npf + k] + 1;
        out << "\n";
      }
    }
    out << "3 1 " << tetType << ' ' << nTets << "\n";
    for (std::size_t e = 0; e < nTets; ++e) {
      out << tag++;
      for (std::size_t k = 0; k < npt; ++k) out << ' ' << gmshNode(&mesh.tets[e * npt], k) + 1;
      out << "\n";
    }
    out << "$EndElements\n";
  }
  if (!out) throw InputError("msh:" + path, path, "write failed");
}

}  // namespace demlink::core
