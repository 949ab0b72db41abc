#include "demlink/core/parallel/thread_pool.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <system_error>

namespace demlink::core {
namespace {

/// Waits until `value` differs from `old`: spin within the budget, then sleep on it.
/// `asleep`, when given, counts the thread while it sleeps.
template <class T>
T awaitChange(const std::atomic<T>& value, T old, std::chrono::nanoseconds budget,
              std::atomic<std::uint32_t>* asleep = nullptr) {
  T now = old;
  if (spinFor(SpinGate::Party::kDem, budget, [&] { return (now = value.load(std::memory_order_acquire)) != old; })) return now;
  if (asleep != nullptr) asleep->fetch_add(1, std::memory_order_relaxed);
  for (;;) {
    value.wait(old, std::memory_order_acquire);
    now = value.load(std::memory_order_acquire);
    if (now != old) break;
  }
  if (asleep != nullptr) asleep->fetch_sub(1, std::memory_order_relaxed);
  return now;
}

/// A home range's word: generation (32 bits) | front (16) | back (16); chunks [front, back)
/// are unclaimed.
constexpr std::uint64_t packRange(std::uint32_t generation, std::uint32_t front, std::uint32_t back) {
  return (static_cast<std::uint64_t>(generation) << 32) | (static_cast<std::uint64_t>(front) << 16) | back;
}
constexpr std::uint32_t rangeGeneration(std::uint64_t word) { return static_cast<std::uint32_t>(word >> 32); }
constexpr std::uint32_t rangeFront(std::uint64_t word) { return static_cast<std::uint32_t>(word >> 16) & 0xFFFF; }
constexpr std::uint32_t rangeBack(std::uint64_t word) { return static_cast<std::uint32_t>(word) & 0xFFFF; }

/// Claims the first (owner) or last (thief) unclaimed chunk of `range` in loop `generation`.
bool claim(std::atomic<std::uint64_t>& range, std::uint32_t generation, bool fromFront, std::uint32_t& chunk) {
  std::uint64_t word = range.load(std::memory_order_acquire);
  for (;;) {
    // A range of another loop (a worker that woke late) or an empty one has nothing for us.
    if (rangeGeneration(word) != generation) return false;
    const std::uint32_t front = rangeFront(word);
    const std::uint32_t back = rangeBack(word);
    if (front >= back) return false;
    const std::uint64_t claimed = fromFront ? packRange(generation, front + 1, back) : packRange(generation, front, back - 1);
    if (range.compare_exchange_weak(word, claimed, std::memory_order_acq_rel, std::memory_order_acquire)) {
      chunk = fromFront ? front : back - 1;
      return true;
    }
  }
}

}  // namespace

ThreadPool::ThreadPool(std::uint32_t threads, std::chrono::nanoseconds spinBudget)
    : ranges_(std::max<std::uint32_t>(threads, 1)),
      spin_budget_(std::clamp(spinBudget, std::chrono::nanoseconds::zero(), kMaxSpinBudget)) {
  workers_.reserve(threads > 0 ? threads - 1 : 0);
  try {
    for (std::uint32_t t = 1; t < threads; ++t) workers_.emplace_back([this, t] { workerLoop(t); });
    SpinGate::instance().addDemPool(static_cast<int>(size()));
    in_gate_ = true;
  } catch (const std::system_error& error) {
    // A destroyed joinable std::thread calls std::terminate: join the started ones first.
    stopWorkers();
    throw ThreadStartError(static_cast<std::uint32_t>(workers_.size()) + 1, threads, error.what());
  }
}

ThreadPool::~ThreadPool() { stopWorkers(); }

void ThreadPool::stopWorkers() {
  if (in_gate_) SpinGate::instance().addDemPool(-static_cast<int>(size()));
  in_gate_ = false;
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

std::uint32_t ThreadPool::drain(std::uint32_t self, std::uint32_t generation) {
  const auto threads = static_cast<std::uint32_t>(ranges_.size());
  std::uint32_t ran = 0;
  std::uint32_t chunk = 0;
  // The loop's size, read while this thread holds an unfinished chunk of it: once its
  // done_ count completes the loop, the caller may already be setting up the next one.
  std::uint32_t chunks = 0;
  // The home range first, front to back: a thread keeps the same chunks (and so the same
  // particles in its cache) from loop to loop; then the others' ranges from their backs.
  for (std::uint32_t k = 0; k < threads; ++k) {
    std::atomic<std::uint64_t>& range = ranges_[(self + k) % threads].word;
    while (claim(range, generation, k == 0, chunk)) {
      if (ran == 0) chunks = chunks_;
      task_(context_, chunk);
      ++ran;
    }
  }
  if (ran > 0 && done_.fetch_add(ran, std::memory_order_acq_rel) + ran == chunks) done_.notify_one();
  return ran;
}

ThreadPool::Site& ThreadPool::siteOf(Task task) {
  for (std::size_t i = 0; i < site_count_; ++i) {
    if (sites_[i].task == task) return sites_[i];
  }
  if (site_count_ < kMaxSites) {
    sites_[site_count_].task = task;
    return sites_[site_count_++];
  }
  return sites_[kMaxSites - 1];
}

void ThreadPool::dispatch(std::uint32_t chunks, Task task, const void* context) {
  if (chunks > kMaxChunks) throw std::length_error("ThreadPool::run: more than 65535 chunks");
  using Clock = std::chrono::steady_clock;
  Site& site = siteOf(task);
  const bool allAsleep = asleep_.load(std::memory_order_relaxed) == workers_.size();
  const Clock::time_point start = Clock::now();
  std::uint32_t callerChunks = chunks;
  // The gate is asked only when the answer matters (it may read /proc/stat every 250 ms).
  const bool coresFree = allAsleep && site.work_seconds >= 0.0 && site.work_seconds < kWakeWorthBusySeconds &&
                         SpinGate::instance().freeCpus() >= static_cast<int>(size());
  if (offersToWorkers(chunks, !allAsleep, site.work_seconds, coresFree)) {
    ++stats_.parallel_runs;
    if (allAsleep) ++stats_.woken_runs;
    callerChunks = runParallel(chunks, task, context);
    stats_.caller_chunks += callerChunks;
    stats_.worker_chunks += chunks - callerChunks;
  } else {
    ++stats_.serial_runs;
    for (std::uint32_t chunk = 0; chunk < chunks; ++chunk) task(context, chunk);
  }
  // The caller's time stands for the whole loop's work in the share of chunks it ran
  // (a worker that ran the others worked about as long).
  const double took = std::chrono::duration<double>(Clock::now() - start).count();
  site.work_seconds = took * chunks / std::max<std::uint32_t>(callerChunks, 1);
}

std::uint32_t ThreadPool::runParallel(std::uint32_t chunks, Task task, const void* context) {
  task_ = task;
  context_ = context;
  chunks_ = chunks;
  done_.store(0, std::memory_order_relaxed);
  const std::uint32_t generation = generation_.load(std::memory_order_relaxed) + 1;
  const auto threads = static_cast<std::uint64_t>(ranges_.size());
  for (std::uint64_t t = 0; t < threads; ++t) {
    // Home ranges by thread index: contiguous, depending only on chunks and the pool's size.
    ranges_[t].word.store(packRange(generation, static_cast<std::uint32_t>(chunks * t / threads),
                                    static_cast<std::uint32_t>(chunks * (t + 1) / threads)),
                          std::memory_order_release);  // publishes task_, context_, chunks_
  }
  generation_.store(generation, std::memory_order_release);
  generation_.notify_all();
  const std::uint32_t ran = drain(0, generation);
  for (std::uint32_t done = done_.load(std::memory_order_acquire); done != chunks;) {
    done = awaitChange(done_, done, spin_budget_);
  }
  return ran;
}

std::chrono::nanoseconds defaultPoolSpinBudget() {
  constexpr std::chrono::nanoseconds kPoolSpinBudget{200'000};
  const char* text = std::getenv("DEMLINK_SPIN_WAIT_US");
  return text != nullptr && *text != '\0' ? defaultSpinBudget() : kPoolSpinBudget;
}

AutoThreadChoice chooseAutoThreads() {
  const std::uint32_t cpus = usableCpus();
  const double load = loadAverage();
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

void ThreadPool::workerLoop(std::uint32_t self) {
  std::uint32_t seen = 0;
  for (;;) {
    seen = awaitChange(generation_, seen, spin_budget_, &asleep_);
    if (stop_.load(std::memory_order_relaxed)) return;
    drain(self, seen);
  }
}

}  // namespace demlink::core
