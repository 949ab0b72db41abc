#pragma once
/// The materials database: named bulk materials (gravel, sand, coals, ores,
/// grains) with contact parameters and a default particle size distribution.
///
/// Why a plain CSV file: it is readable and editable without tools, diffs well,
/// and core can parse it without a new dependency. Why embedded: the built-in
/// database (data/materials.csv) is compiled into the library at build time, so
/// it works from the build tree, an installed tree or a copied binary without a
/// data path to configure. Other files load with MaterialDatabase::fromFile.
///
/// Lookup is by normalised name: ASCII case-insensitive, with ' ' and '-' equal
/// to '_' ("Hard Coal", "hard-coal" and "hard_coal" are the same material).
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

#include "demlink/core/materials/material.hpp"

namespace demlink::core {

/// Default radius distribution of a database material (its own type: the particle
/// sources' core::SizeDistribution describes more shapes and is a different type).
struct MaterialSizeRange {
  enum class Kind : std::uint8_t {
    Constant,  ///< every radius is radius_min (= radius_max)
    Uniform,   ///< radius uniform in [radius_min, radius_max]
  };
  Kind kind = Kind::Constant;
  double radius_min = 0.0;  ///< [m]
  double radius_max = 0.0;  ///< [m]
};

/// One row of the database.
struct MaterialRecord {
  Material material;      ///< name as written in the file; values SI
  MaterialSizeRange size;  ///< default particle radii
  std::string source;     ///< citation or "estimate: why"
  std::size_t line = 0;   ///< line in the file it was read from [-]
};

class MaterialDatabase {
 public:
  /// Parses CSV text. `origin` names the text in errors ("file:line.column").
  /// Throws InputError for a missing or unknown column, a wrong field count, a
  /// non-numeric or out-of-range value (Material::validate rules, radii > 0 and
  /// ordered), an unknown size kind, an empty source or a duplicate name.
  static MaterialDatabase parse(std::string_view text, const std::string& origin);
  /// Reads and parses a file; throws InputError if it cannot be read.
  static MaterialDatabase fromFile(const std::filesystem::path& path);
  /// The database shipped with DEMLink (data/materials.csv as of the build).
  static const MaterialDatabase& builtIn();
  /// The built-in materials followed by `user`'s (a scene's materials_file). A user file
  /// may only add materials: a name the built-in database has (after normalisation) throws
  /// InputError naming "<user origin>:<line>.name", so a scene name never means two things.
  static MaterialDatabase builtInWith(const MaterialDatabase& user);
  /// `records` as the text of a database file (header and one row each) that parse()
  /// reads back to the same values; numbers are written shortest round-trip.
  static std::string toCsv(const std::vector<MaterialRecord>& records);

  /// The record named `name` (normalised lookup) or nullptr.
  [[nodiscard]] const MaterialRecord* find(std::string_view name) const;
  /// The record named `name`; throws InputError(field, name, ...) listing the
  /// known names when there is none.
  [[nodiscard]] const MaterialRecord& at(std::string_view name, const std::string& field) const;
  /// Names in file order.
  [[nodiscard]] std::vector<std::string> names() const;
  [[nodiscard]] const std::vector<MaterialRecord>& records() const { return records_; }
  [[nodiscard]] const std::string& origin() const { return origin_; }

  /// The lookup key of a name: lower case, ' ' and '-' replaced by '_'.
  static std::string normalisedName(std::string_view name);

 private:
  std::string origin_;
  std::vector<MaterialRecord> records_;
};

}  // namespace demlink::core
