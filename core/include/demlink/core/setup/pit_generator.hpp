#pragma once
/// PitGenerator: fills an axis-aligned box with a settled bed of one material up to
/// a target height (the coupling paper's "PitGenerator"; its excavator example is a
/// 6.0 x 2.0 x 1.0 m pit of gravel).
///
/// Method:
///   1. rain: a loose cubic lattice (spacing 2.3 r_max, seeded jitter +-0.05 r_max,
///      radii from the size distribution) starting at the floor, holding
///      overfill x packing_fraction x (box area x target height) of solid volume;
///   2. settle: a private World (the pit material, a floor and four side walls, the
///      main world's contact model and |g| along -z, time step the critical limit at the
///      engine's default restitution tolerance, 1 %, and the impact speed of a fall from
///      the top of the lattice) runs until the rained column has had time to fall and the
///      mean kinetic energy per particle of the whole rain is below the threshold (or
///      max_settle_time passes, with a warning). Not of the kept particles alone: the
///      overburden's last motion still compacts the bed's top, and a plate pressed into
///      a small pit settled by that rule rested 1.6 mm lower and 14x as sensitive to the
///      coupling interval (docs/sources.md);
///   3. keep: the particles whose top (z + r) lies at or below lower.z + target_height
///      are copied into the main world at rest, in lattice order.
/// Why a private world: settling needs many steps; doing it apart from the scene keeps
/// the scene's own planes, meshes and sources out of it and makes the bed depend only
/// on the pit's inputs and seed (same seed, same bed; another seed, another bed).
/// The generator does not look at particles already in the main world.
///
/// Clumps: with `clump_template` set, every lattice point gets one clump of that
/// template (seeded uniform random orientation), r_max above is the template's
/// bounding radius about its COM, the kinetic energy is per clump, and a clump is
/// kept when its highest member top lies at or below the target surface and its COM
/// lies inside the box footprint; it is copied with World::addClump at the same COM
/// and orientation (ClumpSpec wants the template frame: body orientation times the
/// inverse principal rotation), at rest.
///
/// Clods (spheres only): with clod_fraction > 0 the kept bed is grouped into clods of
/// about clod_radius (bonds/clods.hpp, seeded by the pit's seed) and the report lists
/// each member's id and clod, for the bond rule that joins them (BondRule::groups). The
/// bed itself is the same with or without clods.
#include <cstdint>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "demlink/core/base/math_types.hpp"
#include "demlink/core/components/size_distribution.hpp"

namespace demlink::core {

class World;

struct PitSpec {
  Vec3 lower = Vec3::Zero();     ///< box lower corner [m]
  Vec3 upper = Vec3::Zero();     ///< box upper corner [m]
  double target_height = 0.0;    ///< bed surface above lower.z [m], in (0, upper.z - lower.z]
  std::uint32_t material = 0;
  SizeDistribution sizes;  ///< spheres only
  /// Index of a clump template of the main world (World::addClumpTemplate); unset: spheres.
  std::optional<std::uint32_t> clump_template;
  std::uint64_t seed = 0;
  double packing_fraction = 0.6;  ///< estimate of the settled solid fraction [-], in (0, 0.75]
  double overfill = 1.25;         ///< rain this multiple of the estimated need [-], >= 1
  /// Settled when the mean kinetic energy per particle is below this [J]; 0: 1e-4 m g d
  /// of the mean particle (mass m, diameter d).
  double kinetic_energy_threshold = 0.0;
  /// Give up settling after this simulated time [s]; 0: 10 free-fall times of the rain column.
  double max_settle_time = 0.0;
  double clod_fraction = 0.0;  ///< of the kept spheres put into clods [-], in [0, 1]; 0: no clods
  double clod_radius = 0.0;    ///< [m], > 0 with clod_fraction > 0
  double clod_gap = 0.0;       ///< surface gap of touching spheres in a clod [m]: the bond rule's gap tolerance

  /// Throws InputError naming `fieldPrefix + ".<field>"`. For clumps the fit of the
  /// box and target height is checked against `clumpBoundingRadius` [m] (0: not checked).
  void validate(const std::string& fieldPrefix, double clumpBoundingRadius = 0.0) const;
};

struct PitReport {
  std::uint64_t rained = 0;           ///< particles (clumps) settled in the private world
  std::uint64_t kept = 0;             ///< particles (clumps) copied into the main world
  double kept_mass = 0.0;             ///< [kg]
  double bed_top = 0.0;               ///< highest z + r of the kept particles [m]
  double settle_time = 0.0;           ///< simulated settling time [s]
  std::uint64_t settle_steps = 0;
  double settle_wall_seconds = 0.0;   ///< wall-clock time of the settling loop [s]
  /// Solid volume of the kept particles over the box's footprint times the target height [-].
  double packing_fraction = 0.0;
  double final_mean_kinetic_energy = 0.0;  ///< [J] per particle (per clump)
  double threshold = 0.0;             ///< the kinetic energy threshold used [J]
  bool settled = false;               ///< false: stopped at max_settle_time
  std::uint32_t clods = 0;            ///< clods formed [-]
  /// (particle id in the main world, clod number from 1) of every sphere in a clod.
  std::vector<std::pair<std::uint64_t, std::uint32_t>> clod_members;
};

/// Settles a bed as described above and adds it to `world` (materials must be
/// registered; call before World::initialize()). Logs progress with spdlog.
PitReport generatePit(World& world, const PitSpec& spec, const std::string& name, const std::string& fieldPrefix);

}  // namespace demlink::core
