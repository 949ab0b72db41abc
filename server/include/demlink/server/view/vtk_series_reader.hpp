#pragma once
/// Reads back the VTK XML a DEMLink run writes (core/output/vtk_writer.hpp): ParaView
/// collections (.pvd) and PolyData (.vtp) in either of the writer's encodings (appended
/// raw in the machine's byte order, or ascii). Only what the writer produces is accepted;
/// anything else is refused with core::InputError naming the file and what is wrong.
#include <array>
#include <cstdint>
#include <filesystem>
#include <map>
#include <string>
#include <vector>

namespace demlink::server {

struct PvdFrame {
  double time = 0.0;               ///< [s]
  std::filesystem::path file;      ///< resolved against the .pvd's folder
};

/// The DataSet entries of a .pvd, in file order.
[[nodiscard]] std::vector<PvdFrame> readPvd(const std::filesystem::path& path);

/// One DataArray's values (integers exactly in `integers` too, for ids).
struct VtkColumn {
  int components = 1;
  std::vector<double> values;
  std::vector<std::uint64_t> integers;
};

struct PolyData {
  std::size_t point_count = 0;
  std::vector<double> points;  ///< x, y, z per point
  std::map<std::string, VtkColumn> point_data;
  /// Per cell, in VTK's cell order (Verts, Lines, Polys): a deformable body's "intact".
  std::map<std::string, VtkColumn> cell_data;
  std::vector<std::array<std::uint32_t, 2>> lines;      ///< the Lines section's 2-point cells
  std::vector<std::array<std::uint32_t, 3>> triangles;  ///< the Polys section's 3-corner cells
};

/// Reads a .vtp the run wrote (particles, meshes, planes, deformable surfaces).
[[nodiscard]] PolyData readPolyData(const std::filesystem::path& path);

}  // namespace demlink::server
