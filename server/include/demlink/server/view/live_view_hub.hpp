#pragma once
/// The live view's hook into a running simulation. The stepping thread calls offer()
/// after each step; it returns after one clock read unless a page wants a frame now,
/// and then copies a snapshot (captureSnapshot) into a buffer no reader touches.
///
/// Three buffers: the simulation writes `back`, the view thread reads `front`, and `ready`
/// holds the newest complete capture. Publishing swaps back and ready, taking one swaps
/// ready and front: two pointer swaps under a mutex that is never held for longer, so
/// neither thread ever waits on the other's copying or encoding, and a view that falls
/// behind just skips captures. Memory: three snapshots of the largest particle count seen.
///
/// A server steps several simulations at once, each on its own thread; the view follows
/// one of them: the first to offer a world while none is followed, or the one a page
/// chose (follow()), until release() says that world is closing. Offers from the others
/// return after noting their particle count and time for the list of simulations the
/// pages show (in a slot of their own, so the simulations share no cache line).
#include <atomic>
#include <chrono>
#include <cstdint>
#include <functional>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <vector>

#include "demlink/server/view/view_feed.hpp"

namespace demlink::server {

class LiveViewHub final : public ViewFeed {
 public:
  LiveViewHub();

  /// Simulation thread, after a step (and once before the first): captures a snapshot
  /// when a frame is due (at the highest rate a page asked for), else returns at once.
  /// Another world than the last one (or a clock that went back) is a new simulation:
  /// its scene is described again and the pages are sent it.
  void offer(const core::World& world);
  /// Captures now whether or not a frame is due (a run's final state).
  void offerNow(const core::World& world);
  /// Names the simulation of `world` in the pages' list (demlink-server: its output folder,
  /// "sim_003"); a world offered without a name is listed as "simulation <id>".
  void announce(const core::World& world, const std::string& name);
  /// The simulation of `world` is closing (its thread offers no more): it leaves the list,
  /// and when it was followed the next world to offer is followed.
  void release(const core::World& world);
  /// Snapshots captured so far [-].
  [[nodiscard]] std::uint64_t captures() const { return captures_.load(std::memory_order_relaxed); }

  std::string sceneJson() override;
  std::uint64_t sceneVersion() override;
  [[nodiscard]] std::uint32_t frameCount() const override { return 0; }
  [[nodiscard]] double frameTime(std::uint32_t /*index*/) const override { return 0.0; }
  const ViewSnapshot* snapshot(std::uint32_t index, std::uint64_t& version) override;
  void setDemand(double framesPerSecond, CaptureFields fields) override;
  void setNotify(std::function<void()> notify) override { notify_ = std::move(notify); }
  std::string simulationsJson() override;
  std::uint64_t simulationsVersion() override;
  std::optional<std::string> follow(std::uint64_t id) override;

 private:
  using Clock = std::chrono::steady_clock;
  /// One open simulation in the pages' list. Its own thread writes the figures after
  /// every step, the view thread reads them; the slot is reused once the simulation closes.
  struct Listed {
    std::atomic<const core::World*> world{nullptr};  ///< null: a free slot
    std::uint64_t id = 0;                            ///< guarded by listing_mutex_
    std::string name;                                ///< guarded by listing_mutex_
    std::atomic<std::uint64_t> particles{0};
    std::atomic<double> time{0.0};
  };
  /// The calling thread's last slot, so that a step finds its world's slot without a lock.
  struct ListingCache {
    std::uint64_t hub = 0;  ///< serial_ of the hub the slot belongs to
    const core::World* world = nullptr;
    Listed* slot = nullptr;
  };
  static thread_local ListingCache listing_cache_;

  void capture(const core::World& world, Clock::time_point now);
  /// Under capture_mutex_: describes a new simulation's scene when `world` is one.
  void describeIfNew(const core::World& world);
  /// Whether `world` is the one followed (claiming it when none is).
  bool follows(const core::World& world);
  /// Notes the world's particle count and time in its slot (registering it when new).
  void noteListing(const core::World& world);
  /// Under listing_mutex_: the slot of `world`, or null.
  Listed* findSlot(const core::World* world);

  const std::uint64_t serial_;  ///< tells this hub's slots from another's in listing_cache_
  std::atomic<std::int64_t> next_due_ns_;      ///< steady-clock time of the next capture; max: none wanted
  std::atomic<std::int64_t> period_ns_;        ///< 1 / the highest wanted rate; 0: none wanted
  std::atomic<bool> want_speed_{true};
  std::atomic<bool> want_force_{false};
  std::atomic<std::uint64_t> captures_{0};
  std::function<void()> notify_;
  std::atomic<const core::World*> followed_{nullptr};

  std::mutex listing_mutex_;  ///< guards slots_, next_id_, listing_version_ and changes of followed_ by id
  std::vector<std::unique_ptr<Listed>> slots_;
  std::uint64_t next_id_ = 1;
  std::uint64_t listing_version_ = 1;

  /// Held by the followed simulation's thread while it captures, and by follow() while it
  /// hands the view to another: two simulations never capture at once.
  std::mutex capture_mutex_;
  std::mutex mutex_;  ///< guards ready_, ready_version_ and scene_
  std::unique_ptr<ViewSnapshot> back_;
  std::unique_ptr<ViewSnapshot> ready_;
  std::unique_ptr<ViewSnapshot> front_;
  std::uint64_t ready_version_ = 0;
  std::uint64_t front_version_ = 0;
  std::string scene_;
  std::uint64_t scene_version_ = 0;

  // Under capture_mutex_: the previous capture, for the rate figures.
  bool captured_before_ = false;
  bool scene_pending_ = false;  ///< the scene is described; publish it with the next capture
  std::string pending_scene_;
  const core::World* last_world_ = nullptr;
  Clock::time_point last_wall_{};
  double last_time_ = 0.0;
  std::uint64_t last_step_ = 0;
  double initial_mass_ = 0.0;
};

}  // namespace demlink::server
