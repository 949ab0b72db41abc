/// Particle text files (format in particle_file_reader.hpp). Numbers are parsed
/// with std::from_chars: locale-independent, no silent partial parses (a token
/// must be consumed entirely), and "nan"/"inf" are recognised so they can be
/// refused with a clear message instead of slipping through.
#include "demlink/server/scene/particle_file_reader.hpp"

#include <array>
#include <charconv>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <system_error>
#include <unordered_map>

#include "demlink/core/base/input_error.hpp"
#include "demlink/core/base/input_file.hpp"

namespace demlink::server {
namespace {

constexpr std::size_t kColumns = 5;
constexpr std::array<const char*, kColumns> kColumnNames = {"id", "x", "y", "z", "r"};

bool isBlank(char c) { return c == ' ' || c == '\t' || c == '\r' || c == '\v' || c == '\f'; }

std::vector<std::string_view> splitTokens(std::string_view line) {
  std::vector<std::string_view> tokens;
  std::size_t k = 0;
  while (k < line.size()) {
    while (k < line.size() && isBlank(line[k])) ++k;
    const std::size_t start = k;
    while (k < line.size() && !isBlank(line[k])) ++k;
    if (k > start) tokens.push_back(line.substr(start, k - start));
  }
  return tokens;
}

std::string columnLabel(std::size_t column) {
  return "column " + std::to_string(column + 1) + " (" + kColumnNames[column] + ")";
}

double parseCoordinate(std::string_view token, std::size_t column, const std::string& field) {
  double value = 0.0;
  const auto [end, ec] = std::from_chars(token.data(), token.data() + token.size(), value);
  if (ec == std::errc::result_out_of_range) {
    throw core::InputError(field, columnLabel(column), "is out of the range of a double");
  }
  if (ec != std::errc() || end != token.data() + token.size()) {
    throw core::InputError(field, columnLabel(column), "is not a number");
  }
  if (!std::isfinite(value)) throw core::InputError(field, columnLabel(column), "must be finite");
  return value;
}

}  // namespace

std::vector<ParticleRecord> parseParticleText(std::string_view text, const std::string& sourceName) {
  std::vector<ParticleRecord> records;
  std::unordered_map<std::uint64_t, std::size_t> lineOfId;
  std::size_t lineNumber = 0;
  std::size_t pos = 0;
  while (pos < text.size()) {
    const std::size_t newline = text.find('\n', pos);
    const std::size_t length = newline == std::string_view::npos ? std::string_view::npos : newline - pos;
    std::string_view line = text.substr(pos, length);
    pos = newline == std::string_view::npos ? text.size() : newline + 1;
    ++lineNumber;
    if (const std::size_t hash = line.find('#'); hash != std::string_view::npos) line = line.substr(0, hash);
    const std::vector<std::string_view> tokens = splitTokens(line);
    if (tokens.empty()) continue;

    const std::string field = sourceName + ":line " + std::to_string(lineNumber);
    if (tokens.size() != kColumns) {
      throw core::InputError(field, std::to_string(tokens.size()) + " columns", "expected 5 columns (id x y z r)");
    }
    ParticleRecord record;
    record.line = lineNumber;
    const auto [idEnd, idEc] = std::from_chars(tokens[0].data(), tokens[0].data() + tokens[0].size(), record.id);
    if (idEc != std::errc() || idEnd != tokens[0].data() + tokens[0].size()) {
      throw core::InputError(field, columnLabel(0), "is not a non-negative integer");
    }
    for (std::size_t k = 0; k < 3; ++k) {
      record.position[static_cast<Eigen::Index>(k)] = parseCoordinate(tokens[k + 1], k + 1, field);
    }
    record.radius = parseCoordinate(tokens[4], 4, field);
    if (!(record.radius > 0.0)) throw core::InputError(field, columnLabel(4), "must be > 0");
    const auto [it, inserted] = lineOfId.emplace(record.id, lineNumber);
    if (!inserted) {
      throw core::InputError(field, columnLabel(0), "id already used on line " + std::to_string(it->second));
    }
    records.push_back(record);
  }
  if (records.empty()) throw core::InputError(sourceName, "(particle file)", "contains no spheres");
  return records;
}

std::vector<ParticleRecord> readParticleFile(const std::string& path) {
  return parseParticleText(core::readInputFile("particle file", path), path);
}

}  // namespace demlink::server
