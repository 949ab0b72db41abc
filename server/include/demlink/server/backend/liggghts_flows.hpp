#pragma once
/// Particle sources, sinks and sensors of a compiled world on the LIGGGHTS backend
/// (docs/scale-out.md has the mapping table). Kept free of LIGGGHTS and MPI, like
/// liggghts_script.hpp, so it builds and is tested everywhere.
///
/// Sources become LIGGGHTS insertion fixes: LIGGGHTS places the particles, and the backend
/// adds each atom it has not seen before to the compiled world on syncParticles() (a new
/// stable id). Sinks and sensors are not LIGGGHTS fixes: they are our own components, run
/// on the compiled world after each hand-over (liggghtsStride steps), so they report
/// exactly what our engine's code reports for the particles handed over; the atoms a sink
/// removed are then deleted in LIGGGHTS.
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "demlink/core/components/particle_source.hpp"
#include "demlink/core/components/size_distribution.hpp"
#include "demlink/core/world.hpp"

namespace demlink::server {

/// Classes a continuous size distribution (uniform, linear, normal) is split into.
inline constexpr int kLiggghtsSizeClasses = 8;

/// One size class of a LIGGGHTS discrete distribution.
struct LiggghtsSizeClass {
  double radius = 0.0;           ///< [m]
  double number_fraction = 0.0;  ///< probability of the class [-]; the classes sum to 1
};

/// `sizes` as LIGGGHTS's discrete classes: a fixed radius and a discrete distribution as
/// they are; a continuous one as kLiggghtsSizeClasses classes of equal width in
/// [r_min, r_max], each with its probability and the radius of its mean volume
/// (E[r^3 | class])^(1/3), so the mean particle mass, and the count a kg/s rate gives, are
/// ours (to the quadrature's ~1e-10).
[[nodiscard]] std::vector<LiggghtsSizeClass> liggghtsSizeClasses(const core::SizeDistribution& sizes);

/// The id of an insertion fix of the world's `source`-th particle source (its global
/// vector: particles inserted, mass inserted [kg]). Generation 0 is the fix the backend
/// starts with (it also names the source's templates and region); a run-time change of the
/// rate or of on/off replaces the fix by one of the next generation.
[[nodiscard]] std::string liggghtsInsertFix(std::size_t source, std::uint32_t generation = 0);

/// The rate `source` inserts at now, in its declared unit: its rate, or 0 when switched off.
[[nodiscard]] double liggghtsSourceRate(const core::ParticleSource& source);

/// The `fix ... insert/rate/region` command of the world's `index`-th source at its current
/// rate (liggghtsSourceRate) from the world's current step on, with id
/// liggghtsInsertFix(index, generation); empty when it inserts nothing (off, rate 0 or past
/// its stop time). A finite stop time limits the amount: generation 0 to rate x the active
/// time (a restored fix continues its count), a replacement to what is left at its rate.
[[nodiscard]] std::string liggghtsInsertCommand(const core::World& world, const core::ParticleSource& source,
                                                std::size_t index, std::uint32_t generation);

/// The commands of the world's particle sources, in order (per source: one
/// particletemplate/sphere per size class, particledistribution/discrete/numberbased, the
/// region, and fix insert/rate/region when it inserts now). Every source gets its region,
/// so a client can switch it on later. Refuses, with an InputError naming the source's field,
/// what LIGGGHTS cannot insert as we do: a region attached to a mesh, a rotated box, a disc
/// whose normal is not along x, y or z or that is thinner than the largest diameter (LIGGGHTS
/// inserts into a volume).
[[nodiscard]] std::vector<std::string> liggghtsSourceCommands(const core::World& world);

/// Steps between two hand-overs of a LIGGGHTS run: the greatest common divisor of
/// `outputEvery` (0: none) and every sink's and sensor's sample period, so each of them
/// falls on a hand-over. Sinks remove, and flow sensors compare positions, once per stride.
[[nodiscard]] std::uint64_t liggghtsStride(const core::World& world, std::uint64_t outputEvery);

/// Prepares the world's components for hand-overs every `stride` steps: each flow sensor's
/// band is widened to a stride's displacement (and its initial scan redone).
void prepareLiggghtsComponents(core::World& world, std::uint64_t stride);

/// Runs the world's components on the particles just handed over (the world's clock at the
/// hand-over step): the observe stage of every sink and sensor, then every sink's removal
/// (as our engine removes at the start of the next step). Returns the stable ids the sinks
/// removed, in increasing order.
std::vector<std::uint64_t> runLiggghtsComponents(core::World& world);

}  // namespace demlink::server
