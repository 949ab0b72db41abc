#pragma once
/// run_log.csv: the configuration and timing of a headless run, one
/// "section,key,value,unit" row per item (the solver paper's logging subsystem
/// "exports all time and solver configuration data into a CSV file").
///
/// Why rows and not one wide line: the configuration is written (and flushed)
/// when the run starts, the timing appended when it ends, so a run that aborts
/// still leaves a valid CSV with its configuration and a "status" row saying it
/// did not finish. Columns are listed in docs/state.md.
#include <filesystem>
#include <fstream>
#include <string>
#include <string_view>

#include "demlink/core/world.hpp"
#include "demlink/server/scene/run_options.hpp"

namespace demlink::server {

/// Timing of a finished run (all wall-clock seconds).
struct RunTiming {
  double initialise_seconds = 0.0;  ///< world initialisation and restore [s]
  double total_seconds = 0.0;       ///< from the first to the last output [s]
  double output_seconds = 0.0;      ///< writing frames, checkpoints and CSVs [s]
  std::uint64_t steps = 0;          ///< steps taken in this run [-]
  std::uint64_t particle_steps = 0; ///< sum over steps of the particle count [-]
  std::uint64_t neighbour_builds = 0;  ///< builds during this run [-]
  std::size_t frames = 0;           ///< [-]
  std::size_t checkpoints = 0;      ///< checkpoint files written [-]
};

/// "<stage> <seconds> s (<share> %), ..." for every stage that ran, from the world's
/// sampled stage timing (World::setStageTiming); shares are of the stages' sum. For the
/// end of a run: a headless run logs it, a co-simulation appends it to
/// compile_report.txt.
std::string stageTimingSummary(const core::World& world);

class RunLog {
 public:
  /// Creates `path` and writes the header. Throws std::runtime_error if it cannot.
  explicit RunLog(const std::filesystem::path& path);

  /// Appends one row (quoting value if needed) and flushes.
  void add(std::string_view section, std::string_view key, std::string_view value, std::string_view unit = "");
  /// The configuration rows: scene, settings, critical time step, particles, stages.
  void writeConfiguration(const core::World& world, const RunOptions& run, std::uint64_t endStep);
  /// The timing rows and status "completed".
  void writeTiming(const core::World& world, const RunTiming& timing);

 private:
  std::ofstream out_;
  std::filesystem::path path_;
};

}  // namespace demlink::server
