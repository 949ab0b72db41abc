#pragma once
/// A small persistent thread pool for the step's parallel loops.
///
/// Why not OpenMP fork/join: a step runs a handful of short parallel loops (tens of
/// microseconds to milliseconds). libgomp's waiting threads spin for a long time; when
/// another process holds the second core, the spinning thread keeps the core its
/// partner needs, and each join can cost a whole scheduler time slice. Here a waiting
/// thread follows the spin-then-block rule of spin_wait.hpp: it polls for a bounded
/// time (the budget) while a free CPU allows it, so the next hand-over of the same step
/// costs well under a microsecond instead of a futex wake-up, then sleeps on a futex
/// via C++20 std::atomic::wait, giving the core away.
///
/// Work claiming: run(chunks, body) gives every thread (the caller is thread 0) a home
/// range of contiguous chunks, the same for every loop of the same size. A thread claims
/// its home range front to back, then the others' ranges from their backs, each claim
/// one compare-and-swap on the range's own cache line. Why home ranges: the step's loops
/// stream the same particles one after another, so a thread that gets the same chunks
/// again finds them in its own cache; chunks handed out by one shared ticket land on the
/// threads at random, and each loop pulls half of its data from the other core's cache.
/// Stealing from the back keeps the rest: a descheduled or slow thread only holds up the
/// chunk it is running, never a fixed share of the work.
///
/// When a loop goes to the workers (offersToWorkers): every loop of two or more chunks
/// while a worker is awake (spinning between loops: a hand-over costs about a
/// microsecond); while all workers sleep, any loop while the gate of spin_wait.hpp sees a
/// free CPU for every pool thread (the woken worker then spins between loops again), and
/// only a loop whose last run held at least kWakeWorthBusySeconds of work when it does
/// not. Why the gate decides: a worker without a free core arrives late or not at all
/// while the caller pays the wake-up and waits for its chunk in flight. With free cores
/// a wake-up is paid once, and a worker that fell asleep is woken again by the next
/// loop, however short the loops are. No serial-against-threaded timing. A worker
/// descheduled by another process holds up at most the one chunk it is running, the
/// caller claims all the others, and the caller's join wait spins only while the gate
/// of spin_wait.hpp sees a free CPU for every pool thread, so it blocks at once and
/// leaves its core to the descheduled worker (the scheduler pulls it over) when it does
/// not. Callers make their results independent of which thread ran which chunk
/// (parallel_loops.hpp), so none of this changes a result. docs/benchmarks.md has the
/// measurements behind these choices.
#include <array>
#include <atomic>
#include <chrono>
#include <cstdint>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

#include "demlink/core/parallel/spin_wait.hpp"

namespace demlink::core {

/// The operating system refused a thread (address space, RLIMIT_NPROC): the pool joined
/// the threads it had started and throws this instead of terminating the process.
class ThreadStartError : public std::runtime_error {
 public:
  ThreadStartError(std::uint32_t started, std::uint32_t requested, const std::string& cause);
  /// Threads that were running (the caller's included) [-].
  [[nodiscard]] std::uint32_t started() const { return started_; }

 private:
  std::uint32_t started_;
};

/// How long a pool thread spins between loops before it sleeps, when nothing else is
/// asked for [ns]: DEMLINK_SPIN_WAIT_US when set (0 = never), otherwise 200 us. Longer
/// than an exchange wait's 50 us because a step's serial stretches (mesh contacts,
/// sensors, the watchdog) last up to a few hundred microseconds in large scenes, and a
/// worker that sleeps through one pays a wake-up and starts the next loop late
/// (docs/benchmarks.md). Spinning is still gated to free CPUs (spin_wait.hpp).
[[nodiscard]] std::chrono::nanoseconds defaultPoolSpinBudget();

/// What `threads: 0` (auto) resolves to, and why.
struct AutoThreadChoice {
  std::uint32_t threads = 1;
  std::string reason;  ///< e.g. "auto: 2 CPUs usable, load average 1.3 -> 1 thread"
};

/// The thread count for `threads: 0`: the CPUs this process may run on
/// (sched_getaffinity; std::thread::hardware_concurrency when unknown) less the
/// ones other work keeps busy (the 1-minute load average, rounded), at least 1.
/// A count that later proves too high costs little: a descheduled worker holds up
/// at most one chunk of a loop (see ThreadPool).
[[nodiscard]] AutoThreadChoice chooseAutoThreads();

/// How the pool's loops ran so far (for reports and benchmarks).
struct ThreadPoolStats {
  std::uint64_t parallel_runs = 0;  ///< loops offered to the workers
  std::uint64_t serial_runs = 0;    ///< loops of 2+ chunks the caller ran alone (too short to wake a worker)
  std::uint64_t caller_chunks = 0;  ///< chunks of offered loops the caller ran
  std::uint64_t worker_chunks = 0;  ///< chunks of offered loops the workers ran
  std::uint64_t woken_runs = 0;     ///< offered loops that found every worker asleep
};

class ThreadPool {
 public:
  /// Most chunks of one run() [-] (the ticket packs the chunk index in 16 bits).
  static constexpr std::uint32_t kMaxChunks = 0xFFFF;

  /// A pool of `threads` threads in total: the calling thread plus threads-1 workers.
  /// Throws ThreadStartError (after joining the workers it started) when one cannot start.
  /// `spinBudget`: how long a waiting thread polls before it sleeps (zero: never).
  explicit ThreadPool(std::uint32_t threads, std::chrono::nanoseconds spinBudget = defaultPoolSpinBudget());
  ~ThreadPool();
  ThreadPool(const ThreadPool&) = delete;
  ThreadPool& operator=(const ThreadPool&) = delete;

  [[nodiscard]] std::uint32_t size() const { return static_cast<std::uint32_t>(workers_.size()) + 1; }

  /// Runs body(chunk) once for every chunk in [0, chunks) (at most kMaxChunks), on
  /// whichever thread claims it first; returns when all are done. Not reentrant.
  template <class Body>
  void run(std::uint32_t chunks, const Body& body) {
    if (workers_.empty() || chunks <= 1) {
      for (std::uint32_t chunk = 0; chunk < chunks; ++chunk) body(chunk);
      return;
    }
    dispatch(chunks, [](const void* context, std::uint32_t chunk) { (*static_cast<const Body*>(context))(chunk); },
             &body);
  }

  [[nodiscard]] ThreadPoolStats stats() const { return stats_; }

  /// Work of a loop worth waking sleeping workers for even when the gate sees no free CPU
  /// for them [s]: a worker that shares a core with another process still takes a part
  /// of a loop this long, and the wake-up is small beside it.
  static constexpr double kWakeWorthBusySeconds = 2e-3;

  /// The decision rule of the file comment: whether a loop of `chunks` chunks goes to the
  /// workers, with `workersAwake` (some worker spinning, not asleep), `workSeconds` the
  /// work of the loop's last run (its time scaled by all chunks over those the caller
  /// ran; negative: not run yet) and `coresFree` (the gate sees a free CPU for every pool
  /// thread).
  [[nodiscard]] static bool offersToWorkers(std::uint32_t chunks, bool workersAwake, double workSeconds,
                                            bool coresFree) {
    if (chunks < 2) return false;
    if (workersAwake || workSeconds < 0.0 || workSeconds >= kWakeWorthBusySeconds) return true;
    return coresFree;
  }

 private:
  using Task = void (*)(const void* context, std::uint32_t chunk);

  /// What the pool knows of one loop (call site).
  struct Site {
    Task task = nullptr;
    double work_seconds = -1.0;  ///< the last run's work (offersToWorkers) [s]; negative: none yet
  };
  /// Distinct loops told apart; further ones share the last entry [-].
  static constexpr std::size_t kMaxSites = 32;

  void dispatch(std::uint32_t chunks, Task task, const void* context);
  /// Runs all chunks on the caller and the workers; returns how many the caller ran.
  std::uint32_t runParallel(std::uint32_t chunks, Task task, const void* context);
  /// Thread `self` claims and runs chunks of loop `generation` until none is left (its home
  /// range, then the others'); returns how many it ran.
  std::uint32_t drain(std::uint32_t self, std::uint32_t generation);
  void stopWorkers();
  void workerLoop(std::uint32_t self);
  Site& siteOf(Task task);

  /// One thread's home range of the current loop, on a cache line of its own.
  struct alignas(64) Range {
    std::atomic<std::uint64_t> word{0};  ///< generation (32 bits) | front (16) | back (16)
  };

  std::vector<std::thread> workers_;
  std::vector<Range> ranges_;  ///< one per thread, the caller's first
  alignas(64) std::atomic<std::uint32_t> generation_{0};  ///< bumped per offered loop; workers sleep on it
  alignas(64) std::atomic<std::uint32_t> done_{0};        ///< chunks finished in the current loop
  alignas(64) std::atomic<bool> stop_{false};
  Task task_ = nullptr;
  const void* context_ = nullptr;
  std::uint32_t chunks_ = 0;  ///< chunks of the current loop
  std::chrono::nanoseconds spin_budget_;  ///< spin before blocking (spin_wait.hpp)
  std::atomic<std::uint32_t> asleep_{0};  ///< workers blocked (not spinning) on generation_
  bool in_gate_ = false;                  ///< counted in SpinGate's DEM threads

  // Caller thread only.
  ThreadPoolStats stats_;
  std::array<Site, kMaxSites> sites_{};
  std::size_t site_count_ = 0;
};

}  // namespace demlink::core
