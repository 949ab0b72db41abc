#pragma once
/// The output directory of a headless run: particle frames (.vtp), their .pvd
/// index, the plane walls, and summary.csv with one row per frame.
///
/// The .pvd is rewritten and the CSV row flushed after every frame, so a run that
/// is stopped early still leaves a consistent, viewable series.
#include <cstddef>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "demlink/core/output/vtk_writer.hpp"
#include "demlink/core/world.hpp"

namespace demlink::server {

/// Statistics of one frame, as written to summary.csv (NaN as an empty cell).
struct FrameStats {
  double time = 0.0;                 ///< simulated time [s]
  std::size_t particles = 0;         ///< [-]
  double kinetic_energy = 0.0;       ///< translational + rotational [J]
  double mean_z = 0.0;               ///< mean particle centre height [m] (NaN without particles)
  double max_z = 0.0;                ///< highest particle centre [m] (NaN without particles)
  std::uint64_t neighbour_builds = 0;  ///< Verlet-list builds so far [-]
  double wall_seconds = 0.0;         ///< wall time since the run started [s]
};

/// Statistics of the world's current state (wall_seconds left 0).
[[nodiscard]] FrameStats frameStats(const core::World& world);

class FrameSeries {
 public:
  /// Creates `directory` if needed and starts summary.csv. Throws
  /// core::InputError naming `field` if the directory cannot be created or written.
  FrameSeries(std::filesystem::path directory, const std::string& field);

  /// Writes planes.vtp: each plane as a square centred on the projection of the
  /// scene's centre, sized to the bounds or to the particles and plane points.
  /// Does nothing for a scene without planes.
  void writePlanes(const core::World& world);

  /// Writes particles_<frame>.vtp, rewrites particles.pvd and appends a summary row;
  /// with meshes, also meshes_<frame>.vtp (all meshes at their current pose) and meshes.pvd;
  /// with parallel bonds, bonds_<frame>.vtp (core::writeBondsVtp) and bonds.pvd.
  /// Returns the frame's statistics.
  FrameStats writeFrame(const core::World& world, double wallSeconds);

  [[nodiscard]] std::size_t frameCount() const { return entries_.size(); }
  [[nodiscard]] const std::filesystem::path& directory() const { return directory_; }

 private:
  std::filesystem::path directory_;
  void writeMeshes(const core::World& world, double time);
  void writeBonds(const core::World& world, double time);

  std::vector<core::PvdEntry> entries_;
  std::vector<core::PvdEntry> mesh_entries_;
  std::vector<core::PvdEntry> bond_entries_;
  std::ofstream summary_;
};

}  // namespace demlink::server
