#pragma once
/// The files of the FEM body's import path: matrices in Matrix Market format and the node
/// coordinates and surface triangles as plain text (format in docs/deformable.md).
///
/// Matrix Market: "%%MatrixMarket matrix coordinate real|integer general|symmetric", comment
/// lines starting with '%', the size line "rows cols entries", then one "i j value" per entry
/// (1-based). A symmetric file holds the lower triangle (i >= j) and is mirrored on reading.
/// Repeated entries are summed. Dimensions above kMaxMatrixDimension are refused.
///
/// Node file: one node per line, "x y z" [m]. Triangle file: one triangle per line, "a b c",
/// 0-based node indices, counter-clockwise seen from outside. In both, blank lines and lines
/// starting with '#' are skipped; the n-th data line is node (triangle) n - 1.
#include <Eigen/SparseCore>
#include <array>
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "demlink/core/base/math_types.hpp"

namespace demlink::core {

inline constexpr std::uint64_t kMaxMatrixDimension = 100'000'000;

/// Reads a Matrix Market file; InputError naming "mtx:<path>:line <n>" and the reason.
/// `dimension` > 0: the matrix must be dimension x dimension (3 per node of the node
/// file), checked on the size line before anything is allocated, so a few bytes claiming
/// a huge matrix cost nothing.
[[nodiscard]] Eigen::SparseMatrix<double> readMatrixMarket(const std::string& path, std::uint64_t dimension = 0);
[[nodiscard]] Eigen::SparseMatrix<double> parseMatrixMarket(std::string_view text, const std::string& source,
                                                            std::uint64_t dimension = 0);
/// Writes `matrix` (all entries, "general"; only the lower triangle, "symmetric") with 17 digits.
void writeMatrixMarket(const std::string& path, const Eigen::SparseMatrix<double>& matrix, bool symmetric);

/// Reads a node file (see above); InputError naming "nodes:<path>:line <n>".
[[nodiscard]] std::vector<Vec3> readNodeFile(const std::string& path);
[[nodiscard]] std::vector<Vec3> parseNodeFile(std::string_view text, const std::string& source);
/// Reads a triangle file (see above); indices must be below `nodeCount`.
[[nodiscard]] std::vector<std::array<std::uint32_t, 3>> readTriangleFile(const std::string& path,
                                                                         std::size_t nodeCount);
[[nodiscard]] std::vector<std::array<std::uint32_t, 3>> parseTriangleFile(std::string_view text,
                                                                          const std::string& source,
                                                                          std::size_t nodeCount);

}  // namespace demlink::core
