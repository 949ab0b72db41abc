/// Particle-set CSV reading and writing (format in particle_csv.hpp).
///
/// Numbers are parsed with std::from_chars (locale-independent, the whole field
/// must be consumed) and written with {:.17g}, which round-trips every double.
/// Fields are plain (no quoting): a material name containing a comma, a quote
/// or a line break is refused when writing rather than written ambiguously.
#include "demlink/server/scene/particle_csv.hpp"

#include <spdlog/fmt/fmt.h>

#include <algorithm>
#include <array>
#include <charconv>
#include <cmath>
#include <fstream>
#include <numeric>
#include <sstream>
#include <stdexcept>
#include <system_error>
#include <unordered_map>

#include "demlink/core/base/input_error.hpp"
#include "demlink/core/base/input_file.hpp"

namespace demlink::server {
namespace {

constexpr std::size_t kColumns = 9;
constexpr std::array<const char*, kColumns> kNames = {"id", "x", "y", "z", "vx", "vy", "vz", "radius", "material"};

std::string_view trim(std::string_view text) {
  auto blank = [](char c) { return c == ' ' || c == '\t' || c == '\r'; };
  while (!text.empty() && blank(text.front())) text.remove_prefix(1);
  while (!text.empty() && blank(text.back())) text.remove_suffix(1);
  return text;
}

std::vector<std::string_view> splitFields(std::string_view line) {
  std::vector<std::string_view> fields;
  std::size_t start = 0;
  while (true) {
    const std::size_t comma = line.find(',', start);
    fields.push_back(trim(line.substr(start, comma == std::string_view::npos ? std::string_view::npos : comma - start)));
    if (comma == std::string_view::npos) return fields;
    start = comma + 1;
  }
}

std::string columnLabel(std::size_t column) {
  return "column " + std::to_string(column + 1) + " (" + kNames[column] + ")";
}

double parseNumber(std::string_view token, std::size_t column, const std::string& field) {
  double value = 0.0;
  const auto [end, ec] = std::from_chars(token.data(), token.data() + token.size(), value);
  if (ec == std::errc::result_out_of_range) {
    throw core::InputError(field, columnLabel(column), "is out of the range of a double");
  }
  if (ec != std::errc() || end != token.data() + token.size() || token.empty()) {
    throw core::InputError(field, columnLabel(column), "is not a number");
  }
  if (!std::isfinite(value)) throw core::InputError(field, columnLabel(column), "must be finite");
  return value;
}

}  // namespace

std::vector<ParticleCsvRecord> parseParticleCsv(std::string_view text, const std::string& sourceName) {
  std::vector<ParticleCsvRecord> records;
  std::unordered_map<std::uint64_t, std::size_t> lineOfId;
  bool headerSeen = false;
  std::size_t lineNumber = 0;
  std::size_t pos = 0;
  while (pos < text.size()) {
    const std::size_t newline = text.find('\n', pos);
    const std::string_view line =
        trim(text.substr(pos, newline == std::string_view::npos ? std::string_view::npos : newline - pos));
    pos = newline == std::string_view::npos ? text.size() : newline + 1;
    ++lineNumber;
    if (line.empty()) continue;
    const std::string field = sourceName + ":line " + std::to_string(lineNumber);
    const std::vector<std::string_view> fields = splitFields(line);
    if (!headerSeen) {
      bool matches = fields.size() == kColumns;
      for (std::size_t k = 0; matches && k < kColumns; ++k) matches = fields[k] == kNames[k];
      if (!matches) {
        throw core::InputError(field, "(first line)", "expected the header \"" + std::string(kParticleCsvHeader) + "\"");
      }
      headerSeen = true;
      continue;
    }
    if (fields.size() != kColumns) {
      throw core::InputError(field, std::to_string(fields.size()) + " columns",
                             "expected 9 columns (" + std::string(kParticleCsvHeader) + ")");
    }
    ParticleCsvRecord record;
    record.line = lineNumber;
    const auto [idEnd, idEc] = std::from_chars(fields[0].data(), fields[0].data() + fields[0].size(), record.id);
    if (idEc != std::errc() || idEnd != fields[0].data() + fields[0].size() || fields[0].empty()) {
      throw core::InputError(field, columnLabel(0), "is not a non-negative integer");
    }
    for (Eigen::Index k = 0; k < 3; ++k) {
      const auto column = static_cast<std::size_t>(k);
      record.position[k] = parseNumber(fields[1 + column], 1 + column, field);
      record.velocity[k] = parseNumber(fields[4 + column], 4 + column, field);
    }
    record.radius = parseNumber(fields[7], 7, field);
    if (!(record.radius > 0.0)) throw core::InputError(field, columnLabel(7), "must be > 0");
    record.material = std::string(fields[8]);
    if (record.material.empty()) throw core::InputError(field, columnLabel(8), "is empty");
    const auto [it, inserted] = lineOfId.emplace(record.id, lineNumber);
    if (!inserted) {
      throw core::InputError(field, columnLabel(0), "id already used on line " + std::to_string(it->second));
    }
    records.push_back(std::move(record));
  }
  if (!headerSeen) throw core::InputError(sourceName, "(empty file)", "expected the header line and particles");
  if (records.empty()) throw core::InputError(sourceName, "(particle CSV)", "contains no particles");
  return records;
}

std::vector<ParticleCsvRecord> readParticleCsv(const std::filesystem::path& path) {
  return parseParticleCsv(core::readInputFile("particle CSV", path), path.string());
}

void writeParticleCsv(const core::World& world, const std::filesystem::path& path) {
  for (const core::Material& material : world.materials()) {
    if (material.name.find_first_of(",\"\n\r") != std::string::npos) {
      throw std::runtime_error("material name \"" + material.name + "\" cannot be written to " + path.string() +
                               " (contains a comma, quote or line break)");
    }
  }
  const core::ParticleArrays& p = world.particles();
  std::vector<std::size_t> order(p.size());
  std::iota(order.begin(), order.end(), std::size_t{0});
  std::sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) { return p.id[a] < p.id[b]; });
  std::string text(kParticleCsvHeader);
  text += '\n';
  for (std::size_t i : order) {
    const core::Vec3& x = p.position[i];
    const core::Vec3& v = p.velocity[i];
    text += fmt::format("{},{:.17g},{:.17g},{:.17g},{:.17g},{:.17g},{:.17g},{:.17g},{}\n", p.id[i], x.x(), x.y(),
                        x.z(), v.x(), v.y(), v.z(), p.radius[i], world.materials()[p.material[i]].name);
  }
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  out << text;
  out.flush();
  if (!out) throw std::runtime_error("cannot write " + path.string());
}

}  // namespace demlink::server
