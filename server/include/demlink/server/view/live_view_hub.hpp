#pragma once
/// The live view's hook into running simulations. A server steps several simulations at
/// once, each on its own thread, which calls offer() after each step; each page follows one
/// of them (ViewFeed: the one it chose, else the default).
///
/// The hub captures every simulation that at least one page follows, and the default: each
/// has captures of its own (SimulationCapture: three snapshot buffers and its scene), made
/// on its own thread when one of its pages wants a frame, so pages following different
/// simulations each get their own. Memory: one SimulationCapture per simulation followed
/// or default, dropped when no page follows it any more or it closes; the number of
/// simulations is bounded by the server.
///
/// The default is the first simulation to offer a world while there is none, until
/// release() says that world is closing; then the next one to offer. A page following a
/// simulation that closed is moved to the default by the server (cannotFollow()).
///
/// offer() of a simulation nobody follows returns after noting its particle count and time
/// for the list of simulations the pages show, and reading whether it is due; of a followed
/// one after one clock read unless one of its pages wants a frame now. The figures and the
/// due time sit in a slot of the simulation's own, so the simulations share no cache line.
#include <atomic>
#include <chrono>
#include <cstdint>
#include <functional>
#include <limits>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <vector>

#include "demlink/server/view/view_feed.hpp"

namespace demlink::server {

class SimulationCapture;

class LiveViewHub final : public ViewFeed {
 public:
  LiveViewHub();
  ~LiveViewHub() override;

  /// Simulation thread, after a step (and once before the first): captures a snapshot
  /// when a page following this simulation wants a frame (at the highest rate one of them
  /// asked for), else returns at once.
  void offer(const core::World& world);
  /// Captures now, due or not, when some page follows this simulation (a run's final state).
  void offerNow(const core::World& world);
  /// Names the simulation of `world` in the pages' list (demlink-server: its output folder,
  /// "sim_003"); a world offered without a name is listed as "simulation <id>".
  void announce(const core::World& world, const std::string& name);
  /// The simulation of `world` is closing (its thread offers no more): it leaves the list
  /// and its captures are dropped; when it was the default the next world to offer is.
  void release(const core::World& world);
  /// Snapshots captured so far, over all simulations [-].
  [[nodiscard]] std::uint64_t captures() const { return captures_.load(std::memory_order_relaxed); }
  /// Simulations that have captures (three snapshot buffers each) now [-].
  [[nodiscard]] std::size_t captureSets();

  std::string sceneJson(SimulationId simulation) override;
  std::uint64_t sceneVersion(SimulationId simulation) override;
  [[nodiscard]] std::uint32_t frameCount() const override { return 0; }
  [[nodiscard]] double frameTime(std::uint32_t /*index*/) const override { return 0.0; }
  const ViewSnapshot* snapshot(SimulationId simulation, std::uint32_t index, std::uint64_t& version) override;
  void setDemand(const std::vector<SimulationDemand>& demands) override;
  void setNotify(std::function<void()> notify) override { notify_ = std::move(notify); }
  std::string simulationsJson(SimulationId simulation) override;
  std::uint64_t simulationsVersion() override;
  std::optional<std::string> cannotFollow(SimulationId id) override;

 private:
  using Clock = std::chrono::steady_clock;
  static constexpr std::int64_t kNever = std::numeric_limits<std::int64_t>::max();

  /// One open simulation. Its own thread writes the figures after every step, the view
  /// thread reads them; the slot is reused once the simulation closes.
  struct alignas(64) Listed {
    std::atomic<const core::World*> world{nullptr};  ///< null: a free slot
    std::uint64_t id = 0;                            ///< guarded by listing_mutex_
    std::string name;                                ///< guarded by listing_mutex_
    std::atomic<std::uint64_t> particles{0};
    std::atomic<double> time{0.0};
    /// Steady-clock time of the next capture [ns]; kNever: none wanted. Written under
    /// listing_mutex_, read without.
    std::atomic<std::int64_t> next_due_ns{kNever};
    std::atomic<std::int64_t> period_ns{0};  ///< 1 / the highest rate its pages want; 0: none
    std::atomic<bool> want_speed{false};
    std::atomic<bool> want_force{false};
    /// Guarded by listing_mutex_; null while no page follows it and it is not the default.
    /// Shared with the thread capturing into it and the view thread reading it, so dropping
    /// it never waits on either.
    std::shared_ptr<SimulationCapture> capture;
  };
  /// The calling thread's last slot, so that a step finds its world's slot without a lock.
  struct ListingCache {
    std::uint64_t hub = 0;  ///< serial_ of the hub the slot belongs to
    const core::World* world = nullptr;
    Listed* slot = nullptr;
  };
  static thread_local ListingCache listing_cache_;

  /// Notes the world's particle count and time in its slot (registering it when new).
  Listed& noteListing(const core::World& world);
  /// Makes `world` the default when there is none.
  void claimDefaultIfNone(const core::World& world, Listed& slot);
  /// Copies `world` into its slot's captures, when it has some.
  void capture(const core::World& world, Listed& slot, Clock::time_point now);
  /// Under listing_mutex_: gives `slot` captures when a page follows it or it is the
  /// default (else drops them), at the highest rate its pages want.
  void applyDemand(Listed& slot);
  /// Under listing_mutex_: the slot of `world`, or null.
  Listed* findSlot(const core::World* world);
  /// Under listing_mutex_: the open simulation a page following `simulation` is shown.
  Listed* shownSlot(SimulationId simulation);
  /// The captures a page following `simulation` is shown, or null.
  std::shared_ptr<SimulationCapture> shownCapture(SimulationId simulation);

  const std::uint64_t serial_;  ///< tells this hub's slots from another's in listing_cache_
  std::atomic<std::uint64_t> captures_{0};
  std::atomic<std::uint64_t> versions_{0};  ///< the scenes' and frames' versions, over all simulations
  std::function<void()> notify_;
  std::atomic<const core::World*> default_{nullptr};

  /// Guards slots_, the slots' ids, names and captures, next_id_, listing_version_,
  /// demands_, and changes of default_ to null.
  std::mutex listing_mutex_;
  std::vector<std::unique_ptr<Listed>> slots_;
  std::uint64_t next_id_ = 1;
  std::uint64_t listing_version_ = 1;
  std::vector<SimulationDemand> demands_;

  /// View thread: the captures of the snapshot snapshot() returned last, kept until the
  /// next call even when their simulation closes meanwhile.
  std::shared_ptr<SimulationCapture> reading_;
};

}  // namespace demlink::server
