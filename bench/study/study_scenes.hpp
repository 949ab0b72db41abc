#pragma once
/// The scenes of the speed-for-accuracy atlas (demlink-study, docs/accuracy.md) and the
/// bulk quantity each one measures. Every scene is built from one Knobs value, so a sweep
/// changes one knob and keeps the others at the finest setting.
///
/// Scenes (all with one material, Knobs::grains: spheres with radii uniform in
/// [radius_min, radius_max], by default the reference grains' [r, 1.2 r]):
///   impact  two spheres head-on at 1 m/s, no gravity: delivered / requested restitution;
///   bed     spheres rain into a long box around a still blade and settle: packing
///           fraction of the bed's core; then the blade moves through the bed at a
///           constant speed and stops 10 grain diameters short of the far wall: mean drag
///           force over the steady window (the last two thirds of its travel);
///   bed_cohesive  the same bed with a cohesive material (Budget::cohesion_energy_density,
///           the moist-soil law of docs/materials.md): the drag an excavator model feels;
///   heap    a block of spheres collapses on a rough floor: angle of repose of the heap,
///           and (runSlump, demlink-calibrate only) a column's slump out of its mould;
///   hopper  a box with a square orifice in its floor, closed by a gate while it fills:
///           mass discharge rate once the gate opens.
#include <cstdint>
#include <functional>
#include <string>
#include <utility>
#include <vector>

#include "demlink/core/world.hpp"

namespace demlink::study {

using demlink::core::ContactModel;
using demlink::core::IntegratorKind;

/// Grain radius of the atlas's reference grains (before coarse graining) [m].
inline constexpr double kGrainRadius = 0.0025;

/// What a scene is made of: one material and radii uniform in [radius_min, radius_max]
/// (before coarse graining). Every scene's geometry (footprints, the bed's box and blade,
/// the hopper's lattice height) scales with radius_min / kGrainRadius, so a scene of other
/// grains is the atlas's scene at another size.
struct Grains {
  demlink::core::Material material;  ///< Young's modulus before Knobs::modulus_scale
  double radius_min = kGrainRadius;  ///< [m]
  double radius_max = 1.2 * kGrainRadius;  ///< [m]
};
/// The atlas's grains: glass-like, radius uniform in [2.5, 3.0] mm, density 2500 kg/m^3,
/// a "real" modulus of 1e8 Pa, e = 0.5, mu = 0.5, rolling friction 0.1 (it keeps a heap of
/// spheres standing).
[[nodiscard]] Grains referenceGrains();

/// One point of a sweep: the engine's speed/accuracy knobs, and the grains they run.
struct Knobs {
  double dt_fraction = 0.1;  ///< time step / critical limit [-]
  ContactModel law = ContactModel::HertzMindlin;
  IntegratorKind integrator = IntegratorKind::VelocityVerlet;
  double skin_factor = 0.5;    ///< neighbour skin / smallest radius [-]
  double modulus_scale = 1.0;  ///< Young's modulus / the reference modulus [-]
  double coarse = 1.0;         ///< coarse-graining factor alpha (core::CoarseGraining) [-]
  std::uint64_t seed = 1;      ///< jitter of the initial lattices [-]
  Grains grains = referenceGrains();  ///< the atlas's; a calibration gives its material's
};

/// Sizes and durations: the full atlas or the CI smoke run.
struct Budget {
  std::size_t bed_grains = 1000;     ///< grains (before coarse graining) [-]
  std::size_t heap_grains = 500;
  std::size_t hopper_grains = 700;
  /// Bed size factor: every scene's footprint area and grain count grow by it, so its
  /// depth (and the hopper's orifice, the blade's travel) stays [-], >= 1.
  double scale = 1.0;
  /// The bed's footprint area / 0.1 m x 0.05 m before `scale` (the smoke run's small bed) [-].
  double bed_area = 1.0;
  double bed_settle = 0.25;          ///< [s]
  double drag_time = 0.3;            ///< blade travel time at 0.1 m/s [s]
  /// k_c of the cohesive bed (bed_cohesive) [J/m^3]; see docs/accuracy.md "Cohesive drag".
  double cohesion_energy_density = 1.5e5;
  double heap_time = 0.4;            ///< [s]
  std::size_t slump_grains = 400;    ///< slump test's column (runSlump)
  double slump_settle = 0.15;        ///< [s] in the mould
  double slump_time = 0.3;           ///< [s] after the mould is lifted
  double hopper_fill = 0.25;         ///< [s]
  double hopper_flow = 0.2;          ///< [s]
  /// Side of the hopper's square orifice [m]; the box's side is 2.4 times it and the grain
  /// count grows with (orifice / grain size)^3 from hopper_grains at 25 mm and the
  /// reference grains, so the bed keeps its depth in orifice sizes.
  double hopper_orifice = 0.025;
  /// A scene whose thread used more CPU seconds is abandoned [s]: CPU, not wall, so a
  /// loaded machine does not break scenes that an idle one runs.
  double cpu_limit = 600.0;
};

/// The grains' material with Knobs::modulus_scale applied.
[[nodiscard]] demlink::core::Material studyMaterial(const Knobs& knobs);
/// The smallest and the largest radius of the grains after coarse graining [m].
[[nodiscard]] double parcelRadius(const Knobs& knobs);
[[nodiscard]] double parcelRadiusMax(const Knobs& knobs);
/// Largest impact speed the time-step limit is validated for [m/s].
inline constexpr double kImpactSpeed = 2.0;
/// Restitution tolerance of the limit: a scene file's default (docs/physics.md), so
/// dt_fraction 1 is the largest step a scene accepts without allow_unsafe_time_step.
inline constexpr double kRestitutionTolerance = 0.1;

/// Settings for `knobs`: the time step is dt_fraction times the critical limit of the
/// scene's smallest particle (unsafe steps allowed: the atlas probes past the limit).
[[nodiscard]] demlink::core::SimulationSettings studySettings(const Knobs& knobs);
/// The critical limit for `knobs` with velocity Verlet (the integrator knob is compared at
/// the same step) [s].
[[nodiscard]] double criticalLimit(const Knobs& knobs);

/// What a scene run measured and what it cost.
struct SceneResult {
  explicit SceneResult(std::string name = {}) : scene(std::move(name)) {}
  std::string scene;
  std::string status = "ok";  ///< "ok", or why the run broke
  double simulated = 0.0;     ///< [s]
  double wall = 0.0;          ///< [s]
  double particle_steps = 0.0;
  std::vector<std::pair<std::string, double>> metrics;  ///< name, value (SI or [-])
};

[[nodiscard]] SceneResult runImpact(const Knobs& knobs);
/// The settled dry bed of one setting and seed, shared by its dry and cohesive strokes so
/// the bed settles once (a checkpoint, World::saveCheckpoint).
struct SettledBed {
  const std::string* from = nullptr;  ///< start from this settled bed instead of settling one
  std::string* to = nullptr;          ///< the settled bed is written here
};
/// The bed and blade; `cohesive` gives the grains Budget::cohesion_energy_density. With
/// `settled.from`, the run starts from that bed and its cost is the blade's stroke alone.
[[nodiscard]] SceneResult runBed(const Knobs& knobs, const Budget& budget, bool cohesive = false,
                                 SettledBed settled = {});
[[nodiscard]] SceneResult runHeap(const Knobs& knobs, const Budget& budget);
/// A slump test: a square column of grains settles in a mould (Budget::slump_settle), the
/// mould is lifted (its walls stop touching the grains) and the column slumps for
/// Budget::slump_time; metric slump_height_ratio, the 95th-percentile centre height after
/// over the one before [-]. Cohesion holds the column up.
[[nodiscard]] SceneResult runSlump(const Knobs& knobs, const Budget& budget);
[[nodiscard]] SceneResult runHopper(const Knobs& knobs, const Budget& budget);
/// Grains of the hopper scene for `knobs`' grains and `budget`'s orifice and scale
/// (before coarse graining) [-].
[[nodiscard]] std::size_t hopperGrains(const Knobs& knobs, const Budget& budget);

/// CPU seconds this thread has used (a scene runs on one thread) [s].
[[nodiscard]] double threadCpuSeconds();
/// Steps `world` to `until` [s], counting particle-steps into `result`; throws
/// std::runtime_error if this thread's CPU time passes `cpuLimit` or a position is not finite.
void advance(demlink::core::World& world, double until, SceneResult& result, double cpuLimit,
             const std::function<void()>& afterStep = {});

/// A cubic lattice of `count` spheres of material 0 over the footprint of [lo, hi] (x
/// fastest, filling upward from lo.z), radii uniform in [radius, radiusMax], jittered;
/// lattice points where `free` is false are skipped. Returns the highest centre [m].
double addLattice(demlink::core::World& world, std::size_t count, double radius, double radiusMax,
                  const demlink::core::Vec3& lo, const demlink::core::Vec3& hi, std::uint64_t seed,
                  const std::function<bool(const demlink::core::Vec3&)>& free = {});

}  // namespace demlink::study
