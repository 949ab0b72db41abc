#pragma once
/// One running co-simulation: the compiled world, its sample grid, the motion couplings of
/// the rigid bodies, the driven poses of the deformable bodies, the outputs and the output
/// directory (docs/cosim.md).
///
/// Why separate from the host: the host deals with connections, states and faults; this
/// class only knows components and steps, so the equivalence test and the replay can see
/// exactly what the world did. Output files are those of a headless run (FrameSeries,
/// RunLog, sensor CSVs, checkpoints, particles_final.csv) plus compile_report.txt.
#include <cstdint>
#include <filesystem>
#include <functional>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "demlink/core/walls/coupled_motion.hpp"
#include "demlink/server/backend/simulation_backend.hpp"
#include "demlink/server/cosim/cosim_compiler.hpp"
#include "demlink/server/cosim/cosim_outputs.hpp"
#include "demlink/server/cosim/stepping_turns.hpp"
#include "demlink/server/cosim/exchange_scheduler.hpp"
#include "demlink/server/run/run_driver.hpp"

namespace demlink::server {

class CosimSimulation {
 public:
  /// Creates the output directory and its files (RunDriver, plus compile_report.txt),
  /// writes the first frame. Throws core::InputError / std::runtime_error if the directory
  /// cannot be written or is not empty and the scene's run options do not say overwrite.
  /// The engine is options.backend (options.liggghts builds LIGGGHTS, its log
  /// liggghts.log in the output directory); options.before_engine runs before every
  /// engine call; options.mirror: no output files (another MPI rank's copy). With
  /// options.restore_file the world continues from that checkpoint (LIGGGHTS: with its
  /// restart files) at its step, which must be before the end step and a step where every
  /// exchanged component is due (core::InputError naming "restore" otherwise).
  CosimSimulation(CompiledSimulation compiled, const std::filesystem::path& outputDirectory,
                  const CosimOptions& options = {});
  ~CosimSimulation();
  CosimSimulation(const CosimSimulation&) = delete;
  CosimSimulation& operator=(const CosimSimulation&) = delete;

  [[nodiscard]] const CompiledSimulation& compiled() const { return compiled_; }
  [[nodiscard]] const std::vector<CosimComponent>& components() const { return compiled_.components; }
  [[nodiscard]] core::World& world() { return compiled_.scene->world; }
  [[nodiscard]] const ExchangeScheduler& scheduler() const { return scheduler_; }
  [[nodiscard]] const std::filesystem::path& outputDirectory() const { return directory_; }
  /// The rigid body's coupling, or null for another component index.
  [[nodiscard]] const core::CoupledMotion* coupling(std::size_t index) const;

  /// Outputs at step 0 of every exchanged component of `owner`.
  [[nodiscard]] std::vector<v1::DataPackage> initialOutputs(ConnectionId owner);

  /// Checks a package from `from` (component owned by it, due at the current step, valid
  /// input) and stores its input. Returns the fatal Error otherwise (UNKNOWN_COMPONENT,
  /// OUT_OF_ORDER, INVALID_INPUT).
  std::optional<v1::Error> accept(ConnectionId from, const v1::DataPackage& package);
  /// The components of `owner` take no further part; its rigid bodies stop where they are.
  void retire(ConnectionId owner);

  /// What advance() did.
  struct Advance {
    std::vector<std::pair<ConnectionId, v1::DataPackage>> answers;  ///< to each owner
    bool stepped = false;      ///< the world moved
    bool end_reached = false;  ///< the end step is reached
    /// Cut short between two steps (CosimOptions::stop_stepping): no answers, the
    /// scheduler stays at its step; the simulation can only finish.
    bool interrupted = false;
  };
  /// Once every due component has reported: applies the inputs, advances the world to the
  /// next stop and builds the answers of the components whose interval ends there. Does
  /// not step when nothing is exchanged any more and there is no end step. With
  /// CosimOptions::turns it steps only while it holds a turn, and it stops between two
  /// steps once CosimOptions::stop_stepping is set (Advance::interrupted).
  Advance advance();

  /// Final frame, checkpoint_final.bin, particles_final.csv and the run log's timing with
  /// finish_reason (RunDriver::finish); only the first call writes. Throws
  /// std::runtime_error if output cannot be written. On LIGGGHTS the checkpoint is the
  /// backend's (with its restart files; a collective, so every rank calls this).
  void finish(const std::string& reason);

 private:
  void stepWorld();
  /// Restores the world from `checkpoint` and starts the grid at its step.
  void restoreFrom(const std::filesystem::path& checkpoint);
  /// An input the engine cannot apply (LIGGGHTS: a moving frame, a change of gravity).
  std::optional<v1::Error> refusedByEngine(const CosimComponent& c, const v1::DataPackage& package);
  /// options.before_engine, if set.
  void beforeEngine() const;

  CompiledSimulation compiled_;
  std::filesystem::path directory_;
  ExchangeScheduler scheduler_;
  CosimOutputs outputs_;
  std::map<std::size_t, core::CoupledMotion> couplings_;
  /// Driven pose of a client's deformable body: the last sample, its twist and the step it
  /// was sent at; the nodes follow the sample advanced by the twist.
  struct DeformableDrive {
    core::RigidPose sample;
    core::RigidTwist twist;
    std::uint64_t step = 0;
  };
  std::map<std::size_t, DeformableDrive> drives_;
  std::map<std::size_t, v1::DataPackage> inputs_;  ///< stored inputs of the current step
  std::unique_ptr<RunDriver> driver_;  ///< null on a mirror
  std::function<void()> before_engine_;
  std::shared_ptr<const std::atomic<bool>> stop_stepping_;  ///< CosimOptions::stop_stepping
  std::shared_ptr<SteppingTurns> turns_;                    ///< CosimOptions::turns
  std::function<bool(bool)> stop_consensus_;                ///< CosimOptions::stop_consensus
  std::function<void(const core::World&)> step_observer_;   ///< options.step_observer
  std::function<void(const core::World&)> close_observer_;  ///< options.close_observer
  std::unique_ptr<SimulationBackend> backend_;  ///< steps the compiled world (native or LIGGGHTS)
  /// The backend writes the checkpoints, at the stops (LIGGGHTS: the compiled world holds
  /// its particles only there, and a checkpoint needs LIGGGHTS's restart files too); the
  /// driver writes none.
  bool backend_checkpoints_ = false;
  bool finished_ = false;
};

}  // namespace demlink::server
