#pragma once
/// The particle world and its time step. The stages of a step, what each reads
/// and writes and when a scene runs it are the table in step/stage_table.hpp
/// (printed by stageTableMarkdown(), drawn in docs/architecture.md); the world
/// selects the stages its scene needs once, at initialize(), and step() calls
/// only those. What the user chose (SimulationSettings) stays fixed; what evolves
/// is in WorldState (world_state.hpp).
#include <array>
#include <cstdint>
#include <functional>
#include <iosfwd>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "demlink/core/bonds/bond_set.hpp"
#include "demlink/core/components/component_list.hpp"
#include "demlink/core/components/component_world.hpp"
#include "demlink/core/contact/contact_recorder.hpp"
#include "demlink/core/contact/contact_setup.hpp"
#include "demlink/core/contact/critical_time_step.hpp"
#include "demlink/core/deformable/deformable_set.hpp"
#include "demlink/core/materials/material.hpp"
#include "demlink/core/particles/clump_set.hpp"
#include "demlink/core/particles/neighbour_search.hpp"
#include "demlink/core/particles/particle_arrays.hpp"
#include "demlink/core/simulation_settings.hpp"
#include "demlink/core/step/pair_loop_partition.hpp"
#include "demlink/core/step/stage_table.hpp"
#include "demlink/core/step/stepper.hpp"
#include "demlink/core/parallel/thread_pool.hpp"
#include "demlink/core/step/watchdog.hpp"
#include "demlink/core/walls/walls.hpp"
#include "demlink/core/world_state.hpp"

namespace demlink::core {

/// Most materials one world holds [-]: bounds the pair table (the square of the materials
/// in use, 88 bytes a pair: 5.8 MB when all are used) and its set-up time.
inline constexpr std::size_t kMaxMaterials = 256;

/// The facade over the world's subsystems; components see it as a ComponentWorld.
class World final : public ComponentWorld {
 public:
  /// `settingsField` is the name errors give the settings ("settings.time_step"); a
  /// translator passes the settings' path in its scene ("components[0].simulation_box").
  explicit World(SimulationSettings settings, std::string settingsField = "settings");

  /// Adds a validated material; returns its index. Names must be unique.
  std::uint32_t addMaterial(const Material& material);
  [[nodiscard]] std::optional<std::uint32_t> findMaterial(const std::string& name) const;
  /// Gives the pair (materialA, materialB) (indices, either order; equal indices:
  /// a like-material pair) explicit contact coefficients instead of the mean mix.
  /// Call before initialize(); each pair at most once. fieldPrefix names it in errors.
  void setPairOverride(std::uint32_t materialA, std::uint32_t materialB, const PairOverride& values,
                       const std::string& fieldPrefix = "pair_override");
  /// Adds a validated sphere; returns its stable id. fieldPrefix names it in errors.
  std::uint64_t addParticle(const ParticleSpec& spec, const std::string& fieldPrefix = "particle") override;
  /// Adds a validated plane (normal is normalised); returns its index.
  std::size_t addPlane(PlaneSpec plane, const std::string& fieldPrefix = "plane");

  /// Registers a clump template (its name must be unique); returns its index for
  /// addClump. Templates are shared by all clumps made from them.
  std::uint32_t addClumpTemplate(ClumpTemplate shape, const std::string& fieldPrefix = "clump_template");
  /// Adds a rigid clump: one sphere per template member, placed at
  /// spec.position + R(spec.orientation) (offset - template COM), all of
  /// spec.material, moving with the body. Returns the clump id (>= 1; members
  /// carry it in ParticleArrays::clump_id). Works before and after initialize();
  /// a source that adds clumps later must declareFutureParticles(material,
  /// template.minRadius(), ...) before initialize(). See docs/clumps.md.
  std::uint64_t addClump(const ClumpSpec& spec, const std::string& fieldPrefix = "clump") override;
  [[nodiscard]] const std::vector<ClumpTemplate>& clumpTemplates() const override { return clumps_.templates; }
  [[nodiscard]] std::optional<std::uint32_t> findClumpTemplate(const std::string& name) const;
  /// Live clumps (order changes when clumps are removed).
  [[nodiscard]] const std::vector<ClumpBody>& clumps() const override { return clumps_.bodies; }

  /// Adds a mesh body under prescribed motion (its material index must exist);
  /// returns its index. Set its pose and velocity through mesh(index).
  std::size_t addMesh(MeshBody mesh, const std::string& fieldPrefix = "mesh");

  /// Adds a deformable body (mass-spring, FEM; deformable/) before initialize(): its
  /// surface material must exist and its name be unique among deformable bodies
  /// (errors name "<fieldPrefix>.material" / "<fieldPrefix>.name"); the frame must be
  /// inertial. Returns its index. Its criticalTimeStep() joins the time-step check.
  std::size_t addDeformableBody(std::unique_ptr<DeformableBody> body, const std::string& fieldPrefix = "deformable");
  [[nodiscard]] const std::vector<std::unique_ptr<DeformableBody>>& deformableBodies() const override {
    return deformables_.bodies;
  }
  /// The body at `index` (std::out_of_range otherwise), e.g. to set a driven pose.
  [[nodiscard]] DeformableBody& deformableBody(std::size_t index) override { return *deformables_.bodies.at(index); }

  /// Adds a rule that makes parallel bonds (bonds/bond_set.hpp) before initialize():
  /// validates its properties, fraction and materials (errors name "<fieldPrefix>.<field>")
  /// and its bonds join the time-step check; the step then runs stage parallel_bonds.
  /// Returns the rule's index.
  std::size_t addBondRule(BondRule rule, const std::string& fieldPrefix = "parallel_bonds");
  /// The bond rules and every bond made so far.
  [[nodiscard]] const BondSet& bonds() const override { return bonds_; }

  /// Changes the motion of the frame (the "room" of the docs) from the next step
  /// on (validated; names "frame.<field>"): a change of the world's state, the
  /// settings keep the initial motion. An inertial motion returns the step to the
  /// plain integrator (the stage list is selected again).
  void setFrameMotion(const FrameMotion& motion);
  /// The frame's motion now (angular velocity as of the last step).
  [[nodiscard]] const FrameMotion& frameMotion() const { return state_.frame; }
  /// Changes gravity [m/s^2] (frame coordinates) from the next step on; the
  /// settings keep the initial gravity.
  void setGravity(const Vec3& gravity);
  /// Gravity in force [m/s^2], frame coordinates.
  [[nodiscard]] const Vec3& gravity() const { return state_.gravity; }
  /// The domain bounds now (growing bounds: the current box, as of the last
  /// bounds pass at the start of a step); nullopt without bounds.
  [[nodiscard]] std::optional<DomainBounds> currentBounds() const;

  /// Declares that particles of `material` down to `minRadius` [m] will appear
  /// after initialize() (inserted by a source): the critical time step, the
  /// default skin and the linear law's matched stiffness take them into account.
  void declareFutureParticles(std::uint32_t material, double minRadius, const std::string& fieldPrefix) override;

  /// Adds a scene component (source, sink, sensor, tracker); the world owns it and
  /// runs it in the stages it declares. Returns a reference that stays valid.
  WorldComponent& addComponent(std::unique_ptr<WorldComponent> component) override;
  [[nodiscard]] const std::vector<std::unique_ptr<WorldComponent>>& components() const { return components_.all; }

  /// Removes every particle for which `remove(slot)` is true (evaluated once per
  /// slot, in slot order, before anything moves) and adds them to `tally`.
  /// Contact histories of the remaining particles are kept. A clump never goes
  /// in part: when any member is flagged, the whole clump is removed.
  template <class RemovePredicate>
  void removeParticlesIf(RemovePredicate remove, RemovalTally& tally);
  /// removeParticlesIf for a component (one call through the interface per removal pass).
  void removeParticles(const std::function<bool(std::size_t)>& remove, RemovalTally& tally) override {
    removeParticlesIf(remove, tally);
  }
  /// removeParticlesIf into removedAtBounds(): for another engine (LIGGGHTS) whose box
  /// lost particles, so every output reads the one tally our engine's bounds fill.
  template <class RemovePredicate>
  void removeParticlesAtBoundsIf(RemovePredicate remove) {
    removeParticlesIf(remove, state_.removed_at_bounds);
  }

  /// Mixes material pairs, checks the time step against the critical limit
  /// (throws InputError unless allow_unsafe_time_step), chooses the skin, selects
  /// the force kernel and the stages, and evaluates the initial forces. Call once
  /// before step().
  void initialize();
  /// Advances one time step: the selected stages, in table order.
  void step();
  /// Advances `steps` time steps; afterwards the state is exactly what `steps` calls of
  /// step() leave. In between, when no stage between a step's second half kick and the
  /// next step's first kick reads velocities or forces (a scene of particles, planes and
  /// the watchdog: kickDeferrable()), a step leaves its second half kick owed and the
  /// next step makes both half kicks and the drift in one pass over the particles, the
  /// same additions in the same order (integrator.hpp kickTwiceAndDrift): one stream
  /// over the particle columns per step instead of two. A step whose end the watchdog
  /// inspects, and the last step, make their second half kick as usual.
  void advance(std::uint64_t steps);
  /// Whether advance() may owe half kicks in this scene (set with the stages).
  [[nodiscard]] bool kickDeferrable() const { return stepper_.kickDeferrable(); }
  /// Half kicks advance() has owed and paid with the next step's kick so far.
  [[nodiscard]] std::uint64_t fusedKicks() const { return stepper_.fusedKicks(); }

  /// Writes everything the next step depends on (settings, materials, particle
  /// columns, neighbour and near lists with histories, planes, meshes, counters,
  /// component states, deformable bodies) to `out` (format: checkpoint_file.hpp,
  /// docs/state.md). Defined in checkpoint.cpp. Throws std::runtime_error if `out` fails.
  void saveCheckpoint(std::ostream& out) const;
  /// Restores a checkpoint written by a world built from the same scene (same
  /// settings, materials, planes, meshes and components), initialising this
  /// world first if needed. Throws InputError naming `source` and the section
  /// for a bad file or a scene mismatch; the world's own state is only replaced
  /// once the whole file has been read and checked.
  void restoreCheckpoint(std::istream& in, const std::string& source = "checkpoint");
  void restoreCheckpoint(std::string_view bytes, const std::string& source);

  /// What the user chose; unchanged by initialize(), step() and the setters.
  [[nodiscard]] const SimulationSettings& settings() const override { return settings_; }
  /// What evolves: clock, frame motion, gravity, skin, bounds, counters.
  [[nodiscard]] const WorldState& state() const { return state_; }
  [[nodiscard]] std::uint64_t stepCount() const override { return state_.step_count; }
  /// Moves the clock to `stepCount` (>= the current count) without stepping: for a world
  /// another engine advances (the LIGGGHTS backend copies its particles in and then runs
  /// the components' stages on this world at that time). Throws std::invalid_argument
  /// for a step count behind the clock.
  void advanceClockTo(std::uint64_t stepCount);
  [[nodiscard]] double time() const override { return static_cast<double>(state_.step_count) * settings_.time_step; }
  /// Verlet-list skin in force [m] (the default is chosen at initialize()).
  [[nodiscard]] double neighbourSkin() const { return state_.neighbour_skin; }
  [[nodiscard]] ParticleArrays& particles() { return particles_; }
  [[nodiscard]] const ParticleArrays& particles() const override { return particles_; }
  [[nodiscard]] const std::vector<Material>& materials() const override { return materials_; }
  [[nodiscard]] const std::vector<PlaneWall>& planes() const override { return walls_.planes; }
  [[nodiscard]] const std::vector<MeshBody>& meshes() const override { return walls_.meshes; }
  [[nodiscard]] MeshBody& mesh(std::size_t index) { return walls_.meshes.at(index); }
  [[nodiscard]] const TimeStepReport& timeStepReport() const { return time_step_.report; }
  /// The index of the rigid twin of `material` (Material::rigid, named "<name> (rigid)"),
  /// added on first use; rigid planes and meshes use it.
  std::uint32_t rigidTwin(std::uint32_t material);
  /// Estimates the wall time of every stage from now on by timing a sample of steps
  /// (step/stage_sampling.hpp: well under 1 % of the step's cost); off by default.
  void setStageTiming(bool on) { stepper_.setTiming(on); }
  /// Estimated wall seconds of each stage since timing was switched on, by Stage.
  [[nodiscard]] const std::array<double, kStageCount>& stageSeconds() const { return stepper_.stageSeconds(); }
  /// Every speed the world could see at initialize() (particles, sources, meshes,
  /// the frame's rotation), fastest first.
  [[nodiscard]] const std::vector<SeenSpeed>& seenSpeeds() const { return time_step_.seen_speeds; }
  /// The impact speed the time step is validated for [m/s]: the largest of
  /// max_impact_velocity and the seen speeds.
  [[nodiscard]] double validatedImpactSpeed() const { return time_step_.report.impact_speed; }
  /// Warnings of initialize() (a declared speed below a seen one) and of the
  /// watchdog so far, in order.
  [[nodiscard]] std::vector<std::string> warnings() const;
  /// Measures what the watchdog checks, now (stage watchdog calls it every
  /// every_steps steps; tests call it directly).
  [[nodiscard]] WatchdogReading watch();
  /// What in the state is NaN or infinite (a particle's position, velocity, spin or force,
  /// a mesh's pose or velocity, a deformable body's node positions), named; empty when all
  /// is finite. The watchdog stops on it, and the run's writers refuse to write such a state.
  [[nodiscard]] std::string nonFiniteState() const;
  [[nodiscard]] const ContactPairTable& pairTable() const { return contacts_.table; }
  [[nodiscard]] const RemovalTally& removedAtBounds() const { return state_.removed_at_bounds; }
  [[nodiscard]] const NeighbourList& neighbourList() const { return neighbours_.list; }
  /// The pair loop's chunks and their force buffers (memory reports).
  [[nodiscard]] const PairLoopPartition& pairLoopPartition() const { return partition_; }
  /// The step's thread pool; null when running on one thread.
  [[nodiscard]] const ThreadPool* threadPool() const { return pool_.get(); }
  /// Names of the stages this scene runs, in step order, for the compile report:
  /// the selected rows of stageTable(), the law in "particle_contacts:<law>", and
  /// each component as "<kind>:<name>" in the stages it runs in.
  [[nodiscard]] std::vector<std::string> activeStages() const;
  /// The build of the pair loop this world runs (pair_kernel.hpp; chosen at initialize()).
  [[nodiscard]] PairKernel pairKernel() const { return contacts_.kernel; }
  /// Translational + rotational kinetic energy [J].
  [[nodiscard]] double kineticEnergy() const;
  /// Total particle mass [kg].
  [[nodiscard]] double totalMass() const;

  /// Contact output: records of every contact at each multiple of every_steps (and at
  /// initialisation), per-triangle loads of each mesh with their time integrals
  /// (contact_record.hpp). Inactive settings (the default) leave the recording pass
  /// out of the force stage. May be called before or after initialize().
  void setContactOutput(const ContactOutputSettings& settings);
  [[nodiscard]] const ContactOutputSettings& contactOutput() const { return recorder_.settings; }
  /// The contacts of the last recorded force evaluation (valid = false before one).
  [[nodiscard]] const ContactSnapshot& contactSnapshot() const { return recorder_.snapshot; }
  /// Loads per triangle of mesh `index`; empty unless mesh loads are on and a force
  /// evaluation ran since.
  [[nodiscard]] std::span<const TriangleLoad> meshLoads(std::size_t index) const;
  [[nodiscard]] bool initialized() const { return initialized_; }

 private:
  /// Features of the scene now, which select the stages (stage_table.hpp).
  [[nodiscard]] SceneFeatures sceneFeatures() const;
  /// Selects the stage calls step() makes; again whenever the scene changes after initialize().
  void selectStepStages();
  void runStage(Stage stage, StepContext& context);

  // Stages (stage_table.hpp), in step order.
  void moveMeshes(StepContext& context);
  void moveDeformables(StepContext& context);
  void finishDeformables(const StepContext& context);
  void runComponents(Stage stage);
  void removeOutsideBounds();
  void firstKickAndDrift(StepContext& context);
  void explicitEulerUpdate(const StepContext& context);
  void advanceFrame(const StepContext& context);
  void integrateClumps(double kickStep, double driftStep, bool driftFirst);
  void updateNeighbours(const StepContext& context);
  template <class Law, ForcePasses kPasses>
  void computeForces(StepContext& context);
  /// Picks compute_forces_ for the law and the passes the scene uses.
  void selectForceKernel();
  void gatherClumpForces();
  void secondHalfKick(const StepContext& context);
  /// One step; `anotherStepFollows` within advance().
  void stepOnce(bool anotherStepFollows);
  /// Whether the watchdog inspects the state when the step count is `stepCount`.
  [[nodiscard]] bool watchdogInspects(std::uint64_t stepCount) const;
  void runWatchdog();

  /// The speeds the scene shows before it runs (time_step_.seen_speeds), fastest first.
  [[nodiscard]] std::vector<SeenSpeed> collectSeenSpeeds() const;
  /// Refuses settings or particles whose first step would overflow, naming the field.
  void requireFiniteFirstStep() const;
  /// Elastic energy stored in particle-pair and plane contacts [J], and the
  /// deepest overlap (fraction of the smaller radius) with its contact's name.
  template <class Law>
  void measureContacts(WatchdogReading& reading) const;

  /// Throws InputError naming the frame's angular velocity (acceleration) when its
  /// centrifugal (Euler) acceleration at the farthest particle exceeds kMaxAcceleration.
  void requireBoundedFrameAccelerations() const;
  /// The materials particles (present and declared future ones), planes, meshes and pair
  /// overrides use, ascending: the pair table's rows.
  [[nodiscard]] std::vector<std::uint32_t> materialsInUse() const;
  /// Mixes the pair table over `used` and picks the force kernel (rolling or not).
  void buildPairTable(const std::vector<std::uint32_t>& used);
  /// After initialize(): gives `material` rows in the pair table if it has none yet (a
  /// particle, plane or mesh of a material no one used before).
  void coverMaterial(std::uint32_t material);
  void requireNoClumpsInRotatingFrame(const FrameMotion& motion, const std::string& fieldPrefix) const;
  void requireNoDeformablesInMovingFrame(const FrameMotion& motion, const std::string& fieldPrefix) const;
  void applySlotMapping(const std::vector<std::uint32_t>& oldSlotOfNew);
  void rebuildNeighbours();
  /// Arms neighbours_.guard for the neighbour list's last build and the planes' near lists.
  void armRebuildGuard();
  /// Whether the neighbour and near lists may have missed a contact since their build.
  [[nodiscard]] bool neighbourListsStale(ThreadPool* pool) const;
  void removeFlaggedWithClumps(RemovalTally& tally);

  SimulationSettings settings_;  ///< what the user chose; never changed after construction
  std::string settings_field_;    ///< how errors name the settings
  WorldState state_;              ///< what evolves: clock, frame, gravity, skin, bounds, counters
  std::vector<Material> materials_;
  ParticleArrays particles_;
  ClumpSet clumps_;
  Walls walls_;                   ///< planes and meshes with their near lists
  DeformableSet deformables_;     ///< deformable bodies with their near lists
  ComponentList components_;
  BondSet bonds_;                 ///< parallel bonds and the rules that make them
  NeighbourSearch neighbours_;    ///< Verlet list, rebuild guard, pending slot map
  PairLoopPartition partition_;   ///< the pair loop's chunks and force buffers
  ContactSetup contacts_;         ///< pair table, overrides, future particles, passes, kernel
  void (World::*compute_forces_)(StepContext&) = nullptr;  ///< the force stage (selectForceKernel)
  ContactRecorder recorder_;      ///< contact output
  TimeStepCheck time_step_;       ///< the critical time step, seen speeds, warnings of initialize()
  Watchdog watchdog_;
  Stepper stepper_;               ///< the stage calls of a step, owed half kicks, stage timing
  std::unique_ptr<ThreadPool> pool_;  ///< null when running on one thread
  bool initialized_ = false;
};

template <class RemovePredicate>
void World::removeParticlesIf(RemovePredicate remove, RemovalTally& tally) {
  if (!clumps_.bodies.empty()) {
    clumps_.removal_flags.assign(particles_.size(), 0);
    bool any = false;
    for (std::size_t i = 0; i < particles_.size(); ++i) {
      if (remove(i)) {
        clumps_.removal_flags[i] = 1;
        any = true;
      }
    }
    if (any) removeFlaggedWithClumps(tally);
    return;
  }
  // Removals are rare: scan until the first removed slot, build a mapping only then.
  std::size_t first = 0;
  while (first < particles_.size() && !remove(first)) ++first;
  if (first == particles_.size()) return;
  std::vector<std::uint32_t> keep(first);
  for (std::uint32_t k = 0; k < first; ++k) keep[k] = k;
  ++tally.count;
  tally.mass += particles_.mass[first];
  for (std::size_t i = first + 1; i < particles_.size(); ++i) {
    if (remove(i)) {
      ++tally.count;
      tally.mass += particles_.mass[i];
    } else {
      keep.push_back(static_cast<std::uint32_t>(i));
    }
  }
  applySlotMapping(keep);
}

}  // namespace demlink::core
