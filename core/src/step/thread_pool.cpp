#include "demlink/core/step/thread_pool.hpp"

#include <sched.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <string>
#include <system_error>

namespace demlink::core {
namespace {

/// Spin iterations before sleeping: a few microseconds, long enough for the
/// partner's next hand-over when both cores are ours, short enough to yield the
/// core quickly when they are not.
constexpr int kSpinIterations = 4000;

/// Offered loops per judgement of whether threading pays [-].
constexpr std::uint32_t kWindowRuns = 32;
/// Threading pays when a window takes at most this fraction of its serial estimate [-].
constexpr double kPayingFraction = 0.9;
/// A window that has lost this much against its serial estimate ends at once [s]: one
/// descheduled worker costs a scheduler slice (~1-4 ms), so a probe on a loaded machine
/// costs about that, once per back-off period.
constexpr double kProbeLossLimit = 2.0e-3;
/// Serial loops after the first failed window, and their cap as failures repeat [-].
constexpr std::uint32_t kFirstBackoff = 64;
constexpr std::uint32_t kMaxBackoff = 1u << 16;

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

constexpr std::uint64_t packTicket(std::uint32_t generation, std::uint32_t chunks, std::uint32_t next) {
  return (static_cast<std::uint64_t>(generation) << 32) | (static_cast<std::uint64_t>(chunks) << 16) | next;
}
constexpr std::uint32_t ticketChunks(std::uint64_t ticket) { return static_cast<std::uint32_t>(ticket >> 16) & 0xFFFF; }
constexpr std::uint32_t ticketNext(std::uint64_t ticket) { return static_cast<std::uint32_t>(ticket) & 0xFFFF; }

double secondsSince(std::chrono::steady_clock::time_point start, std::chrono::steady_clock::time_point end) {
  return std::chrono::duration<double>(end - start).count();
}

}  // namespace

ThreadPool::ThreadPool(std::uint32_t threads) {
  workers_.reserve(threads > 0 ? threads - 1 : 0);
  try {
    for (std::uint32_t t = 1; t < threads; ++t) workers_.emplace_back([this] { workerLoop(); });
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

std::uint32_t ThreadPool::drain() {
  std::uint32_t ran = 0;
  std::uint64_t ticket = ticket_.load(std::memory_order_acquire);
  for (;;) {
    // The ticket carries its generation and chunk count: a claim on a finished loop's
    // ticket fails, because the caller replaces the ticket before it changes the task.
    if (ticketNext(ticket) >= ticketChunks(ticket)) return ran;
    if (!ticket_.compare_exchange_weak(ticket, ticket + 1, std::memory_order_acq_rel, std::memory_order_acquire)) {
      continue;
    }
    const std::uint32_t chunk = ticketNext(ticket);
    const std::uint32_t chunks = ticketChunks(ticket);
    task_(context_, chunk);
    ++ran;
    if (done_.fetch_add(1, std::memory_order_acq_rel) + 1 == chunks) done_.notify_one();
    ticket = ticket_.load(std::memory_order_acquire);
  }
}

void ThreadPool::dispatch(std::uint32_t chunks, Task task, const void* context) {
  if (chunks > kMaxChunks) throw std::length_error("ThreadPool::run: more than 65535 chunks");
  if (serial_left_ > 0) {
    --serial_left_;
    ++stats_.serial_runs;
    for (std::uint32_t chunk = 0; chunk < chunks; ++chunk) task(context, chunk);
    return;
  }
  ++stats_.parallel_runs;
  using Clock = std::chrono::steady_clock;
  const Clock::time_point start = Clock::now();
  task_ = task;
  context_ = context;
  done_.store(0, std::memory_order_relaxed);
  const std::uint32_t generation = generation_.load(std::memory_order_relaxed) + 1;
  ticket_.store(packTicket(generation, chunks, 0), std::memory_order_release);  // publishes task_, context_
  generation_.store(generation, std::memory_order_release);
  generation_.notify_all();
  const std::uint32_t mine = drain();
  const Clock::time_point drained = Clock::now();
  for (std::uint32_t done = done_.load(std::memory_order_acquire); done != chunks;) done = awaitChange(done_, done);
  const Clock::time_point end = Clock::now();
  const double took = secondsSince(start, end);
  // The caller's own chunk rate extrapolated to all chunks; without a chunk of its own
  // there is no estimate, and the loop counts as neither gain nor loss.
  const double serialEstimate = mine > 0 ? secondsSince(start, drained) * chunks / mine : took;
  judge(serialEstimate, took);
}

void ThreadPool::judge(double serialEstimate, double took) {
  window_serial_ += serialEstimate;
  window_took_ += took;
  ++window_runs_;
  const bool lostTooMuch = window_took_ - window_serial_ > kProbeLossLimit;
  if (window_runs_ < kWindowRuns && !lostTooMuch) return;
  if (!lostTooMuch && window_took_ <= kPayingFraction * window_serial_) {
    backoff_ = kFirstBackoff;
  } else {
    serial_left_ = std::max(backoff_, kFirstBackoff);
    backoff_ = std::min(2 * serial_left_, kMaxBackoff);
    ++stats_.fallbacks;
  }
  window_runs_ = 0;
  window_serial_ = 0.0;
  window_took_ = 0.0;
}

AutoThreadChoice chooseAutoThreads() {
  std::uint32_t cpus = 0;
  cpu_set_t set;
  CPU_ZERO(&set);
  if (sched_getaffinity(0, sizeof set, &set) == 0) cpus = static_cast<std::uint32_t>(CPU_COUNT(&set));
  if (cpus == 0) cpus = std::thread::hardware_concurrency();
  if (cpus == 0) cpus = 1;
  double load = -1.0;
  std::ifstream loadavg("/proc/loadavg");
  if (!(loadavg >> load)) load = -1.0;
  const double busy = load > 0.0 ? std::round(load) : 0.0;
  const auto threads = static_cast<std::uint32_t>(std::clamp(static_cast<double>(cpus) - busy, 1.0,
                                                             static_cast<double>(cpus)));
  char reason[160];
  if (load >= 0.0) {
    std::snprintf(reason, sizeof reason, "auto: %u CPU(s) usable, load average %.2f -> %u thread(s)", cpus, load,
                  threads);
  } else {
    std::snprintf(reason, sizeof reason, "auto: %u CPU(s) usable, load unknown -> %u thread(s)", cpus, threads);
  }
  return {threads, reason};
}

void ThreadPool::workerLoop() {
  std::uint32_t seen = 0;
  for (;;) {
    seen = awaitChange(generation_, seen);
    if (stop_.load(std::memory_order_relaxed)) return;
    drain();
  }
}

}  // namespace demlink::core
