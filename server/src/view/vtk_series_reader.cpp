/// VTK XML reading for the post-run view (contract in vtk_series_reader.hpp).
#include "demlink/server/view/vtk_series_reader.hpp"

#include <bit>
#include <charconv>
#include <cstring>
#include <fstream>
#include <limits>
#include <map>
#include <optional>
#include <sstream>

#include "demlink/core/base/input_error.hpp"

namespace demlink::server {
namespace {

/// Largest file read [B]: a 10-million-particle frame is ~1 GB.
constexpr std::uintmax_t kMaxFileBytes = std::uintmax_t{4} << 30;

[[noreturn]] void refuse(const std::filesystem::path& path, const std::string& why) {
  throw core::InputError("file", path.string(), why);
}

std::string readWhole(const std::filesystem::path& path) {
  std::error_code error;
  const std::uintmax_t size = std::filesystem::file_size(path, error);
  if (error) refuse(path, "cannot read: " + error.message());
  if (size > kMaxFileBytes) refuse(path, "larger than 4 GiB");
  std::ifstream in(path, std::ios::binary);
  std::string bytes(static_cast<std::size_t>(size), '\0');
  in.read(bytes.data(), static_cast<std::streamsize>(size));
  if (!in) refuse(path, "cannot read");
  return bytes;
}

/// One XML tag: its name (with a leading '/' for a closing tag) and attributes.
struct Tag {
  std::string name;
  std::map<std::string, std::string> attributes;
  std::size_t end = 0;  ///< just past '>'
  bool self_closing = false;

  /// The attribute's value, empty when absent.
  [[nodiscard]] std::string attribute(const std::string& key) const {
    const auto found = attributes.find(key);
    return found == attributes.end() ? std::string() : found->second;
  }
};

/// The next tag at or after `from` in `text` (before `limit`), or nullopt.
std::optional<Tag> nextTag(const std::string& text, std::size_t from, std::size_t limit,
                           const std::filesystem::path& path) {
  while (true) {
    const std::size_t open = text.find('<', from);
    if (open == std::string::npos || open >= limit) return std::nullopt;
    if (text.compare(open, 2, "<?") == 0 || text.compare(open, 4, "<!--") == 0) {
      from = open + 2;
      continue;
    }
    const std::size_t close = text.find('>', open);
    if (close == std::string::npos || close >= limit) refuse(path, "unterminated XML tag");
    Tag tag;
    tag.end = close + 1;
    std::string_view inside(text.data() + open + 1, close - open - 1);
    if (!inside.empty() && inside.back() == '/') {
      tag.self_closing = true;
      inside.remove_suffix(1);
    }
    const std::size_t nameEnd = inside.find_first_of(" \t\r\n");
    tag.name = std::string(inside.substr(0, nameEnd));
    std::string_view rest = nameEnd == std::string_view::npos ? std::string_view() : inside.substr(nameEnd);
    while (true) {
      const std::size_t start = rest.find_first_not_of(" \t\r\n");
      if (start == std::string_view::npos) break;
      rest.remove_prefix(start);
      const std::size_t equals = rest.find('=');
      if (equals == std::string_view::npos || equals + 1 >= rest.size() || rest[equals + 1] != '"') {
        refuse(path, "malformed attribute in <" + tag.name + ">");
      }
      const std::size_t valueEnd = rest.find('"', equals + 2);
      if (valueEnd == std::string_view::npos) refuse(path, "unterminated attribute in <" + tag.name + ">");
      tag.attributes[std::string(rest.substr(0, equals))] = std::string(rest.substr(equals + 2, valueEnd - equals - 2));
      rest.remove_prefix(valueEnd + 1);
    }
    return tag;
  }
}

std::string unescapeXml(const std::string& text) {
  std::string out;
  for (std::size_t i = 0; i < text.size(); ++i) {
    if (text[i] != '&') {
      out += text[i];
      continue;
    }
    const std::size_t semicolon = text.find(';', i);
    const std::string entity = text.substr(i, semicolon == std::string::npos ? 1 : semicolon - i + 1);
    if (entity == "&amp;") out += '&';
    else if (entity == "&lt;") out += '<';
    else if (entity == "&gt;") out += '>';
    else if (entity == "&quot;") out += '"';
    else if (entity == "&apos;") out += '\'';
    else {
      out += '&';
      continue;
    }
    i = semicolon;
  }
  return out;
}

std::size_t typeSize(const std::string& type) {
  if (type == "Float64" || type == "UInt64" || type == "Int64") return 8;
  if (type == "UInt32") return 4;
  if (type == "UInt8") return 1;
  return 0;
}

template <class T>
T load(const char* bytes) {
  T value{};
  std::memcpy(&value, bytes, sizeof(T));
  return value;
}

void appendValue(VtkColumn& column, const std::string& type, const char* bytes) {
  if (type == "Float64") {
    column.values.push_back(load<double>(bytes));
    return;
  }
  std::uint64_t integer = 0;
  if (type == "UInt64") integer = load<std::uint64_t>(bytes);
  else if (type == "Int64") integer = static_cast<std::uint64_t>(load<std::int64_t>(bytes));
  else if (type == "UInt32") integer = load<std::uint32_t>(bytes);
  else integer = load<std::uint8_t>(bytes);
  column.integers.push_back(integer);
  column.values.push_back(type == "Int64" ? static_cast<double>(load<std::int64_t>(bytes)) : static_cast<double>(integer));
}

/// The `Corners`-point cells of a Lines or Polys section (cells of other sizes, which the
/// writer does not produce for a surface, are skipped); refuses points out of range and
/// offsets out of order.
template <std::size_t Corners>
void cellsOf(const std::vector<std::int64_t>& connectivity, const std::vector<std::int64_t>& offsets,
             std::size_t pointCount, const std::filesystem::path& path, const std::string& section,
             std::vector<std::array<std::uint32_t, Corners>>& out) {
  std::int64_t previous = 0;
  for (const std::int64_t offset : offsets) {
    if (offset < previous || offset > static_cast<std::int64_t>(connectivity.size())) {
      refuse(path, section + " offsets out of order");
    }
    if (offset - previous == static_cast<std::int64_t>(Corners)) {
      std::array<std::uint32_t, Corners> cell{};
      for (std::size_t k = 0; k < Corners; ++k) {
        const std::int64_t vertex = connectivity[static_cast<std::size_t>(previous) + k];
        if (vertex < 0 || static_cast<std::size_t>(vertex) >= pointCount) refuse(path, "a cell's point out of range in " + section);
        cell[k] = static_cast<std::uint32_t>(vertex);
      }
      out.push_back(cell);
    }
    previous = offset;
  }
}

}  // namespace

std::vector<PvdFrame> readPvd(const std::filesystem::path& path) {
  const std::string text = readWhole(path);
  std::vector<PvdFrame> frames;
  std::size_t at = 0;
  while (const std::optional<Tag> tag = nextTag(text, at, text.size(), path)) {
    at = tag->end;
    if (tag->name != "DataSet") continue;
    const auto time = tag->attributes.find("timestep");
    const auto file = tag->attributes.find("file");
    if (time == tag->attributes.end() || file == tag->attributes.end()) {
      refuse(path, "a DataSet without timestep or file");
    }
    PvdFrame frame;
    const auto [end, error] = std::from_chars(time->second.data(), time->second.data() + time->second.size(), frame.time);
    if (error != std::errc() || end != time->second.data() + time->second.size()) {
      refuse(path, "timestep \"" + time->second + "\" is not a number");
    }
    const std::filesystem::path relative = unescapeXml(file->second);
    if (relative.is_absolute() || relative.string().find("..") != std::string::npos) {
      refuse(path, "DataSet file \"" + relative.string() + "\" leaves the run's folder");
    }
    frame.file = path.parent_path() / relative;
    frames.push_back(std::move(frame));
  }
  return frames;
}

PolyData readPolyData(const std::filesystem::path& path) {
  const std::string text = readWhole(path);
  if (text.find("type=\"PolyData\"") == std::string::npos) refuse(path, "not VTK XML PolyData");
  if (text.find("byte_order=\"BigEndian\"") != std::string::npos && std::endian::native != std::endian::big) {
    refuse(path, "written in big-endian byte order on another machine");
  }
  const std::size_t appended = text.find("<AppendedData");
  const std::size_t headerEnd = appended == std::string::npos ? text.size() : appended;
  std::size_t base = std::string::npos;
  if (appended != std::string::npos) {
    const std::size_t marker = text.find('_', appended);
    if (marker == std::string::npos) refuse(path, "AppendedData without its '_' marker");
    base = marker + 1;
  }

  PolyData data;
  std::string section;  // Points, PointData, CellData, Verts, Lines, Polys
  std::map<std::string, std::vector<std::int64_t>> cells;  // "<section> connectivity|offsets" of Lines, Polys
  std::size_t at = 0;
  while (const std::optional<Tag> tag = nextTag(text, at, headerEnd, path)) {
    at = tag->end;
    if (tag->name == "Piece") {
      const std::string count = tag->attribute("NumberOfPoints");
      if (std::from_chars(count.data(), count.data() + count.size(), data.point_count).ec != std::errc()) {
        refuse(path, "Piece NumberOfPoints \"" + count + "\" is not a count");
      }
      continue;
    }
    if (tag->name == "Points" || tag->name == "PointData" || tag->name == "CellData" || tag->name == "Verts" ||
        tag->name == "Lines" || tag->name == "Polys" || tag->name == "Strips") {
      section = tag->self_closing ? "" : tag->name;
      continue;
    }
    if (tag->name.starts_with('/')) {
      if (tag->name != "/DataArray") section = tag->name == "/" + section ? "" : section;
      continue;
    }
    if (tag->name != "DataArray") continue;
    const std::string type = tag->attribute("type");
    const std::string name = tag->attribute("Name");
    const std::size_t size = typeSize(type);
    if (size == 0) refuse(path, "DataArray " + name + " of unknown type \"" + type + "\"");
    VtkColumn column;
    const std::string components = tag->attribute("NumberOfComponents");
    if (!components.empty() && std::from_chars(components.data(), components.data() + components.size(),
                                                column.components).ec != std::errc()) {
      refuse(path, "DataArray " + name + " NumberOfComponents \"" + components + "\"");
    }
    if (column.components < 1 || column.components > 9) refuse(path, "DataArray " + name + " has bad components");
    if (tag->attribute("format") == "appended") {
      if (base == std::string::npos) refuse(path, "DataArray " + name + " is appended but the file has no AppendedData");
      std::uint64_t offset = 0;
      const std::string offsetText = tag->attribute("offset");
      if (std::from_chars(offsetText.data(), offsetText.data() + offsetText.size(), offset).ec != std::errc() ||
          offset > text.size() - base || text.size() - base - offset < 8) {
        refuse(path, "DataArray " + name + " offset \"" + offsetText + "\" outside the file");
      }
      const std::uint64_t bytes = load<std::uint64_t>(text.data() + base + offset);
      if (bytes % size != 0 || bytes > text.size() - base - offset - 8) {
        refuse(path, "DataArray " + name + " block of " + std::to_string(bytes) + " bytes does not fit the file");
      }
      const char* values = text.data() + base + offset + 8;
      column.values.reserve(bytes / size);
      for (std::uint64_t k = 0; k < bytes / size; ++k) appendValue(column, type, values + k * size);
    } else if (tag->attribute("format") == "ascii") {
      const std::size_t end = text.find("</DataArray>", at);
      if (end == std::string::npos) refuse(path, "DataArray " + name + " without its end");
      std::istringstream values(text.substr(at, end - at));
      std::string word;
      while (values >> word) {
        double value = 0.0;
        const auto [stop, error] = std::from_chars(word.data(), word.data() + word.size(), value);
        if (error != std::errc() || stop != word.data() + word.size()) {
          refuse(path, "DataArray " + name + " value \"" + word.substr(0, 30) + "\" is not a number");
        }
        column.values.push_back(value);
        column.integers.push_back(value >= 0.0 && value < 1.8e19 ? static_cast<std::uint64_t>(value) : 0);
      }
      at = end;
    } else {
      refuse(path, "DataArray " + name + " format \"" + tag->attribute("format") + "\" (appended or ascii)");
    }
    if (section == "Points") {
      data.points = std::move(column.values);
    } else if (section == "PointData") {
      data.point_data[name] = std::move(column);
    } else if (section == "CellData") {
      data.cell_data[name] = std::move(column);
    } else if ((section == "Lines" || section == "Polys") && (name == "connectivity" || name == "offsets")) {
      cells[section + " " + name].assign(column.values.begin(), column.values.end());
    }
  }
  if (data.points.size() != 3 * data.point_count) refuse(path, "Points do not match NumberOfPoints");
  for (const auto& [name, column] : data.point_data) {
    if (column.values.size() != static_cast<std::size_t>(column.components) * data.point_count) {
      refuse(path, "point data " + name + " does not match NumberOfPoints");
    }
  }
  cellsOf<2>(cells["Lines connectivity"], cells["Lines offsets"], data.point_count, path, "Lines", data.lines);
  cellsOf<3>(cells["Polys connectivity"], cells["Polys offsets"], data.point_count, path, "Polys", data.triangles);
  return data;
}

}  // namespace demlink::server
