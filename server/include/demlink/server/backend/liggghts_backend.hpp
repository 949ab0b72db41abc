#pragma once
/// The LIGGGHTS-PUBLIC backend: runs a compiled world on libliggghts across the MPI ranks
/// of the process's MPI_COMM_WORLD (built with DEMLINK_WITH_LIGGGHTS; docs/scale-out.md).
///
/// Every rank compiles the same scene and runs the same calls in lockstep: each rank
/// builds a LiggghtsBackend from its own world, and rank 0 alone writes the read_data file
/// (LIGGGHTS reads it on rank 0 and distributes the atoms) and the outputs. The native
/// engine never needs MPI; MPI is initialised here on first use (a process started
/// without mpirun runs as a singleton of one rank) and finalised at exit.
#include <cstdint>
#include <filesystem>
#include <memory>
#include <unordered_map>
#include <utility>
#include <vector>

#include "demlink/core/components/particle_source.hpp"
#include "demlink/server/backend/simulation_backend.hpp"
#include "demlink/server/run/headless_runner.hpp"
#include "demlink/v1/scene.pb.h"

namespace demlink::server {

/// Initialises MPI once per process (no-op if it already is); returns this process's rank.
/// It asks for MPI_THREAD_MULTIPLE, so that rank 0's simulation may step on a thread of its
/// own while the network thread serves (demlink-server; docs/server.md, "Threads").
int ensureMpi();
/// Whether the MPI library lets any thread make MPI calls (after ensureMpi()): it granted
/// at least MPI_THREAD_SERIALIZED. Callers keep the calls from overlapping themselves.
[[nodiscard]] bool mpiCallsFromAnyThread();
/// Ranks in MPI_COMM_WORLD (after ensureMpi()).
[[nodiscard]] int mpiRanks();

class LiggghtsBackend final : public SimulationBackend {
 public:
  /// Sets LIGGGHTS up from `world` (initialised here if not yet: our time-step check runs
  /// before LIGGGHTS sees the scene). `world` must outlive the backend. Throws
  /// core::InputError for what liggghtsCommands refuses, std::runtime_error if
  /// LIGGGHTS fails.
  /// LIGGGHTS writes its log to `logFile` (empty: no log).
  /// `restore`: a checkpoint writeCheckpoint() wrote (its `.bin`), already restored into
  /// `world` (core::restoreCheckpointFile); LIGGGHTS then reads the atoms from its
  /// `.liggghts` restart file and the backend its tag-to-id map and tallies from its
  /// `.liggghts_ids` file (core::InputError naming a missing or inconsistent file).
  LiggghtsBackend(core::World& world, const std::string& logFile = {}, const std::filesystem::path& restore = {});
  ~LiggghtsBackend() override;
  LiggghtsBackend(const LiggghtsBackend&) = delete;
  LiggghtsBackend& operator=(const LiggghtsBackend&) = delete;

  [[nodiscard]] std::string_view name() const override { return "liggghts"; }
  /// Runs LIGGGHTS to `step`, first replacing the insertion fix of every particle source
  /// whose rate or on/off a client changed (liggghtsInsertCommand: the new fix inserts at
  /// the new rate from this step on; an off source has none), moving each mesh at the twist its compiled-world mesh has
  /// (fix move/mesh, liggghts_motion.hpp: a mesh's first twist creates its move fixes and
  /// makes this run set up again; later twists only set the variables the fixes read),
  /// then advances the compiled world's clock and mesh poses by
  /// the same steps and sets each mesh's wrench in it (meshWrench). A collective.
  void advanceTo(std::uint64_t step) override;
  [[nodiscard]] std::uint64_t stepCount() const override { return step_; }
  /// Gathers positions, velocities and angular velocities to every rank, adds the atoms
  /// LIGGGHTS's sources inserted to the compiled world (new stable ids, in tag order:
  /// insertedParticles), removes from it the particles LIGGGHTS lost at the box
  /// (counted in the world's removedAtBounds(), as our engine counts them), and runs the
  /// sinks and sensors on it at advanceTo()'s clock (runLiggghtsComponents), deleting the
  /// atoms the sinks removed in LIGGGHTS (a collective: every rank must call it).
  void syncParticles() override;
  /// Particles LIGGGHTS's sources inserted that a syncParticles() handed over (an atom
  /// inserted and lost within one stride is in neither tally).
  [[nodiscard]] const core::RemovalTally& insertedParticles() const { return inserted_; }
  /// Particles and mass [kg] the world's `source`-th particle source has inserted (its
  /// report, which syncParticles() feeds from LIGGGHTS's insertion fixes).
  [[nodiscard]] std::pair<std::uint64_t, double> sourceInserted(std::size_t source) const;
  /// The world's particle sources [-].
  [[nodiscard]] std::size_t sourceCount() const { return sources_.size(); }
  [[nodiscard]] const core::World& world() const override { return world_; }
  /// Force on mesh `mesh` by the particles [N] and its torque about the mesh's reference
  /// point [N m], of the last step (fix mesh/surface/stress). advanceTo() also sets them
  /// as the compiled world's mesh wrench.
  [[nodiscard]] std::pair<core::Vec3, core::Vec3> meshWrench(std::size_t mesh) const;
  /// Particles LIGGGHTS holds now [-].
  [[nodiscard]] std::size_t particleCount() const;
  /// Their mass [kg] (a collective).
  [[nodiscard]] double particleMass() const;
  /// Runs one LIGGGHTS command on every rank (all must call it).
  void command(const std::string& line);
  /// Writes a checkpoint after a syncParticles() (a collective): `<base>.bin`, our
  /// checkpoint of the compiled world (its particles as LIGGGHTS holds them, the sinks'
  /// and sensors' state, the clock, the meshes; core/checkpoint_file.hpp), by rank 0;
  /// `<base>.liggghts`, LIGGGHTS's write_restart (atoms, contact histories, fix states);
  /// `<base>.liggghts_ids`, the tag-to-id map and the inserted tally, by rank 0.
  void writeCheckpoint(const std::filesystem::path& base) override;

 private:
  core::World& world_;
  void* lammps_ = nullptr;
  std::uint64_t step_ = 0;
  bool started_ = false;
  /// Per mesh: the twist LIGGGHTS moves it at now, and whether its move fixes exist.
  struct MeshMotion {
    core::Vec3 linear = core::Vec3::Zero();
    core::Vec3 angular = core::Vec3::Zero();
    bool fixed = false;
  };
  std::vector<MeshMotion> motions_;
  /// Gives LIGGGHTS the twist of every mesh whose twist changed; true if a mesh's move
  /// fixes had to be created (the next run must set up).
  bool updateMeshMotion();
  /// Per particle source: its insertion fix now and what of its counters the source's
  /// report holds already.
  struct SourceFix {
    core::ParticleSource* source = nullptr;
    double rate = 0.0;             ///< liggghtsSourceRate when the fix was made [1/s or kg/s]
    bool active = false;           ///< a fix exists (it inserts something)
    std::uint32_t generation = 0;  ///< liggghtsInsertFix(index, generation)
    std::uint64_t counted = 0;     ///< the fix's particles already in the report [-]
    double counted_mass = 0.0;     ///< [kg]
  };
  std::vector<SourceFix> sources_;
  /// Adds what the insertion fixes inserted since the last call to their sources' reports.
  void countInserted();
  /// Replaces the insertion fix of every source whose rate changed; true if one did.
  bool updateSources();
  /// Reads the `.liggghts_ids` file of checkpoint `restore` into the members below.
  void restoreTagMap(const std::filesystem::path& restore);
  std::vector<std::uint64_t> tag_ids_;                         ///< atom tag - 1 -> our stable id
  std::unordered_map<std::uint64_t, std::size_t> tag_of_id_;  ///< our stable id -> atom tag
  core::RemovalTally inserted_;
};

/// runHeadless on LIGGGHTS: refuses what it cannot run (requireLiggghtsCompatible), restores
/// run.restore_file (a LiggghtsBackend checkpoint's `.bin`) if given, and steps to the end
/// time in strides that land on every output.vtk_interval (a progress line each) and
/// output.checkpoint_interval. Rank 0 writes the outputs with the RunDriver of a native run
/// (its checkpoints through LiggghtsBackend::writeCheckpoint, in which every rank takes
/// part). Every rank must call it.
RunSummary runHeadlessLiggghts(const v1::Scene& declarations, TranslatedScene& scene);

}  // namespace demlink::server
