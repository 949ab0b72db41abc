#pragma once
/// The named fields of each component kind an FMU configuration declares, and where each
/// goes in the C ABI's generic declare layout (demlink_c.h, "Generic layout"): the one
/// place that gives the layout's positions names and units, so a configuration never
/// writes a position and a misplaced value cannot silently land in another field.
#include <string>
#include <utility>
#include <vector>

namespace demlink::fmu {

/// Which array of the declare package a field fills.
enum class FieldArray { kReals, kInts, kStrings };

/// How a field's text is read.
enum class FieldType {
  kReal,        ///< `count` numbers separated by spaces
  kInteger,     ///< one whole number
  kChoice,      ///< one of `choices` (stored as its number in ints)
  kText,        ///< the rest of the line (may be empty)
  kTextList,    ///< names separated by spaces, from `index` to the end of strings
  kRealList,    ///< numbers in groups of `count`, from `index` to the end of reals
};

struct FieldSpec {
  const char* name;
  FieldType type;
  FieldArray array;
  int index;  ///< position in the layout's array (reals[1] is the first after the interval)
  int count = 1;
  const char* unit = "";  ///< SI unit of a real field ("" dimensionless)
  std::vector<std::pair<const char*, long long>> choices = {};
  /// The field needs this choice field to have this value, e.g. a sphere's radius needs
  /// shape = sphere ({"shape", "sphere"}); {nullptr, nullptr}: no condition.
  std::pair<const char*, const char*> requires_choice = {nullptr, nullptr};
  /// Of a real field when unset (empty: NaN, "not given"); a choice field with any default
  /// is written even when unset, as its first choice.
  std::vector<double> defaults = {};
  bool required = false;
};

/// The fields of a kind the FMU carries; std::invalid_argument for any other kind.
const std::vector<FieldSpec>& fieldsOf(const std::string& kind);

}  // namespace demlink::fmu
