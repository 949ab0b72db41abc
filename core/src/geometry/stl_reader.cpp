/// STL reading/writing; see stl_reader.hpp for the format-detection and merging rules.
///
/// Robustness: the whole file is read into memory and parsed with explicit bounds checks, so
/// garbage input can only produce an InputError, never an out-of-bounds read or a hang (the
/// ASCII lexer advances by at least one byte per token). Binary fields are decoded byte by byte
/// as little-endian, independent of the host byte order.
/// Vertex merging sorts the 3*N facet corners lexicographically by (x, y, z) and collapses runs
/// of exactly equal coordinates: O(N log N), deterministic, no hashing of floating-point keys.
#include "demlink/core/geometry/stl_reader.hpp"

#include <algorithm>
#include <bit>
#include <cctype>
#include <charconv>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <limits>
#include <locale>
#include <numeric>
#include <sstream>

#include "demlink/core/base/input_error.hpp"
#include "demlink/core/base/input_file.hpp"

namespace demlink::core {
namespace {

constexpr std::size_t kHeaderBytes = 84;
constexpr std::size_t kFacetBytes = 50;
constexpr std::size_t kMaxListedDegenerate = 1000;  ///< individual warnings; then a summary

bool isSpace(char ch) {
  return ch == ' ' || ch == '\t' || ch == '\n' || ch == '\r' || ch == '\v' || ch == '\f';
}

/// True when no byte is a NUL/control byte other than whitespace (UTF-8 bytes are allowed).
bool looksLikeText(std::string_view data) {
  return std::all_of(data.begin(), data.end(), [](char ch) {
    const auto u = static_cast<unsigned char>(ch);
    return isSpace(ch) || (u >= 0x20 && u != 0x7F);
  });
}

bool equalsIgnoreCase(std::string_view a, std::string_view b) {
  if (a.size() != b.size()) return false;
  for (std::size_t i = 0; i < a.size(); ++i) {
    const auto x = static_cast<unsigned char>(a[i]);
    const auto y = static_cast<unsigned char>(b[i]);
    if (std::tolower(x) != std::tolower(y)) return false;
  }
  return true;
}

std::uint32_t readLe32(std::string_view data, std::size_t offset) {
  std::uint32_t v = 0;
  for (std::size_t k = 0; k < 4; ++k) {
    v |= static_cast<std::uint32_t>(static_cast<unsigned char>(data[offset + k])) << (8 * k);
  }
  return v;
}

void appendLe32(std::string& out, std::uint32_t v) {
  for (int k = 0; k < 4; ++k) out.push_back(static_cast<char>((v >> (8 * k)) & 0xFFu));
}

void parseBinary(std::string_view data, const std::string& field, std::vector<Vec3>& corners) {
  const std::uint32_t count = readLe32(data, 80);
  corners.reserve(std::size_t{count} * 3);
  for (std::size_t t = 0; t < count; ++t) {
    const std::size_t facet = kHeaderBytes + kFacetBytes * t + 12;  // skip the facet normal
    for (std::size_t k = 0; k < 3; ++k) {
      Vec3 v;
      for (std::size_t d = 0; d < 3; ++d) {
        const float f = std::bit_cast<float>(readLe32(data, facet + 12 * k + 4 * d));
        v[static_cast<Eigen::Index>(d)] = static_cast<double>(f);
      }
      if (!v.allFinite()) {
        const double bad = !std::isfinite(v.x()) ? v.x() : (!std::isfinite(v.y()) ? v.y() : v.z());
        throw InputError(field + ":triangle " + std::to_string(t), formatValue(bad),
                         "vertex " + std::to_string(k) + " has a non-finite coordinate");
      }
      corners.push_back(v);
    }
  }
}

/// Whitespace-separated tokens with line numbers. An empty token means end of input.
class Lexer {
 public:
  struct Token {
    std::string_view text;
    std::size_t line;
  };
  explicit Lexer(std::string_view text) : text_(text) {}

  Token next() {
    while (pos_ < text_.size() && isSpace(text_[pos_])) {
      if (text_[pos_] == '\n') ++line_;
      ++pos_;
    }
    const std::size_t start = pos_;
    while (pos_ < text_.size() && !isSpace(text_[pos_])) ++pos_;
    return {text_.substr(start, pos_ - start), line_};
  }
  void skipRestOfLine() {
    while (pos_ < text_.size() && text_[pos_] != '\n') ++pos_;
  }

 private:
  std::string_view text_;
  std::size_t pos_ = 0;
  std::size_t line_ = 1;
};

class AsciiParser {
 public:
  AsciiParser(std::string_view text, std::string field, std::vector<Vec3>& corners,
              std::vector<std::string>& warnings)
      : lex_(text), field_(std::move(field)), corners_(corners), warnings_(warnings) {}

  void run() {
    expect(lex_.next(), "solid");
    for (;;) {
      lex_.skipRestOfLine();  // solid name
      if (!parseFacets()) return;
      lex_.skipRestOfLine();  // endsolid name
      const Lexer::Token t = lex_.next();
      if (t.text.empty()) return;
      expect(t, "solid");  // several solids may follow each other
    }
  }

 private:
  [[noreturn]] void fail(const Lexer::Token& t, const std::string& reason) const {
    // The file's words are never quoted (a server file named by a client must not leak
    // into its error): the place and what was expected say enough.
    throw InputError(field_ + ":line " + std::to_string(t.line),
                     t.text.empty() ? std::string("<end of file>") : "a word of " + std::to_string(t.text.size()) +
                                                                         " characters",
                     reason);
  }
  void expect(const Lexer::Token& t, std::string_view keyword) const {
    if (!equalsIgnoreCase(t.text, keyword)) {
      fail(t, "expected keyword '" + std::string(keyword) + "'");
    }
  }
  double number(bool mustBeFinite) {
    const Lexer::Token t = lex_.next();
    std::string_view s = t.text;
    if (s.size() > 1 && s[0] == '+' && s[1] != '-') s.remove_prefix(1);
    double v = 0.0;
    const auto [end, ec] = std::from_chars(s.data(), s.data() + s.size(), v);
    if (s.empty() || ec != std::errc() || end != s.data() + s.size()) {
      fail(t, "expected a number");
    }
    if (mustBeFinite && !std::isfinite(v)) fail(t, "vertex coordinate must be finite");
    return v;
  }
  /// Parses facets up to 'endsolid'. Returns false at end of file (missing 'endsolid').
  bool parseFacets() {
    for (;;) {
      Lexer::Token t = lex_.next();
      if (t.text.empty()) {
        warnings_.push_back(field_ + ":line " + std::to_string(t.line) +
                            ": missing 'endsolid' at end of file");
        return false;
      }
      if (equalsIgnoreCase(t.text, "endsolid")) return true;
      expect(t, "facet");
      expect(lex_.next(), "normal");
      for (int k = 0; k < 3; ++k) (void)number(false);  // file normals are ignored
      expect(lex_.next(), "outer");
      expect(lex_.next(), "loop");
      for (int k = 0; k < 3; ++k) {
        t = lex_.next();
        if (equalsIgnoreCase(t.text, "endloop")) {
          fail(t, "facet has " + std::to_string(k) + " vertices, expected 3");
        }
        expect(t, "vertex");
        const double x = number(true);
        const double y = number(true);
        const double z = number(true);
        corners_.emplace_back(x, y, z);
      }
      t = lex_.next();
      if (equalsIgnoreCase(t.text, "vertex")) fail(t, "facet has more than 3 vertices");
      expect(t, "endloop");
      expect(lex_.next(), "endfacet");
    }
  }

  Lexer lex_;
  std::string field_;
  std::vector<Vec3>& corners_;
  std::vector<std::string>& warnings_;
};

/// Merges identical corners, drops degenerate triangles and compacts the vertex list.
void buildMesh(const std::vector<Vec3>& corners, const std::string& field, StlMesh& mesh) {
  const std::size_t nTri = corners.size() / 3;
  if (nTri == 0) throw InputError(field, "0 triangles", "the STL file contains no triangles");
  if (corners.size() > std::numeric_limits<std::uint32_t>::max()) {
    throw InputError(field, std::to_string(nTri) + " triangles", "too many triangles");
  }
  // rep[i] = lowest corner index with exactly the same coordinates as corner i.
  std::vector<std::uint32_t> order(corners.size());
  std::iota(order.begin(), order.end(), 0u);
  const auto lexLess = [&](std::uint32_t i, std::uint32_t j) {
    const Vec3& p = corners[i];
    const Vec3& q = corners[j];
    if (p.x() != q.x()) return p.x() < q.x();
    if (p.y() != q.y()) return p.y() < q.y();
    if (p.z() != q.z()) return p.z() < q.z();
    return i < j;
  };
  std::sort(order.begin(), order.end(), lexLess);
  std::vector<std::uint32_t> rep(corners.size());
  for (std::size_t k = 0; k < order.size(); ++k) {
    const bool sameAsPrev = k > 0 && corners[order[k]] == corners[order[k - 1]];
    rep[order[k]] = sameAsPrev ? rep[order[k - 1]] : order[k];
  }

  Vec3 lo = corners[0];
  Vec3 hi = corners[0];
  for (const Vec3& c : corners) {
    lo = lo.cwiseMin(c);
    hi = hi.cwiseMax(c);
  }
  const double diag2 = (hi - lo).squaredNorm();
  if (!std::isfinite(diag2)) {
    throw InputError(field, formatValue(diag2), "coordinates too large (bounding box overflows)");
  }
  const double minArea = kStlDegenerateAreaFactor * diag2;

  std::size_t dropped = 0;
  const auto drop = [&](std::size_t t, const std::string& why) {
    if (++dropped <= kMaxListedDegenerate) {
      mesh.warnings.push_back("triangle " + std::to_string(t) +
                              " (0-based, file order) dropped: " + why);
    }
  };
  std::vector<std::uint32_t> newId(corners.size(), std::numeric_limits<std::uint32_t>::max());
  for (std::size_t t = 0; t < nTri; ++t) {
    const std::uint32_t r[3] = {rep[3 * t], rep[3 * t + 1], rep[3 * t + 2]};
    if (r[0] == r[1] || r[1] == r[2] || r[0] == r[2]) {
      drop(t, "repeated vertex (degenerate)");
      continue;
    }
    const double area =
        0.5 * (corners[r[1]] - corners[r[0]]).cross(corners[r[2]] - corners[r[0]]).norm();
    if (!(area > 0.0) || area < minArea) {
      drop(t, "area " + formatValue(area) + " below 1e-12 * bounding-box diagonal^2 (degenerate)");
      continue;
    }
    std::array<std::uint32_t, 3> tri{};
    for (int k = 0; k < 3; ++k) {
      if (newId[r[k]] == std::numeric_limits<std::uint32_t>::max()) {
        newId[r[k]] = static_cast<std::uint32_t>(mesh.vertices.size());
        mesh.vertices.push_back(corners[r[k]]);
      }
      tri[static_cast<std::size_t>(k)] = newId[r[k]];
    }
    mesh.triangles.push_back(tri);
  }
  if (dropped > kMaxListedDegenerate) {
    mesh.warnings.push_back(std::to_string(dropped) +
                            " degenerate triangles dropped in total (first " +
                            std::to_string(kMaxListedDegenerate) + " listed)");
  }
  if (mesh.triangles.empty()) {
    throw InputError(field, std::to_string(nTri) + " triangles", "all triangles are degenerate");
  }
}

void validateForWrite(const std::string& field, const std::vector<Vec3>& vertices,
                      const std::vector<std::array<std::uint32_t, 3>>& triangles, bool floatRange) {
  for (std::size_t i = 0; i < vertices.size(); ++i) {
    const double m = vertices[i].cwiseAbs().maxCoeff();
    const bool ok =
        floatRange ? m <= static_cast<double>(std::numeric_limits<float>::max()) : std::isfinite(m);
    if (!ok) {
      throw InputError(field + ":vertices[" + std::to_string(i) + "]", formatValue(m),
                       "coordinate not finite or out of range");
    }
  }
  for (std::size_t t = 0; t < triangles.size(); ++t) {
    for (const std::uint32_t idx : triangles[t]) {
      if (idx >= vertices.size()) {
        throw InputError(field + ":triangles[" + std::to_string(t) + "]", std::to_string(idx),
                         "vertex index out of range");
      }
    }
  }
}

Vec3 unitNormal(const Vec3& a, const Vec3& b, const Vec3& c) {
  const Vec3 n = (b - a).cross(c - a);
  const double len = n.norm();
  return len > 0.0 ? Vec3(n / len) : Vec3::Zero();
}

void writeFile(const std::string& path, const std::string& bytes) {
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  if (!out) throw InputError("stl:" + path, path, "cannot be opened for writing");
  out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
  out.close();
  if (!out) throw InputError("stl:" + path, path, "write failed");
}

}  // namespace

StlMesh parseStl(std::string_view data, const std::string& sourceName) {
  const std::string field = "stl:" + sourceName;
  if (data.empty()) throw InputError(field, "0 bytes", "file is empty");
  const std::string sizeText = std::to_string(data.size()) + " bytes";
  StlMesh mesh;
  std::vector<Vec3> corners;

  if (data.size() >= kHeaderBytes) {
    const std::uint64_t count = readLe32(data, 80);
    if (kHeaderBytes + kFacetBytes * count == data.size()) {
      parseBinary(data, field, corners);
      buildMesh(corners, field, mesh);
      return mesh;
    }
  }
  std::string_view text = data;
  if (text.starts_with("\xEF\xBB\xBF")) text.remove_prefix(3);  // UTF-8 byte-order mark
  const std::size_t first = std::min(text.size(), text.find_first_not_of(" \t\r\n\v\f"));
  const bool startsSolid = equalsIgnoreCase(text.substr(first, 5), "solid");
  const bool isText = looksLikeText(text);
  if (startsSolid && isText) {
    AsciiParser(text, field, corners, mesh.warnings).run();
    buildMesh(corners, field, mesh);
    return mesh;
  }
  const std::string notAscii =
      startsSolid ? "starts with 'solid' but contains binary bytes" : "does not start with 'solid'";
  if (data.size() < kHeaderBytes) {
    throw InputError(
        field, sizeText,
        "not an ASCII STL (" + notAscii + ") and shorter than the 84-byte binary STL header");
  }
  const std::uint64_t count = readLe32(data, 80);
  throw InputError(field, sizeText,
                   "truncated or invalid binary STL: the header declares " + std::to_string(count) +
                       " triangles, which needs " +
                       std::to_string(kHeaderBytes + kFacetBytes * count) +
                       " bytes (not an ASCII STL either: " + notAscii + ")");
}

StlMesh readStl(const std::string& path) {
  const std::string field = "stl:" + path;
  std::ifstream in = openInputFile(field, path, true);
  std::ostringstream buffer;
  buffer << in.rdbuf();
  if (in.bad()) throw InputError(field, path, "read error");
  return parseStl(buffer.view(), path);
}

void writeStlBinary(const std::string& path, const std::vector<Vec3>& vertices,
                    const std::vector<std::array<std::uint32_t, 3>>& triangles) {
  validateForWrite("stl:" + path, vertices, triangles, true);
  if (triangles.size() > std::numeric_limits<std::uint32_t>::max()) {
    throw InputError("stl:" + path, std::to_string(triangles.size()), "too many triangles");
  }
  std::string bytes = "DEMLink binary STL";
  bytes.resize(80, ' ');
  appendLe32(bytes, static_cast<std::uint32_t>(triangles.size()));
  const auto putVec = [&bytes](const Vec3& v) {
    for (int d = 0; d < 3; ++d) {
      appendLe32(bytes, std::bit_cast<std::uint32_t>(static_cast<float>(v[d])));
    }
  };
  for (const auto& tri : triangles) {
    const Vec3& a = vertices[tri[0]];
    const Vec3& b = vertices[tri[1]];
    const Vec3& c = vertices[tri[2]];
    putVec(unitNormal(a, b, c));
    putVec(a);
    putVec(b);
    putVec(c);
    bytes.append(2, '\0');  // attribute byte count
  }
  writeFile(path, bytes);
}

void writeStlAscii(const std::string& path, const std::vector<Vec3>& vertices,
                   const std::vector<std::array<std::uint32_t, 3>>& triangles,
                   const std::string& solidName) {
  validateForWrite("stl:" + path, vertices, triangles, false);
  std::string name = solidName;
  for (char& ch : name) {
    if (isSpace(ch) || static_cast<unsigned char>(ch) < 0x20) ch = '_';
  }
  std::ostringstream os;
  os.imbue(std::locale::classic());
  os << std::setprecision(17);
  os << "solid " << name << '\n';
  for (const auto& tri : triangles) {
    const Vec3& a = vertices[tri[0]];
    const Vec3& b = vertices[tri[1]];
    const Vec3& c = vertices[tri[2]];
    const Vec3 n = unitNormal(a, b, c);
    os << "  facet normal " << n.x() << ' ' << n.y() << ' ' << n.z() << "\n    outer loop\n";
    for (const Vec3* v : {&a, &b, &c}) {
      os << "      vertex " << v->x() << ' ' << v->y() << ' ' << v->z() << '\n';
    }
    os << "    endloop\n  endfacet\n";
  }
  os << "endsolid " << name << '\n';
  writeFile(path, os.str());
}

}  // namespace demlink::core
