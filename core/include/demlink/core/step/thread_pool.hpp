#pragma once
/// A small persistent thread pool for the step's parallel loops.
///
/// Why not OpenMP fork/join: a step runs ~5 parallel loops of 0.01-3 ms. libgomp's
/// waiting threads spin for a long time; when another process holds the second
/// core, the spinning thread keeps the core its partner needs, and each join can
/// cost a whole scheduler time slice: a 2-thread run became ~470x slower beside
/// two busy processes (docs/benchmarks.md). Here a waiting thread follows the
/// spin-then-block rule of spin_wait.hpp: it polls for a bounded time (the budget,
/// 50 us by default) while a free CPU allows it, so the next hand-over of the same
/// step costs well under a microsecond instead of a futex wake-up (tens of us), then
/// sleeps on a futex via C++20 std::atomic::wait, giving the core away.
///
/// Work claiming: run(chunks, body) publishes the chunks; the caller and every
/// awake worker claim the next unclaimed chunk through one atomic ticket until none
/// is left, so a descheduled or slow thread only holds up the chunk it is running,
/// never a fixed share of the work.
///
/// Never slower than one thread: each loop (told apart by its call site) is judged on
/// its own, on what it costs the step both ways. While probing, the pool runs the
/// loop alternately on all threads and on the caller alone and times each run from
/// its start to the start of the next loop (so the cost of a worker's results in
/// another core's cache, paid by the serial code after the loop, counts too). A loop
/// too short to gain from threads (a few chunks of element-wise work on an idle
/// machine, or anything beside a busy process) is then run on the caller alone, a loop
/// that gains on all threads, for a hold period that doubles while the verdict stays
/// the same; a threaded loop that starts losing (another process took a core) returns
/// to the caller alone at once. Callers make their results independent of which thread
/// ran which chunk (parallel.hpp), so this decision never changes a result.
#include <array>
#include <atomic>
#include <chrono>
#include <cstdint>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

#include "demlink/core/step/spin_wait.hpp"

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

/// What `threads: 0` (auto) resolves to, and why.
struct AutoThreadChoice {
  std::uint32_t threads = 1;
  std::string reason;  ///< e.g. "auto: 2 CPUs usable, load average 1.3 -> 1 thread"
};

/// The thread count for `threads: 0`: the CPUs this process may run on
/// (sched_getaffinity; std::thread::hardware_concurrency when unknown) less the
/// ones other work keeps busy (the 1-minute load average, rounded), at least 1.
/// A count that later proves too high costs little: the pool falls back to the
/// caller alone while threading does not pay.
[[nodiscard]] AutoThreadChoice chooseAutoThreads();

/// How the pool's loops ran so far (for reports and benchmarks).
struct ThreadPoolStats {
  std::uint64_t parallel_runs = 0;  ///< loops offered to the workers
  std::uint64_t serial_runs = 0;    ///< loops the caller ran alone (probes included)
  std::uint64_t fallbacks = 0;      ///< times a loop was put on the caller alone
  std::uint64_t probes = 0;         ///< serial-against-threaded comparisons made
};

class ThreadPool {
 public:
  /// Most chunks of one run() [-] (the ticket packs the chunk index in 16 bits).
  static constexpr std::uint32_t kMaxChunks = 0xFFFF;

  /// A pool of `threads` threads in total: the calling thread plus threads-1 workers.
  /// Throws ThreadStartError (after joining the workers it started) when one cannot start.
  /// `spinBudget`: how long a waiting thread polls before it sleeps (zero: never).
  explicit ThreadPool(std::uint32_t threads, std::chrono::nanoseconds spinBudget = defaultSpinBudget());
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

 private:
  using Task = void (*)(const void* context, std::uint32_t chunk);

  /// What the pool knows of one loop (call site) [s].
  struct Site {
    Task task = nullptr;
    bool parallel = true;        ///< the current verdict
    std::uint32_t hold_left = 0;  ///< runs before the next probe (0: probing)
    std::uint32_t hold = 0;       ///< length of the last hold [runs]
    std::uint32_t probe_runs = 0;  ///< runs of the current probe
    double probe_serial = 0.0;    ///< summed serial run times of the probe
    double probe_parallel = 0.0;  ///< summed threaded run times of the probe
    double serial_mean = 0.0;     ///< mean serial run time of the last probe
    double loss = 0.0;            ///< threaded time beyond serial_mean during a hold
  };
  /// Distinct loops judged separately; further ones share the last entry [-].
  static constexpr std::size_t kMaxSites = 32;

  void dispatch(std::uint32_t chunks, Task task, const void* context);
  /// Runs all chunks on the caller and the workers.
  void runParallel(std::uint32_t chunks, Task task, const void* context);
  /// Claims and runs chunks of the current ticket until none is left; returns how many it ran.
  std::uint32_t drain();
  void stopWorkers();
  void workerLoop();
  Site& siteOf(Task task);
  /// Records one run of `site` (its time until the next loop started) [s].
  void judge(Site& site, bool parallel, double seconds);

  std::vector<std::thread> workers_;
  /// generation (32 bits) | chunks (16) | next unclaimed chunk (16).
  std::atomic<std::uint64_t> ticket_{0};
  std::atomic<std::uint32_t> generation_{0};  ///< bumped per offered loop; workers sleep on it
  std::atomic<std::uint32_t> done_{0};        ///< chunks finished in the current loop
  std::atomic<bool> stop_{false};
  Task task_ = nullptr;
  const void* context_ = nullptr;
  std::chrono::nanoseconds spin_budget_;  ///< spin before blocking (spin_wait.hpp)
  bool in_gate_ = false;                  ///< counted in SpinGate's DEM threads

  // Adaptive threading (caller thread only).
  ThreadPoolStats stats_;
  std::array<Site, kMaxSites> sites_{};
  std::size_t site_count_ = 0;
  Site* last_site_ = nullptr;  ///< the previous loop, whose run ends when the next starts
  bool last_parallel_ = false;
  double last_took_ = 0.0;  ///< the previous loop's own time [s]
  std::chrono::steady_clock::time_point last_start_{};
  std::chrono::steady_clock::time_point last_end_{};
};

}  // namespace demlink::core
