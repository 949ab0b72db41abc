#pragma once
/// What demlink-calibrate runs for each measurement: the atlas's scenes (bench/study,
/// docs/accuracy.md) with the calibrated material's grains, at the sizes of
/// calibrationBudget() so that one run takes seconds:
///   angle_of_repose   heap: a block of 300 grains collapses on a floor of the same
///                     material (0.3 s); the flank's angle [deg];
///   slump_height_ratio slump: a column of 400 grains settles in a mould (0.15 s), the mould
///                     is lifted and it slumps (0.3 s); its height after over before [-]
///                     (cohesion holds the column up);
///   bulk_density      bed: 400 grains rain into a box 0.63 x 0.32 of the atlas's footprint
///                     (lengths in the grains' size) and settle (0.2 s); packing fraction of
///                     the bed's core x particle density [kg/m^3];
///   hopper_discharge  hopper: a flat-floored box 2.4 orifices wide, filled with grains to
///                     the atlas's depth in orifices (700 grains at 10 grain radii), gate
///                     open at 0.25 s; discharge rate over 0.05-0.15 s after [kg/s].
#include <cstdint>

#include "calibration_targets.hpp"
#include "study_scenes.hpp"

namespace demlink::calibrate {

/// The scenes' sizes and durations (above).
[[nodiscard]] study::Budget calibrationBudget();

/// Narrowest orifice a hopper measurement may name, in mean grain diameters [-]: the
/// atlas's is 4.5; much below it the grains arch over the orifice and the flow stops.
inline constexpr double kMinOrificeDiameters = 4.0;

/// Largest grain count of a calibration's hopper scene [-]: an orifice much wider than the
/// grains needs a bed too large to run in seconds.
inline constexpr double kMaxHopperGrains = 3000.0;

/// The grains of `material` with `size`'s radii.
[[nodiscard]] study::Grains grainsOf(const core::Material& material, const core::MaterialSizeRange& size);

/// Grains the hopper scene holds for grains of `size` and this orifice [-].
[[nodiscard]] double hopperGrainCount(const core::MaterialSizeRange& size, double orifice);

/// The bulk quantity of `measurement`'s scene for `grains` with lattice seed `seed`, at a
/// time step of `dtFraction` of the critical limit, in quantityUnit(). Throws
/// std::runtime_error naming the scene when it broke (watchdog, CPU limit).
[[nodiscard]] double measure(const Measurement& measurement, const study::Grains& grains, std::uint64_t seed,
                             double dtFraction);

}  // namespace demlink::calibrate
