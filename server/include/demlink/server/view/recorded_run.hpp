#pragma once
/// A finished run's output folder as a ViewFeed (demlink-view): the particle frames of
/// particles.pvd, the meshes of meshes.pvd, planes.vtp and each deformable_<name>.pvd
/// surface series, read with vtk_series_reader.hpp one frame at a time, when a page asks.
///
/// The files hold world-frame vertices, not poses, so meshes, planes and deformable
/// surfaces all travel as surfaces (ViewSurface) whose triangles (and a mass-spring body's
/// springs) the scene JSON lists once; each frame's cell data "intact" flags the torn.
/// The files hold no masses, so the overlay's mass figures stay empty.
#include <filesystem>
#include <string>
#include <vector>

#include "demlink/server/view/view_feed.hpp"
#include "demlink/server/view/vtk_series_reader.hpp"

namespace demlink::server {

class RecordedRun final : public ViewFeed {
 public:
  /// Reads the folder's .pvd indexes (and the first frame, for the scene); throws
  /// core::InputError naming `field` when the folder holds no particles.pvd, or naming the
  /// file that cannot be read.
  RecordedRun(const std::filesystem::path& directory, const std::string& field);

  std::string sceneJson(SimulationId /*simulation*/) override { return scene_; }
  std::uint64_t sceneVersion(SimulationId /*simulation*/) override { return 1; }
  [[nodiscard]] std::uint32_t frameCount() const override { return static_cast<std::uint32_t>(frames_.size()); }
  [[nodiscard]] double frameTime(std::uint32_t index) const override;
  /// Frame `index` (clamped to the last); version = index + 1. Throws core::InputError
  /// when a frame's file is unreadable.
  const ViewSnapshot* snapshot(SimulationId simulation, std::uint32_t index, std::uint64_t& version) override;
  void setDemand(const std::vector<SimulationDemand>& /*demands*/) override {}
  void setNotify(std::function<void()> /*notify*/) override {}

 private:
  /// One surface series: a name, its triangles (from its first file), its files by frame
  /// and a mass-spring body's springs (from its first file).
  struct SurfaceSeries {
    std::string name;
    std::vector<std::array<std::uint32_t, 3>> triangles;
    std::vector<PvdFrame> frames;  ///< one entry: the same file at every frame (planes.vtp)
    std::vector<std::array<std::uint32_t, 2>> springs;  ///< a mass-spring body's, as its files' line cells
  };
  void load(std::uint32_t index);

  std::vector<PvdFrame> frames_;
  std::vector<SurfaceSeries> surfaces_;
  std::string scene_;
  ViewSnapshot snapshot_;
  std::uint32_t loaded_ = 0;
  bool any_loaded_ = false;
};

}  // namespace demlink::server
