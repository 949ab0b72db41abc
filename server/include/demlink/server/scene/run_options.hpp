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
  double checkpoint_interval = 0.0;  ///< simulated time between checkpoint files [s]; 0: none
  double contact_interval = 0.0;     ///< simulated time between contact outputs [s]; 0: none
  bool mesh_loads = false;           ///< per-triangle loads as cell data of the mesh frames
  bool final_checkpoint = true;      ///< write checkpoint_final.bin at the end
  bool final_particles_csv = true;   ///< write particles_final.csv at the end
  /// Checkpoint to continue from (demlink-run --restore), written by a run of the
  /// same scene; empty: start from the scene's initial state.
  std::string restore_file;
  /// Write into a non-empty output folder (demlink-run --overwrite); false: such a folder is
  /// refused, so one run never overwrites another's results (output_directory.hpp).
  bool overwrite = false;
  /// The scene file, for the run log; empty if the scene did not come from a file.
  std::string scene_file;
  /// Scene path of the SimulationBox (e.g. "components[0].simulation_box"), so
  /// errors found at run time name the field in the scene.
  std::string field_prefix = "simulation_box";
};

}  // namespace demlink::server
