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
/// Determinism: run(parts, body) always cuts the work into the same parts, and
/// part k always runs on thread k % size(); what a part computes never depends
/// on timing.
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

class ThreadPool {
 public:
  /// A pool of `threads` threads in total: the calling thread plus threads-1 workers.
  /// Throws ThreadStartError (after joining the workers it started) when one cannot start.
  explicit ThreadPool(std::uint32_t threads);
  ~ThreadPool();
  ThreadPool(const ThreadPool&) = delete;
  ThreadPool& operator=(const ThreadPool&) = delete;

  [[nodiscard]] std::uint32_t size() const { return static_cast<std::uint32_t>(workers_.size()) + 1; }

  /// Runs body(part) for every part in [0, parts); part k on thread k % size().
  /// Returns when all parts are done. Not reentrant.
  template <class Body>
  void run(std::uint32_t parts, const Body& body) {
    if (workers_.empty() || parts <= 1) {
      for (std::uint32_t part = 0; part < parts; ++part) body(part);
      return;
    }
    dispatch(parts, [](const void* context, std::uint32_t part) { (*static_cast<const Body*>(context))(part); },
             &body);
  }

 private:
  using Task = void (*)(const void* context, std::uint32_t part);

  void dispatch(std::uint32_t parts, Task task, const void* context);
  void stopWorkers();
  void workerLoop(std::uint32_t thread);
  void runShare(std::uint32_t thread) const;

  std::vector<std::thread> workers_;
  std::atomic<std::uint64_t> generation_{0};
  std::atomic<std::uint32_t> busy_{0};
  std::atomic<bool> stop_{false};
  Task task_ = nullptr;
  const void* context_ = nullptr;
  std::uint32_t parts_ = 0;
};

}  // namespace demlink::core
