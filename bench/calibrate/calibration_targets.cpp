#include "calibration_targets.hpp"

#include <cmath>
#include <limits>

#include "calibration_scenes.hpp"
#include "demlink/core/base/input_error.hpp"
#include "demlink/core/base/input_file.hpp"
#include "demlink/core/base/log_text.hpp"
#include "demlink/server/scene/scene_loader.hpp"
#include "demlink/v1/calibration.pb.h"

namespace demlink::calibrate {
namespace {

using core::InputError;

constexpr std::uint32_t kMaxSeeds = 20;

/// A required number of a TARGETS file: present, finite, within [low, high] (or above low
/// when `strictly`).
double required(bool present, double value, const std::string& field, double low, bool strictly,
                double high = std::numeric_limits<double>::infinity()) {
  if (!present) throw InputError(field, "(missing)", "required");
  if (!std::isfinite(value)) throw InputError(field, core::formatValue(value), "must be a finite number");
  if (strictly ? !(value > low) : !(value >= low)) {
    throw InputError(field, core::formatValue(value), std::string(strictly ? "must be > " : "must be >= ") +
                                                          core::formatValue(low));
  }
  if (!(value < high)) throw InputError(field, core::formatValue(value), "must be < " + core::formatValue(high));
  return value;
}

Parameter parameterNamed(const std::string& name, const std::string& field) {
  for (Parameter p : {Parameter::SlidingFriction, Parameter::RollingFriction, Parameter::CohesionEnergyDensity}) {
    if (name == parameterName(p)) return p;
  }
  throw InputError(field, name.empty() ? "(missing)" : core::quotedLogText(name),
                   "unknown parameter (known: sliding_friction, rolling_friction, cohesion_energy_density)");
}

std::uint32_t seeds(bool present, std::uint32_t value, std::uint32_t fallback, std::uint32_t low,
                    const std::string& field) {
  if (!present) return fallback;
  if (value < low || value > kMaxSeeds) {
    throw InputError(field, std::to_string(value),
                     "must be in " + std::to_string(low) + ".." + std::to_string(kMaxSeeds));
  }
  return value;
}

Targets checked(const v1::CalibrationTargets& in, const std::filesystem::path& file) {
  Targets out;
  out.file = file;
  if (in.material().empty()) throw InputError("material", "(missing)", "the base material's name is required");
  core::MaterialDatabase database = core::MaterialDatabase::builtIn();
  if (!in.materials_file().empty()) {
    std::filesystem::path path = in.materials_file();
    if (path.is_relative()) path = file.parent_path() / path;
    try {
      database = core::MaterialDatabase::builtInWith(core::MaterialDatabase::fromFile(path));
    } catch (const InputError& error) {
      throw error.as("materials_file");
    }
  }
  out.base = database.at(in.material(), "material");
  out.name = in.name().empty() ? core::MaterialDatabase::normalisedName(out.base.material.name) + "_calibrated"
                               : in.name();
  if (core::MaterialDatabase::builtIn().find(out.name) != nullptr) {
    throw InputError("name", core::quotedLogText(out.name),
                     "is a built-in material's name; the calibrated entry needs its own");
  }

  if (in.fit_size() == 0) throw InputError("fit", "(missing)", "give 1 to 3 parameters to fit");
  if (in.fit_size() > 3) throw InputError("fit", std::to_string(in.fit_size()) + " parameters", "at most 3");
  for (int k = 0; k < in.fit_size(); ++k) {
    const v1::CalibrationTargets::Parameter& p = in.fit(k);
    const std::string field = "fit[" + std::to_string(k) + "]";
    FitParameter fit;
    fit.parameter = parameterNamed(p.name(), field + ".name");
    for (const FitParameter& other : out.fit) {
      if (other.parameter == fit.parameter) {
        throw InputError(field + ".name", core::quotedLogText(p.name()), "is fitted twice");
      }
    }
    fit.bounds.min = required(p.has_min(), p.min(), field + ".min", 0.0, false);
    fit.bounds.max = required(p.has_max(), p.max(), field + ".max", 0.0, false);
    if (!(fit.bounds.max > fit.bounds.min)) {
      throw InputError(field + ".max", core::formatValue(fit.bounds.max),
                       "must be > min (" + core::formatValue(fit.bounds.min) + ")");
    }
    out.fit.push_back(fit);
  }

  const v1::CalibrationTargets::Measurements& m = in.measurements();
  if (m.has_angle_of_repose()) {
    out.measurements.push_back({Quantity::AngleOfRepose,
                                required(true, m.angle_of_repose(), "measurements.angle_of_repose", 0.0, true, 90.0)});
  }
  if (m.has_bulk_density()) {
    out.measurements.push_back(
        {Quantity::BulkDensity, required(true, m.bulk_density(), "measurements.bulk_density", 0.0, true,
                                         out.base.material.density)});
  }
  if (m.has_hopper_discharge()) {
    const auto& h = m.hopper_discharge();
    const std::string field = "measurements.hopper_discharge";
    Measurement hopper{Quantity::HopperDischarge,
                       required(h.has_rate(), h.rate(), field + ".rate", 0.0, true)};
    hopper.orifice = required(h.has_orifice(), h.orifice(), field + ".orifice", 0.0, true);
    const double diameter = out.base.size.radius_min + out.base.size.radius_max;
    if (hopper.orifice < kMinOrificeDiameters * diameter) {
      throw InputError(field + ".orifice", core::formatValue(hopper.orifice),
                       "must be >= " + core::formatValue(kMinOrificeDiameters) + " mean grain diameters (" +
                           core::formatValue(kMinOrificeDiameters * diameter) + " m for " +
                           out.base.material.name + "): a narrower orifice jams");
    }
    const double grains = hopperGrainCount(out.base.size, hopper.orifice);
    if (grains > kMaxHopperGrains) {
      throw InputError(field + ".orifice", core::formatValue(hopper.orifice),
                       "the hopper scene would hold " + std::to_string(std::lround(grains)) + " grains of " +
                           out.base.material.name + " (at most " + std::to_string(std::lround(kMaxHopperGrains)) +
                           " run in seconds); measure with a smaller orifice or coarser grains");
    }
    out.measurements.push_back(hopper);
  }
  if (m.has_slump_height_ratio()) {
    out.measurements.push_back({Quantity::SlumpHeightRatio, required(true, m.slump_height_ratio(),
                                                                     "measurements.slump_height_ratio", 0.0, true, 1.0)});
  }
  if (out.measurements.size() < out.fit.size()) {
    throw InputError("measurements", std::to_string(out.measurements.size()) + " given",
                     "fitting " + std::to_string(out.fit.size()) +
                         " parameters needs at least as many measurements (angle_of_repose, bulk_density, "
                         "hopper_discharge, slump_height_ratio)");
  }
  out.fit_seeds = seeds(in.has_fit_seeds(), in.fit_seeds(), 2, 1, "fit_seeds");
  out.uncertainty_seeds = seeds(in.has_uncertainty_seeds(), in.uncertainty_seeds(), 4, 2, "uncertainty_seeds");
  return out;
}

}  // namespace

const char* parameterName(Parameter parameter) {
  switch (parameter) {
    case Parameter::SlidingFriction: return "sliding_friction";
    case Parameter::RollingFriction: return "rolling_friction";
    case Parameter::CohesionEnergyDensity: return "cohesion_energy_density";
  }
  return "?";
}

void setParameter(core::Material& material, Parameter parameter, double value) {
  switch (parameter) {
    case Parameter::SlidingFriction: material.sliding_friction = value; return;
    case Parameter::RollingFriction: material.rolling_friction = value; return;
    case Parameter::CohesionEnergyDensity: material.cohesion_energy_density = value; return;
  }
}

const char* quantityName(Quantity quantity) {
  switch (quantity) {
    case Quantity::AngleOfRepose: return "angle_of_repose";
    case Quantity::BulkDensity: return "bulk_density";
    case Quantity::HopperDischarge: return "hopper_discharge";
    case Quantity::SlumpHeightRatio: return "slump_height_ratio";
  }
  return "?";
}

const char* quantityUnit(Quantity quantity) {
  switch (quantity) {
    case Quantity::AngleOfRepose: return "deg";
    case Quantity::BulkDensity: return "kg/m^3";
    case Quantity::HopperDischarge: return "kg/s";
    case Quantity::SlumpHeightRatio: return "-";
  }
  return "?";
}

Targets parseTargets(const std::string& json, const std::filesystem::path& file) {
  v1::CalibrationTargets in;
  server::parseJsonMessage(json, file.string(), "calibration targets",
                           "{\"material\": ..., \"fit\": [...], \"measurements\": {...}}", in);
  try {
    return checked(in, file);
  } catch (const InputError& error) {
    throw InputError(file.string() + ":" + error.field(), error.value(), error.reason());
  }
}

Targets readTargets(const std::filesystem::path& file) {
  return parseTargets(core::readInputFile("TARGETS", file), file);
}

}  // namespace demlink::calibrate
