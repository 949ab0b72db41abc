#pragma once
/// Line-by-line reading of the FEM input files (Gmsh .msh, Matrix Market, node and triangle
/// lists) with errors that name the file, the line and the reason.
///
/// Why one reader for all four: they share the rules a user-supplied file needs. The whole
/// file is read into memory (at most kMaxTextFileBytes) and walked with bounds checks, so a
/// malformed file ends in an InputError, never a crash or a hang. Errors never echo the file's
/// content (it may be large, binary or private): the field is "<kind>:<path>:line <n>", the
/// value "line <n>". A count announced by a header is checked against the bytes that remain
/// (requireFits) before anything is allocated, so a header claiming 1e12 entries is refused.
#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

namespace demlink::core {

/// Largest input text file read [bytes] (2 GiB).
inline constexpr std::size_t kMaxTextFileBytes = std::size_t{2} << 30;

/// Reads a whole file; InputError (field "<kind>:<path>") when it is missing, not a regular
/// file, unreadable or larger than kMaxTextFileBytes.
[[nodiscard]] std::string loadTextFile(const std::string& path, const std::string& kind);

class TextLines {
 public:
  /// Walks `text` (not copied); `kind` ("msh", "mtx", ...) and `source` (the path) name it in errors.
  TextLines(std::string_view text, const std::string& kind, const std::string& source);

  /// Moves to the next line and returns it without the line end; false at the end of the text.
  bool next(std::string_view& line);
  /// Like next(), but a missing line is an error saying `what` was expected.
  std::string_view expectLine(const std::string& what);
  /// Splits the current line into whitespace-separated tokens (views into the text).
  [[nodiscard]] std::vector<std::string_view> tokens(std::string_view line) const;
  /// Parses a token as an unsigned integer / a finite real; errors name `what`.
  [[nodiscard]] std::uint64_t toCount(std::string_view token, const std::string& what) const;
  [[nodiscard]] double toReal(std::string_view token, const std::string& what) const;
  /// Throws unless `count` entries of at least `minBytesEach` bytes fit in the rest of the text.
  void requireFits(std::uint64_t count, std::size_t minBytesEach, const std::string& what) const;

  [[nodiscard]] std::size_t lineNumber() const { return line_; }
  /// InputError at the current line.
  [[noreturn]] void fail(const std::string& reason) const;
  /// InputError about the whole file (field "<kind>:<path>").
  [[noreturn]] void failFile(const std::string& value, const std::string& reason) const;

 private:
  std::string_view text_;
  std::size_t pos_ = 0;
  std::size_t line_ = 0;
  std::string field_;
};

}  // namespace demlink::core
