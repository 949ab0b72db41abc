/// Materials database parser. A small CSV reader of our own (quoted fields with
/// "" escapes, no multi-line fields) is enough for this one file and keeps core
/// free of a CSV dependency. Columns are found by header name, so their order
/// in the file is free; every error names "origin:line.column" and the value.
#include "demlink/core/materials/material_database.hpp"

#include <array>
#include <charconv>
#include <fstream>
#include <map>
#include <sstream>

#include "demlink/core/base/input_error.hpp"
#include "demlink/core/base/input_file.hpp"

namespace demlink::core {

/// data/materials.csv as of the build (generated: material_database_data.cpp).
extern const char* const kBuiltInMaterialsCsv;

namespace {

constexpr std::array<std::string_view, 12> kColumns = {
    "name",       "density",    "youngs_modulus", "poisson_ratio", "restitution", "sliding_friction",
    "rolling_friction", "size_kind", "radius_min", "radius_max", "source", "cohesion_energy_density"};
/// Columns a file may leave out (their values then keep core::Material's defaults).
constexpr std::size_t kCohesionColumn = 11;
constexpr std::size_t kAbsent = static_cast<std::size_t>(-1);

std::string_view trim(std::string_view s) {
  while (!s.empty() && (s.front() == ' ' || s.front() == '\t')) s.remove_prefix(1);
  while (!s.empty() && (s.back() == ' ' || s.back() == '\t' || s.back() == '\r')) s.remove_suffix(1);
  return s;
}

std::string quotedText(std::string_view text) { return "\"" + std::string(text) + "\""; }

/// Splits one CSV line into trimmed fields. `where` prefixes errors.
std::vector<std::string> splitFields(std::string_view line, const std::string& where) {
  std::vector<std::string> fields;
  std::size_t k = 0;
  while (true) {
    while (k < line.size() && (line[k] == ' ' || line[k] == '\t')) ++k;
    std::string field;
    if (k < line.size() && line[k] == '"') {
      ++k;
      bool closed = false;
      while (k < line.size()) {
        if (line[k] == '"') {
          if (k + 1 < line.size() && line[k + 1] == '"') {
            field += '"';
            k += 2;
            continue;
          }
          closed = true;
          ++k;
          break;
        }
        field += line[k++];
      }
      if (!closed) throw InputError(where, quotedText(field), "unterminated quoted field");
      while (k < line.size() && (line[k] == ' ' || line[k] == '\t' || line[k] == '\r')) ++k;
      if (k < line.size() && line[k] != ',') {
        throw InputError(where, quotedText(field), "text after a closing quote (expected ',')");
      }
    } else {
      const std::size_t end = line.find(',', k);
      field = std::string(trim(line.substr(k, end == std::string_view::npos ? line.size() - k : end - k)));
      k = end == std::string_view::npos ? line.size() : end;
    }
    fields.push_back(std::move(field));
    if (k >= line.size()) break;
    ++k;  // the comma
  }
  return fields;
}

double parseNumber(const std::string& text, const std::string& field) {
  double value = 0.0;
  const char* first = text.data();
  const char* last = first + text.size();
  const auto [end, ec] = std::from_chars(first, last, value);
  if (text.empty() || ec != std::errc() || end != last) throw InputError(field, quotedText(text), "not a number");
  return value;
}

MaterialSizeRange::Kind parseSizeKind(const std::string& text, const std::string& field) {
  const std::string key = MaterialDatabase::normalisedName(text);
  if (key == "uniform") return MaterialSizeRange::Kind::Uniform;
  if (key == "constant") return MaterialSizeRange::Kind::Constant;
  throw InputError(field, quotedText(text), "unknown size kind (known: uniform, constant)");
}

}  // namespace

std::string MaterialDatabase::normalisedName(std::string_view name) {
  std::string key(trim(name));
  for (char& c : key) {
    if (c >= 'A' && c <= 'Z') c = static_cast<char>(c - 'A' + 'a');
    if (c == ' ' || c == '-') c = '_';
  }
  return key;
}

MaterialDatabase MaterialDatabase::parse(std::string_view text, const std::string& origin) {
  MaterialDatabase db;
  db.origin_ = origin;
  std::array<std::size_t, kColumns.size()> columnOf{};
  std::size_t fieldCount = 0;
  bool haveHeader = false;
  std::map<std::string, std::size_t> lineOfName;
  std::size_t lineNumber = 0;
  std::size_t pos = 0;
  while (pos < text.size()) {
    const std::size_t end = text.find('\n', pos);
    const std::string_view raw = text.substr(pos, end == std::string_view::npos ? text.size() - pos : end - pos);
    pos = end == std::string_view::npos ? text.size() : end + 1;
    ++lineNumber;
    const std::string_view line = trim(raw);
    if (line.empty() || line.front() == '#') continue;
    const std::string where = origin + ":" + std::to_string(lineNumber);
    const std::vector<std::string> fields = splitFields(line, where);

    if (!haveHeader) {
      haveHeader = true;
      fieldCount = fields.size();
      std::map<std::string, std::size_t> indexOf;
      for (std::size_t k = 0; k < fields.size(); ++k) {
        const std::string& column = fields[k];
        bool known = false;
        for (std::string_view c : kColumns) known = known || c == column;
        if (!known) throw InputError(where + ".header", quotedText(column), "unknown column");
        if (!indexOf.emplace(column, k).second) throw InputError(where + ".header", quotedText(column), "column repeated");
      }
      for (std::size_t c = 0; c < kColumns.size(); ++c) {
        const auto it = indexOf.find(std::string(kColumns[c]));
        if (it == indexOf.end() && c == kCohesionColumn) {
          columnOf[c] = kAbsent;
          continue;
        }
        if (it == indexOf.end()) {
          throw InputError(where + ".header", quotedText(kColumns[c]), "missing column " + std::string(kColumns[c]));
        }
        columnOf[c] = it->second;
      }
      continue;
    }

    if (fields.size() != fieldCount) {
      throw InputError(where, std::to_string(fields.size()) + " fields",
                       "expected " + std::to_string(fieldCount) + " fields as in the header");
    }
    auto field = [&](std::size_t c) -> const std::string& { return fields[columnOf[c]]; };
    auto number = [&](std::size_t c) { return parseNumber(field(c), where + "." + std::string(kColumns[c])); };

    MaterialRecord record;
    record.line = lineNumber;
    Material& m = record.material;
    m.name = field(0);
    if (normalisedName(m.name).empty()) throw InputError(where + ".name", "\"\"", "a material needs a name");
    m.density = number(1);
    m.youngs_modulus = number(2);
    m.poisson_ratio = number(3);
    m.restitution = number(4);
    m.sliding_friction = number(5);
    m.rolling_friction = number(6);
    if (columnOf[kCohesionColumn] != kAbsent) m.cohesion_energy_density = number(kCohesionColumn);
    m.validate(where);
    record.size.kind = parseSizeKind(field(7), where + ".size_kind");
    record.size.radius_min = number(8);
    record.size.radius_max = number(9);
    requirePositive(where + ".radius_min", record.size.radius_min);
    requirePositive(where + ".radius_max", record.size.radius_max);
    if (record.size.radius_max < record.size.radius_min) {
      throw InputError(where + ".radius_max", formatValue(record.size.radius_max),
                       "must be >= radius_min (" + formatValue(record.size.radius_min) + ")");
    }
    if (record.size.kind == MaterialSizeRange::Kind::Constant && record.size.radius_max != record.size.radius_min) {
      throw InputError(where + ".radius_max", formatValue(record.size.radius_max),
                       "size kind constant needs radius_max = radius_min (" + formatValue(record.size.radius_min) +
                           ")");
    }
    record.source = field(10);
    if (record.source.empty()) {
      throw InputError(where + ".source", "\"\"", "every material needs a source (a citation, or \"estimate: why\")");
    }
    const auto [it, inserted] = lineOfName.emplace(normalisedName(m.name), lineNumber);
    if (!inserted) {
      throw InputError(where + ".name", quotedText(m.name), "already defined at line " + std::to_string(it->second));
    }
    db.records_.push_back(std::move(record));
  }
  if (!haveHeader) throw InputError(origin, "(empty)", "no header line (and no materials)");
  return db;
}

MaterialDatabase MaterialDatabase::fromFile(const std::filesystem::path& path) {
  return parse(readInputFile("materials database", path), path.string());
}

const MaterialDatabase& MaterialDatabase::builtIn() {
  static const MaterialDatabase db = parse(kBuiltInMaterialsCsv, "data/materials.csv (built in)");
  return db;
}

const MaterialRecord* MaterialDatabase::find(std::string_view name) const {
  const std::string key = normalisedName(name);
  for (const MaterialRecord& record : records_) {
    if (normalisedName(record.material.name) == key) return &record;
  }
  return nullptr;
}

const MaterialRecord& MaterialDatabase::at(std::string_view name, const std::string& field) const {
  if (const MaterialRecord* record = find(name)) return *record;
  std::string known;
  for (const MaterialRecord& record : records_) known += (known.empty() ? "" : ", ") + record.material.name;
  throw InputError(field, quotedText(name),
                   "not in the materials database " + origin_ + " (known: " + (known.empty() ? "none" : known) + ")");
}

MaterialDatabase MaterialDatabase::builtInWith(const MaterialDatabase& user) {
  MaterialDatabase db = builtIn();
  db.origin_ += " and " + user.origin_;
  for (const MaterialRecord& record : user.records_) {
    if (const MaterialRecord* clash = db.find(record.material.name)) {
      throw InputError(user.origin_ + ":" + std::to_string(record.line) + ".name", quotedText(record.material.name),
                       "the built-in database already has " + clash->material.name +
                           "; a materials file may only add materials, so give it another name");
    }
    db.records_.push_back(record);
  }
  return db;
}

std::string MaterialDatabase::toCsv(const std::vector<MaterialRecord>& records) {
  std::string out;
  auto number = [&out](double value) {
    std::array<char, 32> buffer{};
    const auto [end, ec] = std::to_chars(buffer.data(), buffer.data() + buffer.size(), value);
    out.append(buffer.data(), ec == std::errc() ? end : buffer.data());
  };
  auto text = [&out](const std::string& value) {
    if (value.find_first_of(",\"") == std::string::npos) {
      out.append(value);
      return;
    }
    out.push_back('"');
    for (char c : value) {
      if (c == '"') out.push_back('"');
      out.push_back(c);
    }
    out.push_back('"');
  };
  for (std::size_t c = 0; c < kColumns.size(); ++c) {
    if (c > 0) out.push_back(',');
    out.append(kColumns[c]);
  }
  out.push_back('\n');
  for (const MaterialRecord& record : records) {
    const Material& m = record.material;
    text(m.name);
    for (double value : {m.density, m.youngs_modulus, m.poisson_ratio, m.restitution, m.sliding_friction,
                         m.rolling_friction}) {
      out.push_back(',');
      number(value);
    }
    out.append(record.size.kind == MaterialSizeRange::Kind::Uniform ? ",uniform," : ",constant,");
    number(record.size.radius_min);
    out.push_back(',');
    number(record.size.radius_max);
    out.push_back(',');
    text(record.source);
    out.push_back(',');
    number(m.cohesion_energy_density);
    out.push_back('\n');
  }
  return out;
}

std::vector<std::string> MaterialDatabase::names() const {
  std::vector<std::string> out;
  out.reserve(records_.size());
  for (const MaterialRecord& record : records_) out.push_back(record.material.name);
  return out;
}

}  // namespace demlink::core
