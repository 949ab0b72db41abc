#pragma once
/// A small persistent thread pool for the step's parallel loops.
///
/// Why not OpenMP fork/join: a step runs ~5 parallel loops of 0.1-3 ms. libgomp's
/// waiting threads spin for a long time; when another process holds the second
/// core, the spinning thread keeps the core its partner needs, and each join can
/// cost a whole scheduler time slice: a 2-thread run became ~470x slower beside
/// two busy processes (docs/benchmarks.md). Here a waiting thread spins for a few
/// microseconds (cheap hand-over when cores are free), then sleeps on a futex via
/// C++20 std::atomic::wait, giving the core away.
///
/// Work claiming: run(chunks, body) publishes the chunks; the caller and every
/// awake worker claim the next unclaimed chunk through one atomic ticket until none
/// is left, so a descheduled or slow thread only holds up the chunk it is running,
/// never a fixed share of the work.
///
/// Graceful degradation: a thread that is descheduled in the middle of a chunk
/// still makes the caller wait for a scheduler time slice. The pool therefore
/// measures what threading buys: from the caller's own chunk rate it estimates how
/// long the loop would have taken serially and compares with how long it took.
/// When a window of loops gains too little (another process holds the cores), the
/// pool runs the next loops on the caller alone, then probes again, backing off
/// exponentially while probes keep failing. Callers make their results independent
/// of which thread ran which chunk (parallel.hpp), so this decision never changes a
/// result.
#include <atomic>
#include <cstdint>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

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
  std::uint64_t serial_runs = 0;    ///< loops the caller ran alone because threading did not pay
  std::uint64_t fallbacks = 0;      ///< times the pool switched to the caller alone
};

class ThreadPool {
 public:
  /// Most chunks of one run() [-] (the ticket packs the chunk index in 16 bits).
  static constexpr std::uint32_t kMaxChunks = 0xFFFF;

  /// A pool of `threads` threads in total: the calling thread plus threads-1 workers.
  /// Throws ThreadStartError (after joining the workers it started) when one cannot start.
  explicit ThreadPool(std::uint32_t threads);
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

  void dispatch(std::uint32_t chunks, Task task, const void* context);
  /// Claims and runs chunks of the current ticket until none is left; returns how many it ran.
  std::uint32_t drain();
  void stopWorkers();
  void workerLoop();
  /// Records one offered loop: `serialEstimate` and `took` in seconds.
  void judge(double serialEstimate, double took);

  std::vector<std::thread> workers_;
  /// generation (32 bits) | chunks (16) | next unclaimed chunk (16).
  std::atomic<std::uint64_t> ticket_{0};
  std::atomic<std::uint32_t> generation_{0};  ///< bumped per offered loop; workers sleep on it
  std::atomic<std::uint32_t> done_{0};        ///< chunks finished in the current loop
  std::atomic<bool> stop_{false};
  Task task_ = nullptr;
  const void* context_ = nullptr;

  // Adaptive threading (caller thread only).
  ThreadPoolStats stats_;
  std::uint32_t serial_left_ = 0;    ///< loops still to run on the caller alone
  std::uint32_t backoff_ = 0;        ///< serial loops after the next failed window
  std::uint32_t window_runs_ = 0;    ///< offered loops in the current window
  double window_serial_ = 0.0;       ///< estimated serial time of the window [s]
  double window_took_ = 0.0;         ///< measured time of the window [s]
};

}  // namespace demlink::core
