#include "demlink/core/step/thread_pool.hpp"

#include <string>
#include <system_error>

namespace demlink::core {
namespace {

/// Spin iterations before sleeping: a few microseconds, long enough for the
/// partner's next hand-over when both cores are ours, short enough to yield the
/// core quickly when they are not.
constexpr int kSpinIterations = 4000;

inline void cpuRelax() {
#if defined(__x86_64__) || defined(__i386__)
  __builtin_ia32_pause();
#endif
}

/// Waits until `value` differs from `old`: spin briefly, then sleep on it.
template <class T>
T awaitChange(const std::atomic<T>& value, T old) {
  for (int i = 0; i < kSpinIterations; ++i) {
    const T now = value.load(std::memory_order_acquire);
    if (now != old) return now;
    cpuRelax();
  }
  for (;;) {
    value.wait(old, std::memory_order_acquire);
    const T now = value.load(std::memory_order_acquire);
    if (now != old) return now;
  }
}

}  // namespace

ThreadPool::ThreadPool(std::uint32_t threads) {
  workers_.reserve(threads > 0 ? threads - 1 : 0);
  try {
    for (std::uint32_t t = 1; t < threads; ++t) workers_.emplace_back([this, t] { workerLoop(t); });
  } catch (const std::system_error& error) {
    // A destroyed joinable std::thread calls std::terminate: join the started ones first.
    stopWorkers();
    throw ThreadStartError(static_cast<std::uint32_t>(workers_.size()) + 1, threads, error.what());
  }
}

ThreadPool::~ThreadPool() { stopWorkers(); }

void ThreadPool::stopWorkers() {
  stop_.store(true, std::memory_order_relaxed);
  generation_.fetch_add(1, std::memory_order_release);
  generation_.notify_all();
  for (std::thread& worker : workers_) worker.join();
  workers_.clear();
}

ThreadStartError::ThreadStartError(std::uint32_t started, std::uint32_t requested, const std::string& cause)
    : std::runtime_error("could start only " + std::to_string(started) + " of " + std::to_string(requested) +
                         " threads: " + cause),
      started_(started) {}

void ThreadPool::runShare(std::uint32_t thread) const {
  for (std::uint32_t part = thread; part < parts_; part += size()) task_(context_, part);
}

void ThreadPool::dispatch(std::uint32_t parts, Task task, const void* context) {
  task_ = task;
  context_ = context;
  parts_ = parts;
  busy_.store(static_cast<std::uint32_t>(workers_.size()), std::memory_order_relaxed);
  generation_.fetch_add(1, std::memory_order_release);  // publishes task_, context_, parts_
  generation_.notify_all();
  runShare(0);
  for (std::uint32_t left = busy_.load(std::memory_order_acquire); left != 0;) left = awaitChange(busy_, left);
}

void ThreadPool::workerLoop(std::uint32_t thread) {
  std::uint64_t seen = 0;
  for (;;) {
    seen = awaitChange(generation_, seen);
    if (stop_.load(std::memory_order_relaxed)) return;
    runShare(thread);
    if (busy_.fetch_sub(1, std::memory_order_acq_rel) == 1) busy_.notify_one();
  }
}

}  // namespace demlink::core
