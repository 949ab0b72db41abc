#pragma once
/// demlink-calibrate's TARGETS file (proto/demlink/v1/calibration.proto), read and checked:
/// the base material resolved in the materials database, the parameters to fit and the
/// measurements, each mapped to a scene of the atlas (calibration_scenes.hpp).
#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "calibration_fit.hpp"
#include "demlink/core/materials/material_database.hpp"

namespace demlink::calibrate {

/// A parameter the fit may change.
enum class Parameter : std::uint8_t { SlidingFriction, RollingFriction, CohesionEnergyDensity };
/// Its name in TARGETS files, reports and the materials file's columns.
[[nodiscard]] const char* parameterName(Parameter parameter);
/// Sets `parameter` of `material` to `value`.
void setParameter(core::Material& material, Parameter parameter, double value);

/// A bulk quantity the user measured.
enum class Quantity : std::uint8_t { AngleOfRepose, BulkDensity, HopperDischarge, SlumpHeightRatio };
[[nodiscard]] const char* quantityName(Quantity quantity);
[[nodiscard]] const char* quantityUnit(Quantity quantity);

struct FitParameter {
  Parameter parameter = Parameter::SlidingFriction;
  Bounds bounds;
};

struct Measurement {
  Quantity quantity = Quantity::AngleOfRepose;
  double value = 0.0;    ///< in quantityUnit: deg, kg/m^3, kg/s, -
  double orifice = 0.0;  ///< hopper discharge only: the square orifice's side [m]
};

struct Targets {
  std::filesystem::path file;       ///< the TARGETS file
  core::MaterialRecord base;        ///< the base material (size, source) as found
  std::string name;                 ///< of the calibrated entry
  std::vector<FitParameter> fit;    ///< 1..3, each parameter once
  std::vector<Measurement> measurements;  ///< at least fit.size()
  std::uint32_t fit_seeds = 2;
  std::uint32_t uncertainty_seeds = 4;
};

/// Reads and checks a TARGETS file. Throws core::InputError whose field is
/// "<file>:<field path>" (e.g. "targets.json:fit[1].max") and whose value is the offending
/// one: unreadable or malformed JSON, an unknown field, an unknown material or parameter,
/// a parameter twice, missing or inverted bounds, a negative or missing measured value,
/// fewer measurements than parameters, or a hopper the calibration cannot run in seconds.
[[nodiscard]] Targets readTargets(const std::filesystem::path& file);

/// The same checks on TARGETS JSON held in memory; `file` names it in errors and anchors a
/// relative materials_file.
[[nodiscard]] Targets parseTargets(const std::string& json, const std::filesystem::path& file);

}  // namespace demlink::calibrate
