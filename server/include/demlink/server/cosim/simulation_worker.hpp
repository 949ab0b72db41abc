#pragma once
/// One simulation's thread (docs/server.md, "Threads"): it runs the calls into its own
/// CosimHost one at a time, in the order the network thread queued them, and the host's
/// timers (poll() at nextDeadline()). After every call it hands what the host returned,
/// with the host's status, to `report` (which posts it to the network thread), except a
/// call that returned nothing while the next is already queued: the next call's report
/// covers it. The thread ends by itself once its simulation has ended.
///
/// The host is only ever touched by this thread, so it needs no locks; the network thread
/// never waits for it except in finish() (server shutdown), which the host's stop flag
/// keeps short.
///
/// Between calls the thread waits spin-then-block (core/parallel/spin_history.hpp) with
/// the network loop's budget: a client exchanging back to back sends its next package a
/// round trip after the answer, and a thread blocked on the condition variable would add
/// its wake-up (tens of microseconds on a VM) to every round trip. It spins as the network
/// loop's deputy, not as an exchange party of its own: of the two, only one works on a
/// package at a time, and the gate still counts each spinner.
#include <atomic>
#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <deque>
#include <functional>
#include <memory>
#include <mutex>
#include <thread>
#include <vector>

#include "demlink/server/cosim/cosim_host.hpp"

namespace demlink::server {

class SimulationWorker {
 public:
  using Work = std::function<std::vector<Outgoing>(CosimHost&)>;
  /// What the host returned, its status after the call, whether its simulation has ended,
  /// and how many posted calls have run so far (timer polls not counted).
  using Report = std::function<void(std::vector<Outgoing>, CosimHost::Status, bool ended, std::uint64_t calls_done)>;

  /// `spinWait`: the spin budget of the waits between calls (0: block at once).
  SimulationWorker(std::unique_ptr<CosimHost> host, Report report,
                   std::chrono::nanoseconds spinWait = std::chrono::nanoseconds::zero());
  /// Drops queued work and joins the thread.
  ~SimulationWorker();
  SimulationWorker(const SimulationWorker&) = delete;
  SimulationWorker& operator=(const SimulationWorker&) = delete;

  /// Queues a call into the host (after the calls queued before it).
  void post(Work work);
  /// Drops the queued calls, runs `last` on the thread once the call in progress returns,
  /// joins the thread and returns what `last` returned (nothing if the simulation had
  /// already ended). Not reported through `report`.
  std::vector<Outgoing> finish(const Work& last);

 private:
  void loop();

  std::unique_ptr<CosimHost> host_;
  Report report_;
  std::mutex mutex_;
  std::condition_variable wake_;
  std::deque<Work> queue_;
  /// queue_.size() or quit_, readable without the lock: what a spinning wait polls.
  std::atomic<std::size_t> pending_{0};
  std::chrono::nanoseconds spin_wait_{0};
  bool quit_ = false;
  bool ended_ = false;  ///< the host's simulation has ended; the thread returns
  std::uint64_t calls_done_ = 0;  ///< the thread's own count
  std::thread thread_;
};

}  // namespace demlink::server
