#pragma once
/// The stages of one time step, in order. This table is the one list of them:
/// World::initialize() selects from it the stages a scene needs (selectStages),
/// World::step() calls exactly those in table order with one StepContext,
/// World::activeStages() reports their names (the compile report), and the
/// "One time step" table of docs/architecture.md is stageTableMarkdown() (a test
/// compares the two).
///
/// A row marked `pass` is not a call of its own: it is part of the stage above it
/// (the force stage is one call chosen at initialisation, with the law and the
/// rolling term compiled in), listed so that the report says which passes that
/// call makes. Everything else is one call per step when selected, none otherwise.
///
/// A row marked `kick_may_be_owed` neither reads nor changes velocities or forces
/// between a step's second half kick and the next step's first kick (or, as
/// `forces`, runs after that first kick): a scene whose selected rows all carry
/// the mark may leave a step's second half kick owed to the next step
/// (Stepper, World::advance).
#include <array>
#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "demlink/core/parallel/thread_pool.hpp"

namespace demlink::core {

enum class Stage : std::uint8_t {
  kMeshMotion,
  kInsertRemove,
  kBoundsRemoval,
  kGrowingBounds,
  kVelocityVerlet,
  kExplicitEuler,
  kMovingFrame,
  kClumpRigidBodies,
  kDeformableMotion,
  kNeighbourList,
  kForces,
  kParticleContacts,
  kPlaneContacts,
  kMeshContacts,
  kDeformableContacts,
  kRollingResistance,
  kCohesion,
  kContactRecording,
  kParallelBonds,
  kDeformableForces,
  kClumpForceSum,
  kSecondHalfKick,
  kClumpHalfKick,
  kAdvanceClock,
  kObserve,
  kWatchdog,
};
inline constexpr std::size_t kStageCount = static_cast<std::size_t>(Stage::kWatchdog) + 1;

/// What a step's stages share.
struct StepContext {
  double dt = 0.0;             ///< time step [s]
  std::uint64_t step = 0;      ///< index of the step being taken; it starts at step * dt
  ThreadPool* pool = nullptr;  ///< null: serial
  /// Set by deformable_motion: a deformable surface moved more than skin/2 since the
  /// last neighbour build (neighbour_list then rebuilds). Rigid meshes are checked in
  /// neighbour_list itself (mesh_rebuild_check.hpp).
  bool mesh_moved_far = false;
  /// The step may leave its second half kick owed to the next step's first kick
  /// (World::advance: another step follows, nothing between them reads velocities, and
  /// the watchdog does not inspect this step's end).
  bool may_owe_kick = false;
  /// The step's force evaluation also runs the second half kick and the next step's
  /// first kick and drift, chunk by chunk in the pair loop (Stepper::beginStep).
  bool next_kick_in_forces = false;
  /// The first kick left force and torque zero, so the force stage need not clear them.
  bool forces_cleared = false;
  /// The step count the forces being evaluated belong to: the step's end (at
  /// initialisation, the count now).
  std::uint64_t force_step = 0;
  /// The force evaluation's weight in time integrals [s]: dt in a step, 0 at
  /// initialisation.
  double force_weight = 0.0;
};

/// The features of a scene that decide which stages run.
struct SceneFeatures {
  bool meshes = false;
  bool planes = false;
  bool insert_remove_components = false;
  bool observe_components = false;
  bool fixed_bounds = false;
  bool growing_bounds = false;
  bool velocity_verlet = true;  ///< false: explicit Euler
  bool frame_moving = false;    ///< the frame is not inertial
  bool clumps = false;          ///< clump templates are declared
  bool rolling = false;         ///< some material pair has rolling friction
  bool deformables = false;     ///< the scene has deformable bodies (mass-spring, FEM)
  bool watchdog = false;        ///< the watchdog runs (its every_steps > 0)
  bool cohesion = false;        ///< some material pair has cohesion (k_c > 0)
  bool contact_recording = false;  ///< contact output is requested (contacts or mesh loads)
  bool parallel_bonds = false;     ///< the scene declares parallel bonds
};

struct StageInfo {
  Stage stage;
  /// Report name; "particle_contacts:<law>" gets the law's name in the report,
  /// and the component stages report each component as "<kind>:<name>".
  std::string_view name;
  bool pass;  ///< part of the stage call above it, not a call of its own
  bool kick_may_be_owed;  ///< allows a second half kick owed across steps (see above)
  std::string_view does;
  std::string_view reads;
  std::string_view writes;
  std::string_view runs_when;
  bool (*runs)(const SceneFeatures&);  ///< the code of runs_when
};

/// Every stage, in step order.
[[nodiscard]] const std::array<StageInfo, kStageCount>& stageTable();
[[nodiscard]] const StageInfo& stageInfo(Stage stage);
/// The stages (passes included) a scene with `features` runs, in step order.
[[nodiscard]] std::vector<Stage> selectStages(const SceneFeatures& features);
/// Whether a scene running `stages` may owe a step's second half kick to the next
/// step: every one of them is marked kick_may_be_owed.
[[nodiscard]] bool kickMayBeOwed(const std::vector<Stage>& stages);
/// The whole table as Markdown: | stage | does | reads | writes | runs when | kick
/// may be owed | (passes as "↳ `name`"), one row per line.
[[nodiscard]] std::string stageTableMarkdown();

}  // namespace demlink::core
