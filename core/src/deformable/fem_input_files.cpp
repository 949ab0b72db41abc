/// See fem_input_files.hpp.
#include "demlink/core/deformable/fem_input_files.hpp"

#include <algorithm>
#include <cctype>
#include <fstream>

#include "demlink/core/deformable/text_lines.hpp"
#include "demlink/core/base/input_error.hpp"

namespace demlink::core {
namespace {

std::string lower(std::string_view s) {
  std::string r(s);
  for (char& c : r) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return r;
}

bool isSkipped(std::string_view line, char comment) {
  const std::size_t first = line.find_first_not_of(" \t\v\f");
  return first == std::string_view::npos || line[first] == comment;
}

}  // namespace

Eigen::SparseMatrix<double> parseMatrixMarket(std::string_view text, const std::string& source,
                                              std::uint64_t dimension) {
  TextLines in(text, "mtx", source);
  const auto banner = in.tokens(in.expectLine("the %%MatrixMarket banner"));
  if (banner.size() != 5 || banner[0] != "%%MatrixMarket" || lower(banner[1]) != "matrix") {
    in.fail("expected '%%MatrixMarket matrix coordinate real general|symmetric'");
  }
  if (lower(banner[2]) != "coordinate") in.fail("only the 'coordinate' (sparse) format is read");
  const std::string field = lower(banner[3]);
  if (field != "real" && field != "integer" && field != "double")
    in.fail("only real or integer entries are read");
  const std::string symmetry = lower(banner[4]);
  if (symmetry != "general" && symmetry != "symmetric")
    in.fail("only 'general' or 'symmetric' matrices are read");
  const bool symmetric = symmetry == "symmetric";

  std::string_view line = in.expectLine("the size line 'rows cols entries'");
  while (isSkipped(line, '%')) line = in.expectLine("the size line 'rows cols entries'");
  const auto size = in.tokens(line);
  if (size.size() != 3) in.fail("the size line needs 'rows cols entries'");
  const std::uint64_t rows = in.toCount(size[0], "rows");
  const std::uint64_t cols = in.toCount(size[1], "cols");
  const std::uint64_t entries = in.toCount(size[2], "entries");
  if (rows > kMaxMatrixDimension || cols > kMaxMatrixDimension) {
    in.fail("matrix dimension above the limit of " + std::to_string(kMaxMatrixDimension));
  }
  if (dimension > 0 && (rows != dimension || cols != dimension)) {
    in.fail("the size line says " + std::to_string(rows) + " x " + std::to_string(cols) + "; must be " +
            std::to_string(dimension) + " x " + std::to_string(dimension) + " (3 DOF per node of the node file)");
  }
  if (symmetric && rows != cols) in.fail("a symmetric matrix must be square");
  in.requireFits(entries, 6, "the size line");

  std::vector<Eigen::Triplet<double>> triplets;
  triplets.reserve(static_cast<std::size_t>(symmetric ? 2 * entries : entries));
  std::uint64_t read = 0;
  while (in.next(line)) {
    if (isSkipped(line, '%')) continue;
    if (read == entries) in.fail("more entries than the size line announces");
    const auto tok = in.tokens(line);
    if (tok.size() != 3) in.fail("an entry needs 'row column value'");
    const std::uint64_t i = in.toCount(tok[0], "row");
    const std::uint64_t j = in.toCount(tok[1], "column");
    const double v = in.toReal(tok[2], "value");
    if (i < 1 || i > rows || j < 1 || j > cols)
      in.fail("row or column outside the matrix (indices are 1-based)");
    if (symmetric && j > i) in.fail("a symmetric file holds the lower triangle only (row >= column)");
    const auto r = static_cast<int>(i - 1);
    const auto c = static_cast<int>(j - 1);
    triplets.emplace_back(r, c, v);
    if (symmetric && r != c) triplets.emplace_back(c, r, v);
    ++read;
  }
  if (read != entries) {
    in.failFile(std::to_string(read) + " entries",
                "the size line announces " + std::to_string(entries) + " entries (file truncated?)");
  }
  Eigen::SparseMatrix<double> matrix(static_cast<Eigen::Index>(rows), static_cast<Eigen::Index>(cols));
  matrix.setFromTriplets(triplets.begin(), triplets.end());
  return matrix;
}

Eigen::SparseMatrix<double> readMatrixMarket(const std::string& path, std::uint64_t dimension) {
  return parseMatrixMarket(loadTextFile(path, "mtx"), path, dimension);
}

void writeMatrixMarket(const std::string& path, const Eigen::SparseMatrix<double>& matrix, bool symmetric) {
  std::ofstream out(path);
  if (!out) throw InputError("mtx:" + path, path, "cannot be opened for writing");
  out.precision(17);
  std::size_t count = 0;
  for (int c = 0; c < matrix.outerSize(); ++c) {
    for (Eigen::SparseMatrix<double>::InnerIterator it(matrix, c); it; ++it) {
      if (!symmetric || it.row() >= it.col()) ++count;
    }
  }
  out << "%%MatrixMarket matrix coordinate real " << (symmetric ? "symmetric" : "general") << "\n"
      << matrix.rows() << ' ' << matrix.cols() << ' ' << count << "\n";
  for (int c = 0; c < matrix.outerSize(); ++c) {
    for (Eigen::SparseMatrix<double>::InnerIterator it(matrix, c); it; ++it) {
      if (!symmetric || it.row() >= it.col())
        out << it.row() + 1 << ' ' << it.col() + 1 << ' ' << it.value() << "\n";
    }
  }
  if (!out) throw InputError("mtx:" + path, path, "write failed");
}

std::vector<Vec3> parseNodeFile(std::string_view text, const std::string& source) {
  TextLines in(text, "nodes", source);
  std::vector<Vec3> nodes;
  std::string_view line;
  while (in.next(line)) {
    if (isSkipped(line, '#')) continue;
    const auto tok = in.tokens(line);
    if (tok.size() != 3) in.fail("a node line needs 'x y z'");
    if (nodes.size() >= UINT32_MAX) in.fail("too many nodes");
    nodes.emplace_back(in.toReal(tok[0], "x"), in.toReal(tok[1], "y"), in.toReal(tok[2], "z"));
  }
  if (nodes.empty()) in.failFile("0 nodes", "the node file lists no nodes");
  return nodes;
}

std::vector<Vec3> readNodeFile(const std::string& path) {
  return parseNodeFile(loadTextFile(path, "nodes"), path);
}

std::vector<std::array<std::uint32_t, 3>> parseTriangleFile(std::string_view text, const std::string& source,
                                                            std::size_t nodeCount) {
  TextLines in(text, "triangles", source);
  std::vector<std::array<std::uint32_t, 3>> triangles;
  std::string_view line;
  while (in.next(line)) {
    if (isSkipped(line, '#')) continue;
    const auto tok = in.tokens(line);
    if (tok.size() != 3) in.fail("a triangle line needs three node indices 'a b c'");
    std::array<std::uint32_t, 3> t{};
    for (std::size_t k = 0; k < 3; ++k) {
      const std::uint64_t n = in.toCount(tok[k], "node index");
      if (n >= nodeCount) {
        in.fail("node index " + std::to_string(n) + " out of range (" + std::to_string(nodeCount) +
                " nodes, indices are 0-based)");
      }
      t[k] = static_cast<std::uint32_t>(n);
    }
    if (t[0] == t[1] || t[1] == t[2] || t[0] == t[2]) in.fail("a triangle repeats a node");
    triangles.push_back(t);
  }
  if (triangles.empty()) in.failFile("0 triangles", "the triangle file lists no triangles");
  return triangles;
}

std::vector<std::array<std::uint32_t, 3>> readTriangleFile(const std::string& path, std::size_t nodeCount) {
  return parseTriangleFile(loadTextFile(path, "triangles"), path, nodeCount);
}

}  // namespace demlink::core
