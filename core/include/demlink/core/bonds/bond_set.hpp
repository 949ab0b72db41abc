#pragma once
/// A world's parallel bonds (parallel_bond.hpp): the rules that make them and the bonds
/// themselves, keyed by the stable ids of their particles.
///
/// A rule bonds, once, at its creation step, every pair of spheres whose surfaces are at
/// most gap_tolerance apart, both centres inside its region (none: anywhere) and both
/// materials in its list (empty: any); a fraction below 1 keeps each candidate pair with
/// that probability (a seeded stream over the pairs in id order, so the choice does not
/// depend on slot order or threads). Members of one clump are never bonded, and a pair
/// is bonded at most once.
///
/// Why ids and slots: the force loop needs slots, which change when particles are
/// removed or re-sorted; the bond keeps both and the world calls remapSlots() with each
/// slot mapping (as it does for clump members), so the bonds follow their particles. A
/// bond whose particle is removed is dropped. The bond list is in creation order (pairs
/// in id order), the order forces are added in, so results do not depend on slots.
#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <unordered_map>
#include <utility>
#include <vector>

#include "demlink/core/bonds/parallel_bond.hpp"
#include "demlink/core/regions/region_shape.hpp"
#include "demlink/core/particles/particle_arrays.hpp"

namespace demlink::core {

class MeshBody;
class ThreadPool;
class StateWriter;
class StateReader;
struct Material;
struct TimeStepReport;

/// How and when one group of bonds is made.
struct BondRule {
  std::string name;                       ///< the declaring component's name
  ParallelBondProperties properties;
  std::optional<VolumeShape> region;      ///< none: the whole world
  RegionPlacement placement;              ///< where `region` is
  std::vector<std::uint32_t> materials;   ///< both particles' materials among these; empty: any
  std::uint64_t create_step = 0;          ///< bonds are made at the end of the first step after this count
  double fraction = 1.0;                  ///< probability a candidate pair is bonded [-], (0, 1]
  std::uint64_t seed = 0;                 ///< of the fraction's stream
  /// Clods (bonds/clods.hpp): group of each particle id; when set, only particles listed
  /// here are bonded, and only to particles of their own group.
  std::optional<std::unordered_map<std::uint64_t, std::uint32_t>> groups;
};

/// Bonds counted by state; every bond made is in exactly one of the three.
struct BondCounts {
  std::uint64_t intact = 0;
  std::uint64_t broken = 0;   ///< broken since they were made (also when a particle was removed since)
  std::uint64_t dropped = 0;  ///< lost intact with a removed particle

  /// Bonds made so far [-].
  [[nodiscard]] std::uint64_t created() const { return intact + broken + dropped; }
};

class BondSet {
 public:
  /// Adds a rule (validated by the caller, World::addBondRule); returns its index.
  std::size_t addRule(BondRule rule);
  [[nodiscard]] bool hasRules() const { return !rules_.empty(); }
  [[nodiscard]] const std::vector<BondRule>& rules() const { return rules_; }
  /// Every bond made so far, broken ones included (they load nothing).
  [[nodiscard]] const std::vector<ParallelBond>& bonds() const { return bonds_; }
  [[nodiscard]] const BondCounts& counts() const { return counts_; }
  /// Whether rule `rule` has made its bonds.
  [[nodiscard]] bool made(std::size_t rule) const { return made_.at(rule) != 0; }

  /// The bond stage: advances every intact bond by dt with the particles' state at the
  /// step's end and adds its load to their force and torque; then makes the bonds of
  /// every rule whose creation step `stepCount` has reached. The bonds advance in chunks
  /// over `pool` (null: serial), each writing only its own bonds and loads; the loads are
  /// then added in bond order on the calling thread, so any thread count gives the same bits.
  void step(ThreadPool* pool, const std::vector<MeshBody>& meshes, double time, ParticleArrays& particles, double dt,
            std::uint64_t stepCount);
  /// Follows a slot mapping (new slot of old slot, kRemovedSlot for removed particles).
  void remapSlots(std::span<const std::uint32_t> newSlotOfOld);
  /// Elastic energy stored in the intact bonds [J].
  [[nodiscard]] double strainEnergy(const ParticleArrays& particles) const;
  /// The bond's cross-section with its particles' radii now.
  [[nodiscard]] BondSection section(const ParallelBond& bond, const ParticleArrays& particles) const;

  /// Adds each rule's limits to the time step (named "parallel_bonds <name> axial" and
  /// "... rotational") for spheres of radius minRadiusOfMaterial (<= 0: the material has
  /// no spheres). A sphere may carry up to kBondCoordinationBound bonds:
  /// omega^2 <= 2 Z k / m (Gershgorin), dt < 2 / omega with k = max(kn, ks) A against the
  /// sphere's mass and, for rotation, k = ks A R^2 + max(kn I, ks J) against its moment
  /// of inertia 2/5 m R^2.
  void addTimeStepLimits(TimeStepReport& report, const std::vector<Material>& materials,
                         const std::vector<double>& minRadiusOfMaterial) const;

  /// Checkpoint payload (section BOND): per rule whether it has made its bonds, the
  /// counts, and every bond by ids with its force, moments and state.
  void save(StateWriter& out) const;
  /// Reads what save() wrote into a staging set, finding the slots of the ids in
  /// `particles`; throws InputError via in.fail() for a bad file. Call on a copy and
  /// swap on success (World::restoreCheckpoint).
  void restore(StateReader& in, const ParticleArrays& particles);

 private:
  void make(const std::vector<MeshBody>& meshes, double time, const ParticleArrays& particles, std::size_t rule);

  std::vector<BondRule> rules_;
  std::vector<char> made_;  ///< per rule
  std::vector<ParallelBond> bonds_;
  BondCounts counts_;
  /// Scratch of step(): per bond, its load this step and what became of it (skipped, loaded, broke).
  std::vector<BondLoad> loads_;
  std::vector<std::uint8_t> outcomes_;
};

/// Candidate pairs (slots) among the `eligible` particles whose surfaces are at most
/// `gap` apart, each once with the smaller id first, sorted by ids; members of one clump
/// are never paired.
[[nodiscard]] std::vector<std::pair<std::uint32_t, std::uint32_t>> pairsWithinGap(const ParticleArrays& particles,
                                                                                  const std::vector<char>& eligible,
                                                                                  double gap);

/// Most bonds one sphere is assumed to carry in the time-step limit [-]: the kissing
/// number of equal spheres.
inline constexpr double kBondCoordinationBound = 12.0;

}  // namespace demlink::core
