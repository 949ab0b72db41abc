#pragma once
/// The outputs of one run, headless or coupled: the folder, frames and checkpoints on
/// their intervals, sensor CSVs, the run log's configuration and timing rows, the final
/// frame, checkpoint and particle CSV. The headless runner and a co-simulation both step
/// their world and call afterStep() / finish(); neither keeps an output loop of its own.
///
///   planRun()      seconds -> steps for end_time, vtk_interval, checkpoint_interval
///   RunDriver()    claims the folder (output_directory.hpp), opens summary.csv,
///                  run_log.csv (configuration rows) and the sensor CSVs; asks the
///                  world for contact output when the run writes it
///                  (World::setContactOutput: contact_every, mesh_loads)
///   start()        planes.vtp and the first frame; the run's wall clock starts
///   afterStep()    springs that broke (broken_springs.csv, deformable_series.hpp),
///                  a frame every frame_every steps and at end_step, a checkpoint
///                  checkpoint_NNNNNN.bin every checkpoint_every steps (N = step / every),
///                  contacts_NNNNNN.vtp / .csv (series contacts.pvd) every contact_every steps
///   finish()       the last frame if the last step has none, checkpoint_final.bin,
///                  particles_final.csv, the timing rows and status "completed"
///   abort()        status "aborted: <why>" instead (a run that fails keeps a valid log)
///
/// Why steps and not seconds: frames and checkpoints land on the same absolute steps
/// whatever the run's history (restored or not, stepped one exchange at a time or in one
/// go), so a continued run reproduces the uninterrupted one.
#include <chrono>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <string>
#include <vector>

#include "demlink/core/world.hpp"
#include "demlink/server/run/deformable_series.hpp"
#include "demlink/server/run/frame_series.hpp"
#include "demlink/server/run/run_log.hpp"
#include "demlink/server/scene/run_options.hpp"

namespace demlink::server {

/// A run's schedule in whole steps.
struct RunPlan {
  std::uint64_t end_step = 0;          ///< [-]; 0: no end step (a co-simulation runs until every client said Bye)
  std::uint64_t frame_every = 0;       ///< [-]; 0: first and last frame only
  std::uint64_t checkpoint_every = 0;  ///< [-]; 0: no periodic checkpoints
  std::uint64_t contact_every = 0;     ///< [-]; 0: no contact output
  std::vector<std::string> warnings;   ///< times rounded to whole steps (intervalSteps)

  /// A frame is due at `step`: every frame_every steps, and at end_step.
  [[nodiscard]] bool frameDue(std::uint64_t step) const;
  /// A periodic checkpoint is due at `step` (every checkpoint_every steps).
  [[nodiscard]] bool checkpointDue(std::uint64_t step) const;
  /// The periodic checkpoint's file name at `step`: checkpoint_NNNNNN.bin, N = step / checkpoint_every.
  [[nodiscard]] std::string checkpointName(std::uint64_t step) const;
};

/// Converts run.end_time, run.vtk_interval, run.checkpoint_interval and run.contact_interval with
/// core::intervalSteps (0 is off, except an end time where `endTimeRequired`; off-grid
/// times are rounded with a warning). Fields are named run.field_prefix + ".end_time",
/// ".output.vtk_interval", ".output.checkpoint_interval", ".output.contact_interval".
/// Throws core::InputError.
[[nodiscard]] RunPlan planRun(const RunOptions& run, double timeStep, bool endTimeRequired);

class RunDriver {
 public:
  /// Claims `directory` (claimOutputDirectory with run.overwrite, errors naming
  /// `directoryField`), starts summary.csv, run_log.csv with its configuration rows and a
  /// CSV per sensor. Throws core::InputError / std::runtime_error if it cannot.
  RunDriver(core::World& world, const RunOptions& run, RunPlan plan, const std::filesystem::path& directory,
            const std::string& directoryField);

  /// Wall time spent initialising the world before the run [s], for the run log.
  void setInitialiseSeconds(double seconds) { timing_.initialise_seconds = seconds; }
  /// Writes a checkpoint at a path (the base name ends in .bin).
  using CheckpointWriter = std::function<void(const std::filesystem::path&)>;
  /// Writes the checkpoints with `writer` instead of core::writeCheckpointFile of the world
  /// (the LIGGGHTS backend adds its restart files, LiggghtsBackend::writeCheckpoint).
  void setCheckpointWriter(CheckpointWriter writer) { checkpoint_writer_ = std::move(writer); }
  /// planes.vtp and the frame of the current step; the run's wall clock starts here.
  void start(const core::World& world);
  /// Call after every world step, or after a stride of steps in which no output but the
  /// last step's falls (a backend that hands its particles over every few steps): writes
  /// the frame and checkpoint due at this step.
  void afterStep(const core::World& world);
  /// The final outputs and timing rows (plus "timing,finish_reason,<reason>" if `reason`
  /// is not empty). Only the first finish() or abort() writes; if an output fails, the
  /// log gets status "aborted: ..." and the error is rethrown.
  void finish(const core::World& world, const std::string& reason = {});
  /// Ends the run log with status "aborted: <why>" (nothing if the run already ended).
  void abort(const std::string& why);
  /// Ends a run the watchdog stopped: checkpoint_final.bin of the state it stopped
  /// in (for diagnosis; no frame, which could hold non-finite values), the timing
  /// rows and status "failed: <why>".
  void fail(const core::World& world, const std::string& why);

  [[nodiscard]] const RunPlan& plan() const { return plan_; }
  [[nodiscard]] const RunTiming& timing() const { return timing_; }
  [[nodiscard]] const std::filesystem::path& directory() const { return frames_.directory(); }
  [[nodiscard]] std::size_t frameCount() const { return frames_.frameCount(); }
  /// The sensor CSV files opened at construction.
  [[nodiscard]] const std::vector<std::filesystem::path>& sensorFiles() const { return sensor_files_; }
  /// Wall time since start() [s].
  [[nodiscard]] double wallSeconds() const;

 private:
  void writeFrame(const core::World& world);
  void writeCheckpoint(const core::World& world, const std::string& name);
  void writeContacts(const core::World& world);

  RunOptions run_;
  RunPlan plan_;
  FrameSeries frames_;
  std::vector<core::PvdEntry> contact_entries_;
  DeformableSeries deformables_;
  RunLog log_;
  std::vector<std::filesystem::path> sensor_files_;
  RunTiming timing_;
  std::chrono::steady_clock::time_point start_;
  CheckpointWriter checkpoint_writer_;
  std::uint64_t first_step_ = 0;
  std::uint64_t last_step_ = 0;  ///< of the last start() / afterStep()
  std::uint64_t first_build_ = 0;
  std::uint64_t last_frame_step_ = 0;
  bool ended_ = false;
};

}  // namespace demlink::server
