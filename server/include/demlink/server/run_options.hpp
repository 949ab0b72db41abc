#pragma once
/// What a headless run needs besides the world: when to stop and where and how
/// often to write results. Filled by the scene translator from the
/// SimulationBox's end_time and output settings.
#include <string>

namespace demlink::server {

struct RunOptions {
  double end_time = 0.0;           ///< simulated time at which the run stops [s]
  std::string output_directory;    ///< where frames and summary.csv go; empty: the caller's default
  double vtk_interval = 0.0;       ///< simulated time between frames [s]; 0: first and last frame only
  double progress_interval = 2.0;  ///< wall-clock time between progress lines [s]
  /// Scene path of the SimulationBox (e.g. "components[0].simulation_box"), so
  /// errors found at run time name the field in the scene.
  std::string field_prefix = "simulation_box";
};

}  // namespace demlink::server
