/// See text_lines.hpp.
#include "demlink/core/deformable/text_lines.hpp"

#include <charconv>
#include <cmath>
#include <filesystem>
#include <fstream>

#include "demlink/core/base/input_error.hpp"
#include "demlink/core/base/input_file.hpp"

namespace demlink::core {

std::string loadTextFile(const std::string& path, const std::string& kind) {
  const std::string field = kind + ":" + path;
  const std::uintmax_t size = requireInputFile(field, path, kMaxTextFileBytes);
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(field, path, "cannot be opened for reading");
  std::string text(static_cast<std::size_t>(size), '\0');
  in.read(text.data(), static_cast<std::streamsize>(size));
  if (in.gcount() != static_cast<std::streamsize>(size)) throw InputError(field, path, "read error");
  return text;
}

TextLines::TextLines(std::string_view text, const std::string& kind, const std::string& source)
    : text_(text), field_(kind + ":" + source) {}

bool TextLines::next(std::string_view& line) {
  if (pos_ >= text_.size()) return false;
  const std::size_t end = std::min(text_.find('\n', pos_), text_.size());
  line = text_.substr(pos_, end - pos_);
  if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
  pos_ = end + 1;
  ++line_;
  return true;
}

std::string_view TextLines::expectLine(const std::string& what) {
  std::string_view line;
  if (!next(line)) fail("unexpected end of file: expected " + what);
  return line;
}

std::vector<std::string_view> TextLines::tokens(std::string_view line) const {
  std::vector<std::string_view> out;
  std::size_t i = 0;
  while (i < line.size()) {
    while (i < line.size() && (line[i] == ' ' || line[i] == '\t' || line[i] == '\v' || line[i] == '\f')) ++i;
    const std::size_t start = i;
    while (i < line.size() && !(line[i] == ' ' || line[i] == '\t' || line[i] == '\v' || line[i] == '\f')) ++i;
    if (i > start) out.push_back(line.substr(start, i - start));
  }
  return out;
}

std::uint64_t TextLines::toCount(std::string_view token, const std::string& what) const {
  std::uint64_t value = 0;
  const auto [end, ec] = std::from_chars(token.data(), token.data() + token.size(), value);
  if (ec != std::errc() || end != token.data() + token.size()) fail(what + " is not a non-negative integer");
  return value;
}

double TextLines::toReal(std::string_view token, const std::string& what) const {
  if (token.size() > 1 && token[0] == '+' && token[1] != '-') token.remove_prefix(1);
  double value = 0.0;
  const auto [end, ec] = std::from_chars(token.data(), token.data() + token.size(), value);
  if (ec != std::errc() || end != token.data() + token.size()) fail(what + " is not a number");
  if (!std::isfinite(value)) fail(what + " is not finite");
  return value;
}

void TextLines::requireFits(std::uint64_t count, std::size_t minBytesEach, const std::string& what) const {
  const std::size_t remaining = pos_ < text_.size() ? text_.size() - pos_ : 0;
  if (count > remaining / minBytesEach) {
    fail(what + " announces " + std::to_string(count) + " entries but only " + std::to_string(remaining) +
         " bytes follow");
  }
}

void TextLines::fail(const std::string& reason) const {
  throw InputError(field_ + ":line " + std::to_string(line_), "line " + std::to_string(line_), reason);
}

void TextLines::failFile(const std::string& value, const std::string& reason) const {
  throw InputError(field_, value, reason);
}

}  // namespace demlink::core
