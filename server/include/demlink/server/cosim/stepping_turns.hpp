#pragma once
/// How simulations that step at the same time share the CPUs (docs/server.md, "Several
/// simulations"): at most `concurrent` of them step at once; one that has stepped for a
/// slice while another waits gives its turn to the one that has waited longest and queues
/// again (first come, first served). A simulation that waits for its clients holds no turn.
///
/// Why turns and not only the operating system's scheduler: a simulation's DEM threads
/// spin between loops, so two simulations on two cores each with two threads would fight
/// over every core; with turns the stepping simulations never ask for more CPUs than the
/// machine has (given one engine thread each), and a huge interval in one simulation
/// delays another's short one by at most one slice per turn ahead of it.
#include <atomic>
#include <chrono>
#include <condition_variable>
#include <cstddef>
#include <cstdint>
#include <deque>
#include <mutex>

namespace demlink::server {

class SteppingTurns {
 public:
  using Clock = std::chrono::steady_clock;

  /// `concurrent` >= 1 simulations step at once; a turn is given up after `slice` when
  /// another simulation waits.
  SteppingTurns(std::size_t concurrent, Clock::duration slice);

  /// One simulation's turn for the steps of one interval: waits for it on construction
  /// and gives it back on destruction.
  class Turn {
   public:
    /// Waits until this simulation may step, or `stop` (may be null) becomes true.
    Turn(SteppingTurns& turns, const std::atomic<bool>* stop);
    ~Turn();
    Turn(const Turn&) = delete;
    Turn& operator=(const Turn&) = delete;

    /// Called between two steps: false once `stop` is true. After a slice of stepping, if
    /// another simulation waits, the turn goes to it and this call waits for the next one.
    [[nodiscard]] bool mayStep();

   private:
    SteppingTurns& turns_;
    const std::atomic<bool>* stop_;
    bool held_ = false;
    Clock::time_point since_;
  };

  /// Wakes every waiting simulation so it sees its stop flag (server shutdown).
  void wakeAll();
  /// Simulations allowed to step at once [-].
  [[nodiscard]] std::size_t concurrent() const { return concurrent_; }

 private:
  /// Queues, then waits to be first in the queue with a free turn; false if stopped.
  bool acquire(const std::atomic<bool>* stop);
  void release();
  [[nodiscard]] bool othersWait();

  const std::size_t concurrent_;
  const Clock::duration slice_;
  std::mutex mutex_;
  std::condition_variable changed_;
  std::deque<std::uint64_t> queue_;  ///< tickets of the waiting simulations, oldest first
  std::uint64_t next_ticket_ = 0;
  std::size_t stepping_ = 0;
};

}  // namespace demlink::server
