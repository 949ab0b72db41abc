#pragma once
/// Where the view server's frames come from: a running simulation (LiveViewHub) or a
/// finished run's files (RecordedRun). The server calls a feed on its own thread only.
#include <cstdint>
#include <functional>
#include <optional>
#include <string>

#include "demlink/server/view/view_snapshot.hpp"

namespace demlink::server {

class ViewFeed {
 public:
  virtual ~ViewFeed() = default;
  /// The scene JSON (describeScene), or empty while not known yet (a live run that has
  /// not reached its first step).
  [[nodiscard]] virtual std::string sceneJson() = 0;
  /// Grows whenever the scene changes (a server's next simulation): pages get it again.
  [[nodiscard]] virtual std::uint64_t sceneVersion() = 0;
  /// Frames a recorded run holds; 0 for a live run.
  [[nodiscard]] virtual std::uint32_t frameCount() const = 0;
  /// Simulated time of recorded frame `index` [s] (the timeline's labels).
  [[nodiscard]] virtual double frameTime(std::uint32_t index) const = 0;
  /// A live run: the newest snapshot and its version (which grows with every capture),
  /// or null before the first. A recorded run: frame `index` (clamped), version = index + 1.
  /// The pointer stays valid until the next call.
  [[nodiscard]] virtual const ViewSnapshot* snapshot(std::uint32_t index, std::uint64_t& version) = 0;
  /// What the pages want now: the highest frame rate any asked for [1/s] (0: none
  /// connected) and the optional columns they colour by.
  virtual void setDemand(double framesPerSecond, CaptureFields fields) = 0;
  /// Called (from the simulation thread) after each new capture; the server posts to
  /// its own thread from it. Set once, before the run steps.
  virtual void setNotify(std::function<void()> notify) = 0;
  /// The simulations a live server runs and which one the view follows, as a
  /// "simulations" message; empty when there is nothing to choose (a recorded run).
  [[nodiscard]] virtual std::string simulationsJson() { return {}; }
  /// Grows whenever a simulation opens or closes or the view follows another.
  [[nodiscard]] virtual std::uint64_t simulationsVersion() { return 0; }
  /// Follows simulation `id` (an id of simulationsJson) for every page from now on;
  /// returns why not when that cannot be.
  [[nodiscard]] virtual std::optional<std::string> follow(std::uint64_t /*id*/) {
    return std::string("this view shows one recorded run");
  }
};

}  // namespace demlink::server
