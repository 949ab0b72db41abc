#pragma once
/// One simulation's captures for the pages that follow it: its snapshots in three buffers
/// and the scene they belong to (LiveViewHub keeps one per followed simulation).
///
/// The simulation writes `back`, the view thread reads `front`, and `ready` holds the newest
/// complete capture. Publishing swaps back and ready, taking one swaps ready and front: two
/// pointer swaps under a mutex that is never held for longer, so neither thread ever waits
/// on the other's copying or encoding, and a view that falls behind just skips captures.
/// Memory: three snapshots of the largest particle count seen.
///
/// capture() runs on the simulation's own thread, one call at a time; the rest on the view's.
#include <atomic>
#include <chrono>
#include <cstdint>
#include <memory>
#include <mutex>
#include <string>

#include "demlink/server/view/view_snapshot.hpp"

namespace demlink::server {

class SimulationCapture {
 public:
  using Clock = std::chrono::steady_clock;

  SimulationCapture();

  /// Copies `world` into the back buffer and publishes it. Another world than the last one
  /// (or a step count that went back) is a new simulation: its scene is described again and
  /// published together with this frame, so a page that is sent the scene is never sent a
  /// frame of the simulation before it. Scene and frame take their versions from `versions`,
  /// a counter shared by all captures, so no two scenes or frames of a view share one.
  void capture(const core::World& world, const CaptureFields& fields, Clock::time_point now,
               std::atomic<std::uint64_t>& versions);

  /// The scene JSON (describeScene), or empty before the first capture.
  [[nodiscard]] std::string sceneJson();
  /// The scene's version; 0 before the first capture.
  [[nodiscard]] std::uint64_t sceneVersion();
  /// The newest snapshot and its version, or null before the first capture. The pointer
  /// stays valid until the next call (or this object's end).
  [[nodiscard]] const ViewSnapshot* snapshot(std::uint64_t& version);

 private:
  std::mutex mutex_;  ///< guards ready_, ready_version_, scene_ and scene_version_
  std::unique_ptr<ViewSnapshot> back_;
  std::unique_ptr<ViewSnapshot> ready_;
  std::unique_ptr<ViewSnapshot> front_;
  std::uint64_t ready_version_ = 0;
  std::uint64_t front_version_ = 0;
  std::string scene_;
  std::uint64_t scene_version_ = 0;

  // The simulation thread's own: the previous capture, for the rate figures.
  bool captured_before_ = false;
  const core::World* last_world_ = nullptr;
  Clock::time_point last_wall_{};
  double last_time_ = 0.0;
  std::uint64_t last_step_ = 0;
  double initial_mass_ = 0.0;
};

}  // namespace demlink::server
