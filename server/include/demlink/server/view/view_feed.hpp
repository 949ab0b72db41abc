#pragma once
/// Where the view server's frames come from: a running simulation (LiveViewHub) or a
/// finished run's files (RecordedRun). The server calls a feed on its own thread only.
///
/// A live server runs several simulations; each page follows one of them, named by a
/// SimulationId (kDefaultSimulation until the page chooses), and is sent that one's scene
/// and frames. A recorded run has one and ignores the id.
#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "demlink/server/view/view_snapshot.hpp"

namespace demlink::server {

/// A simulation's id in the "simulations" message (>= 1), or kDefaultSimulation.
using SimulationId = std::uint64_t;
/// The simulation a page that has not chosen follows: the feed's default.
inline constexpr SimulationId kDefaultSimulation = 0;

/// What the pages following one simulation want.
struct SimulationDemand {
  SimulationId simulation = kDefaultSimulation;
  double frames_per_second = 0.0;  ///< the highest rate any of them asked for [1/s]
  CaptureFields fields;            ///< the optional columns any of them colours by
};

class ViewFeed {
 public:
  virtual ~ViewFeed() = default;
  /// The scene JSON (describeScene) of `simulation`, or empty while not known yet (a live
  /// simulation that has not been captured since a page chose it).
  [[nodiscard]] virtual std::string sceneJson(SimulationId simulation) = 0;
  /// Grows whenever the scene changes (a server's next simulation): pages get it again.
  /// Versions are unique across the feed's simulations; 0: no scene yet.
  [[nodiscard]] virtual std::uint64_t sceneVersion(SimulationId simulation) = 0;
  /// Frames a recorded run holds; 0 for a live run.
  [[nodiscard]] virtual std::uint32_t frameCount() const = 0;
  /// Simulated time of recorded frame `index` [s] (the timeline's labels).
  [[nodiscard]] virtual double frameTime(std::uint32_t index) const = 0;
  /// A live run: the newest snapshot of `simulation` and its version (which grows with every
  /// capture and is unique across the simulations), or null before the first. A recorded
  /// run: frame `index` (clamped), version = index + 1. The pointer stays valid until the
  /// next call.
  [[nodiscard]] virtual const ViewSnapshot* snapshot(SimulationId simulation, std::uint32_t index,
                                                     std::uint64_t& version) = 0;
  /// What the pages want now, one entry per simulation some page follows (none: no page).
  virtual void setDemand(const std::vector<SimulationDemand>& demands) = 0;
  /// Called (from a simulation thread) after each new capture and when a simulation opens
  /// or closes; the server posts to its own thread from it. Set once, before the run steps.
  virtual void setNotify(std::function<void()> notify) = 0;
  /// The simulations a live server runs and which one a page following `simulation` is
  /// shown, as a "simulations" message; empty when there is nothing to choose (a recorded run).
  [[nodiscard]] virtual std::string simulationsJson(SimulationId /*simulation*/) { return {}; }
  /// Grows whenever a simulation opens or closes or the default moves to another.
  [[nodiscard]] virtual std::uint64_t simulationsVersion() { return 0; }
  /// Why a page cannot follow simulation `id` (no open simulation has it), or nullopt when it can.
  [[nodiscard]] virtual std::optional<std::string> cannotFollow(SimulationId /*id*/) {
    return std::string("this view shows one recorded run");
  }
};

}  // namespace demlink::server
