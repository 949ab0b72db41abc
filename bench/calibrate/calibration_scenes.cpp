#include "calibration_scenes.hpp"

#include <stdexcept>
#include <string>

namespace demlink::calibrate {
namespace {

double metric(const study::SceneResult& result, const std::string& name) {
  for (const auto& [key, value] : result.metrics) {
    if (key == name) return value;
  }
  throw std::logic_error("scene " + result.scene + " reported no " + name);
}

}  // namespace

study::Budget calibrationBudget() {
  study::Budget b;
  b.heap_grains = 300;
  b.heap_time = 0.3;
  b.bed_grains = 400;
  b.bed_area = 0.4;
  b.bed_settle = 0.2;
  b.drag_time = 0.0;  // the packing is measured before the blade would move
  b.hopper_grains = 700;
  b.hopper_fill = 0.25;
  b.hopper_flow = 0.15;
  b.cpu_limit = 120.0;
  return b;
}

study::Grains grainsOf(const core::Material& material, const core::MaterialSizeRange& size) {
  return study::Grains{material, size.radius_min, size.radius_max};
}

double hopperGrainCount(const core::MaterialSizeRange& size, double orifice) {
  study::Knobs knobs;
  knobs.grains.radius_min = size.radius_min;
  knobs.grains.radius_max = size.radius_max;
  study::Budget budget = calibrationBudget();
  budget.hopper_orifice = orifice;
  return static_cast<double>(study::hopperGrains(knobs, budget));
}

double measure(const Measurement& measurement, const study::Grains& grains, std::uint64_t seed, double dtFraction) {
  study::Knobs knobs;
  knobs.grains = grains;
  knobs.seed = seed;
  knobs.dt_fraction = dtFraction;
  study::Budget budget = calibrationBudget();
  try {
    switch (measurement.quantity) {
      case Quantity::AngleOfRepose:
        return metric(study::runHeap(knobs, budget), "repose_angle_deg");
      case Quantity::BulkDensity:
        return metric(study::runBed(knobs, budget), "packing_fraction") * grains.material.density;
      case Quantity::SlumpHeightRatio:
        return metric(study::runSlump(knobs, budget), "slump_height_ratio");
      case Quantity::HopperDischarge:
        budget.hopper_orifice = measurement.orifice;
        return metric(study::runHopper(knobs, budget), "discharge_rate");
    }
  } catch (const std::runtime_error& error) {
    throw std::runtime_error(std::string("the ") + quantityName(measurement.quantity) + " scene broke (seed " +
                             std::to_string(seed) + "): " + error.what());
  }
  throw std::logic_error("unknown quantity");
}

}  // namespace demlink::calibrate
