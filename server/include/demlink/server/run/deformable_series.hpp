#pragma once
/// The output files of a run's deformable bodies (docs/deformable.md, "Scene files and
/// clients"):
///   deformable_<name>_NNNNNN.vtp  mass-spring body: nodes, springs as lines, triangles
///                                 (cell field "intact": 0 for a broken spring)
///   deformable_<name>_NNNNNN.vtu  FEM body: tetrahedra with displacement, velocity and
///                                 von Mises stress per cell (.vtp of the surface for
///                                 imported matrices, which have no elements)
///   deformable_<name>.pvd         the body's series, a frame with every particle frame
///   broken_springs.csv            one row per broken spring, written in the step it broke
///
/// Why a file per body and not one file: a mass-spring sheet and an FEM block are
/// different VTK data set types (PolyData, UnstructuredGrid).
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "demlink/core/output/vtk_writer.hpp"
#include "demlink/core/world.hpp"

namespace demlink::server {

/// One line per deformable body for compile reports and the log: kind, nodes, springs,
/// triangles, its critical time step and what sets it.
[[nodiscard]] std::vector<std::string> deformableReportLines(const core::World& world);
/// One line per deformable body at the end of a run: broken springs, kinetic energy,
/// reactions at the fixed and driven nodes.
[[nodiscard]] std::vector<std::string> deformableFinalLines(const core::World& world);

class DeformableSeries {
 public:
  /// Opens broken_springs.csv in `directory` (which exists) when the world has a
  /// mass-spring body; springs broken before now (a restored checkpoint) are not listed
  /// again. Throws std::runtime_error if the file cannot be written.
  DeformableSeries(const std::filesystem::path& directory, const core::World& world);

  /// Writes every body's frame file and rewrites its .pvd.
  void writeFrame(const core::World& world);
  /// Appends the springs that broke since the last call to broken_springs.csv.
  void afterStep(const core::World& world);

 private:
  std::filesystem::path directory_;
  std::vector<std::vector<core::PvdEntry>> entries_;  ///< per body
  std::vector<std::size_t> broken_written_;           ///< per body: rows written so far
  std::ofstream broken_;
};

}  // namespace demlink::server
