/// See gmsh_reader.hpp. Both formats are read section by section; node tags may be sparse
/// and are mapped through a hash map, so a huge tag costs no memory.
#include "demlink/core/deformable/gmsh_reader.hpp"

#include <array>
#include <unordered_map>

#include "demlink/core/deformable/text_lines.hpp"

namespace demlink::core {
namespace {

/// Nodes per element of the Gmsh element types a mesh file commonly holds; 0 = unknown.
std::size_t gmshNodeCount(std::uint64_t type) {
  // Element type -> nodes: line, triangle, quadrangle, tetrahedron, hexahedron, prism, pyramid,
  // their second-order forms (8..14), the point (15), the incomplete second-order forms (16..19)
  // and 4- to 6-node lines (26..28).
  constexpr std::array<std::pair<std::uint64_t, std::size_t>, 22> kNodes = {{
      {1, 2},  {2, 3},   {3, 4},   {4, 4},   {5, 8},   {6, 6},   {7, 5},   {8, 3},   {9, 6},  {10, 9}, {11, 10},
      {12, 27}, {13, 18}, {14, 14}, {15, 1}, {16, 8}, {17, 20}, {18, 15}, {19, 13}, {26, 4}, {27, 5}, {28, 6},
  }};
  for (const auto& [t, n] : kNodes) {
    if (t == type) return n;
  }
  return 0;
}

bool isPointOrLine(std::uint64_t type) {
  return type == 1 || type == 8 || type == 15 || (type >= 26 && type <= 28);
}

class GmshParser {
 public:
  GmshParser(std::string_view text, const std::string& source) : in_(text, "msh", source) {}

  TetMesh run() {
    std::string_view line;
    bool sawFormat = false;
    bool sawNodes = false;
    bool sawElements = false;
    while (in_.next(line)) {
      const auto tok = in_.tokens(line);
      if (tok.empty()) continue;
      if (tok[0] == "$MeshFormat") {
        readFormat();
        sawFormat = true;
      } else if (tok[0] == "$Nodes") {
        if (!sawFormat) in_.fail("$Nodes before $MeshFormat");
        version4_ ? readNodes4() : readNodes2();
        sawNodes = true;
      } else if (tok[0] == "$Elements") {
        if (!sawNodes) in_.fail("$Elements before $Nodes");
        version4_ ? readElements4() : readElements2();
        sawElements = true;
      } else if (tok[0].starts_with("$")) {
        skipSection(tok[0]);
      } else {
        in_.fail("expected a section header such as $MeshFormat");
      }
    }
    if (!sawFormat) in_.failFile("no $MeshFormat", "not a Gmsh .msh file");
    if (!sawElements) in_.failFile("no $Elements", "the file has no elements");
    return finish();
  }

 private:
  void readFormat() {
    const auto tok = in_.tokens(in_.expectLine("the format line 'version file-type data-size'"));
    if (tok.size() < 3) in_.fail("the format line needs version, file-type and data-size");
    if (tok[0] == "2.2") {
      version4_ = false;
    } else if (tok[0] == "4.1") {
      version4_ = true;
    } else {
      in_.fail("unsupported .msh version (2.2 and 4.1 are read; save the mesh in one of them)");
    }
    if (tok[1] != "0") in_.fail("binary .msh files are not read (save as ASCII)");
    expectEnd("$EndMeshFormat");
  }

  void expectEnd(std::string_view end) {
    const auto tok = in_.tokens(in_.expectLine(std::string(end)));
    if (tok.size() != 1 || tok[0] != end) in_.fail("expected " + std::string(end));
  }

  void skipSection(std::string_view begin) {
    const std::string end = "$End" + std::string(begin.substr(1));
    std::string_view line;
    while (in_.next(line)) {
      const auto tok = in_.tokens(line);
      if (!tok.empty() && tok[0] == end) return;
    }
    in_.fail("unexpected end of file: expected " + end);
  }

  void addNode(std::uint64_t tag, const Vec3& x) {
    if (!tags_.emplace(tag, static_cast<std::uint32_t>(nodes_.size())).second) {
      in_.fail("node tag " + std::to_string(tag) + " defined twice");
    }
    nodes_.push_back(x);
    fileTags_.push_back(tag);
  }

  Vec3 coordinates(const std::vector<std::string_view>& tok, std::size_t first) {
    return {in_.toReal(tok[first], "x"), in_.toReal(tok[first + 1], "y"), in_.toReal(tok[first + 2], "z")};
  }

  void readNodes2() {
    const auto head = in_.tokens(in_.expectLine("the node count"));
    if (head.size() != 1) in_.fail("expected the node count");
    const std::uint64_t count = in_.toCount(head[0], "node count");
    in_.requireFits(count, 8, "$Nodes");
    nodes_.reserve(static_cast<std::size_t>(count));
    for (std::uint64_t i = 0; i < count; ++i) {
      const auto tok = in_.tokens(in_.expectLine("a node line 'tag x y z'"));
      if (tok.size() != 4) in_.fail("a node line needs 'tag x y z'");
      addNode(in_.toCount(tok[0], "node tag"), coordinates(tok, 1));
    }
    expectEnd("$EndNodes");
  }

  /// A line of four counts, a format 4.1 section or block header; `names` names them.
  std::array<std::uint64_t, 4> fourCounts(const std::string& names) {
    const auto tok = in_.tokens(in_.expectLine("'" + names + "'"));
    if (tok.size() != 4) in_.fail("expected '" + names + "'");
    std::array<std::uint64_t, 4> out{};
    for (std::size_t k = 0; k < 4; ++k)
      out[k] = in_.toCount(tok[k], "field " + std::to_string(k + 1) + " of '" + names + "'");
    return out;
  }

  void readNodes4() {
    const auto [blocks, count, minTag, maxTag] = fourCounts("numEntityBlocks numNodes minNodeTag maxNodeTag");
    in_.requireFits(blocks, 8, "$Nodes entity blocks");
    in_.requireFits(count, 8, "$Nodes");
    nodes_.reserve(static_cast<std::size_t>(count));
    std::uint64_t total = 0;
    for (std::uint64_t b = 0; b < blocks; ++b) {
      const auto [dim, entity, parametric, n] = fourCounts("entityDim entityTag parametric numNodesInBlock");
      in_.requireFits(n, 8, "node block");
      total += n;
      if (total > count) in_.fail("the node blocks hold more nodes than the header's numNodes");
      std::vector<std::uint64_t> blockTags(static_cast<std::size_t>(n));
      for (auto& tag : blockTags) {
        const auto tok = in_.tokens(in_.expectLine("a node tag"));
        if (tok.size() != 1) in_.fail("expected one node tag per line");
        tag = in_.toCount(tok[0], "node tag");
      }
      for (const std::uint64_t tag : blockTags) {
        const auto tok = in_.tokens(in_.expectLine("node coordinates"));
        if (tok.size() < 3 || (parametric == 0 && tok.size() != 3)) in_.fail("expected 'x y z'");
        addNode(tag, coordinates(tok, 0));
      }
    }
    if (total != count) in_.fail("the node blocks hold fewer nodes than the header's numNodes");
    expectEnd("$EndNodes");
  }

  /// One element of `type` with Gmsh node tags `tags` (one per node of the type).
  void addElement(std::uint64_t type, const std::vector<std::string_view>& tags) {
    if (isPointOrLine(type)) return;
    std::size_t order = 0;
    bool volume = false;
    if (type == 4 || type == 11) {
      order = type == 4 ? 1 : 2;
      volume = true;
    } else if (type == 2 || type == 9) {
      order = type == 2 ? 1 : 2;
    } else {
      in_.fail("unsupported element type " + std::to_string(type) +
               " (read: 4 and 11 tetrahedra, 2 and 9 triangles, points and lines)");
    }
    if (volume) {
      if (order_ != 0 && order_ != order) in_.fail("linear and quadratic tetrahedra in one mesh");
      order_ = order;
    }
    std::vector<std::uint32_t>& out = volume ? tets_ : faces_;
    if (!volume) faceOrders_.push_back(static_cast<std::uint8_t>(order));
    for (std::size_t k = 0; k < tags.size(); ++k) {
      // Gmsh numbers the mid-edge nodes of edges (2,3) and (1,3) as 8 and 9, VTK the other way round.
      const std::size_t src = (volume && order == 2 && (k == 8 || k == 9)) ? 17 - k : k;
      const std::uint64_t tag = in_.toCount(tags[src], "node tag");
      const auto it = tags_.find(tag);
      if (it == tags_.end())
        in_.fail("element refers to node tag " + std::to_string(tag) + ", not in $Nodes");
      out.push_back(it->second);
    }
    if (volume) orient(order);
  }

  /// Turns a negatively oriented tetrahedron over; refuses a flat one.
  void orient(std::size_t order) {
    const std::size_t npt = order == 2 ? 10 : 4;
    std::uint32_t* t = &tets_[tets_.size() - npt];
    const Vec3& x0 = nodes_[t[0]];
    const double det = (nodes_[t[1]] - x0).cross(nodes_[t[2]] - x0).dot(nodes_[t[3]] - x0);
    const double scale = (nodes_[t[1]] - x0).norm() * (nodes_[t[2]] - x0).norm() * (nodes_[t[3]] - x0).norm();
    if (!(std::abs(det) > 1e-12 * scale)) in_.fail("flat tetrahedron (zero volume)");
    if (det < 0.0) {
      std::swap(t[1], t[2]);
      if (order == 2) {
        std::swap(t[4], t[6]);  // (0,1) <-> (0,2)
        std::swap(t[8], t[9]);  // (1,3) <-> (2,3)
      }
    }
  }

  void readElements2() {
    const auto head = in_.tokens(in_.expectLine("the element count"));
    if (head.size() != 1) in_.fail("expected the element count");
    const std::uint64_t count = in_.toCount(head[0], "element count");
    in_.requireFits(count, 8, "$Elements");
    for (std::uint64_t i = 0; i < count; ++i) {
      const auto tok = in_.tokens(in_.expectLine("an element line"));
      if (tok.size() < 3) in_.fail("an element line needs 'tag type numTags ...'");
      const std::uint64_t type = in_.toCount(tok[1], "element type");
      const std::uint64_t numTags = in_.toCount(tok[2], "number of tags");
      const std::size_t nodes = gmshNodeCount(type);
      if (nodes == 0) in_.fail("unsupported element type " + std::to_string(type));
      if (numTags > tok.size() || tok.size() != 3 + numTags + nodes) {
        in_.fail("element type " + std::to_string(type) + " needs " + std::to_string(nodes) + " node tags");
      }
      addElement(type, {tok.begin() + static_cast<long>(3 + numTags), tok.end()});
    }
    expectEnd("$EndElements");
  }

  void readElements4() {
    const auto [blocks, count, minTag, maxTag] =
        fourCounts("numEntityBlocks numElements minElementTag maxElementTag");
    in_.requireFits(blocks, 8, "$Elements entity blocks");
    in_.requireFits(count, 4, "$Elements");
    std::uint64_t total = 0;
    for (std::uint64_t b = 0; b < blocks; ++b) {
      const auto [dim, entity, type, n] = fourCounts("entityDim entityTag elementType numElementsInBlock");
      const std::size_t nodes = gmshNodeCount(type);
      if (nodes == 0) in_.fail("unsupported element type " + std::to_string(type));
      in_.requireFits(n, 4, "element block");
      total += n;
      if (total > count) in_.fail("the element blocks hold more elements than the header's numElements");
      for (std::uint64_t i = 0; i < n; ++i) {
        const auto tok = in_.tokens(in_.expectLine("an element line"));
        if (tok.size() != 1 + nodes) {
          in_.fail("element type " + std::to_string(type) + " needs a tag and " + std::to_string(nodes) +
                   " node tags");
        }
        addElement(type, {tok.begin() + 1, tok.end()});
      }
    }
    if (total != count) in_.fail("the element blocks hold fewer elements than the header's numElements");
    expectEnd("$EndElements");
  }

  TetMesh finish() {
    if (tets_.empty()) in_.failFile("0 tetrahedra", "the mesh has no tetrahedra (element type 4 or 11)");
    TetMesh mesh;
    mesh.order = static_cast<int>(order_);
    // Keep only nodes used by tetrahedra, in file order.
    std::vector<std::uint32_t> newIndex(nodes_.size(), UINT32_MAX);
    for (const std::uint32_t n : tets_) newIndex[n] = 0;
    for (std::size_t i = 0; i < nodes_.size(); ++i) {
      if (newIndex[i] == 0) {
        newIndex[i] = static_cast<std::uint32_t>(mesh.nodes.size());
        mesh.nodes.push_back(nodes_[i]);
        mesh.tags.push_back(fileTags_[i]);
      }
    }
    mesh.tets.reserve(tets_.size());
    for (const std::uint32_t n : tets_) mesh.tets.push_back(newIndex[n]);
    // Faces of the tetrahedra's order whose nodes all belong to tetrahedra.
    const std::size_t npf = mesh.nodesPerFace();
    for (std::size_t f = 0, at = 0; f < faceOrders_.size(); ++f) {
      const std::size_t n = faceOrders_[f] == 2 ? 6 : 3;
      bool keep = n == npf;
      for (std::size_t k = 0; keep && k < n; ++k) keep = newIndex[faces_[at + k]] != UINT32_MAX;
      for (std::size_t k = 0; keep && k < n; ++k) mesh.faces.push_back(newIndex[faces_[at + k]]);
      at += n;
    }
    return mesh;
  }

  TextLines in_;
  bool version4_ = false;
  std::size_t order_ = 0;
  std::unordered_map<std::uint64_t, std::uint32_t> tags_;
  std::vector<Vec3> nodes_;
  std::vector<std::uint64_t> fileTags_;
  std::vector<std::uint32_t> tets_;
  std::vector<std::uint32_t> faces_;
  std::vector<std::uint8_t> faceOrders_;
};

}  // namespace

TetMesh parseGmsh(std::string_view text, const std::string& source) { return GmshParser(text, source).run(); }

TetMesh readGmsh(const std::string& path) { return parseGmsh(loadTextFile(path, "msh"), path); }

}  // namespace demlink::core
