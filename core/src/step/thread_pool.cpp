#include "demlink/core/step/thread_pool.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <string>
#include <system_error>

namespace demlink::core {
namespace {

/// Runs of each kind (threaded, caller alone) in one probe of a loop [-].
constexpr std::uint32_t kProbeRunsEach = 8;
/// Threads are kept for a loop when its threaded runs took at most this fraction of its
/// serial runs [-]: a margin against timing noise, so a loop that gains nothing measurable
/// stays on one thread (fewer cores used for the same time).
constexpr double kPayingFraction = 0.95;
/// Threaded time beyond the serial estimate after which a probe or a hold ends at once
/// [s]: one descheduled worker costs a scheduler slice (~1-4 ms), so on a loaded machine a
/// probe costs about that, once per hold.
constexpr double kLossLimit = 2.0e-3;
/// The gap after a loop, until the next loop starts, that counts towards the loop's run
/// [s]: the serial code there pays for results left in another core's cache, but a long
/// gap (output, a co-simulation exchange) is no effect of the loop and would only add noise.
constexpr double kMaxGap = 1.0e-3;
/// Runs of the first hold after a probe, and the cap as verdicts repeat [-].
constexpr std::uint32_t kFirstHold = 64;
constexpr std::uint32_t kMaxHold = 1u << 16;

/// Waits until `value` differs from `old`: spin within the budget, then sleep on it.
template <class T>
T awaitChange(const std::atomic<T>& value, T old, std::chrono::nanoseconds budget) {
  T now = old;
  if (spinFor(SpinGate::Party::kDem, budget, [&] { return (now = value.load(std::memory_order_acquire)) != old; })) return now;
  for (;;) {
    value.wait(old, std::memory_order_acquire);
    now = value.load(std::memory_order_acquire);
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

ThreadPool::ThreadPool(std::uint32_t threads, std::chrono::nanoseconds spinBudget)
    : spin_budget_(std::clamp(spinBudget, std::chrono::nanoseconds::zero(), kMaxSpinBudget)) {
  workers_.reserve(threads > 0 ? threads - 1 : 0);
  try {
    for (std::uint32_t t = 1; t < threads; ++t) workers_.emplace_back([this] { workerLoop(); });
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
  const Clock::time_point start = Clock::now();
  if (last_site_ != nullptr) {
    const double gap = std::min(secondsSince(last_end_, start), kMaxGap);
    judge(*last_site_, last_parallel_, last_took_ + gap);
  }
  Site& site = siteOf(task);
  // While probing, threaded and serial runs alternate, threaded first.
  const bool parallel = site.hold_left > 0 ? site.parallel : site.probe_runs % 2 == 0;
  if (parallel) {
    ++stats_.parallel_runs;
    runParallel(chunks, task, context);
  } else {
    ++stats_.serial_runs;
    for (std::uint32_t chunk = 0; chunk < chunks; ++chunk) task(context, chunk);
  }
  last_end_ = Clock::now();
  last_site_ = &site;
  last_parallel_ = parallel;
  last_took_ = secondsSince(start, last_end_);
}

void ThreadPool::runParallel(std::uint32_t chunks, Task task, const void* context) {
  task_ = task;
  context_ = context;
  done_.store(0, std::memory_order_relaxed);
  const std::uint32_t generation = generation_.load(std::memory_order_relaxed) + 1;
  ticket_.store(packTicket(generation, chunks, 0), std::memory_order_release);  // publishes task_, context_
  generation_.store(generation, std::memory_order_release);
  generation_.notify_all();
  drain();
  for (std::uint32_t done = done_.load(std::memory_order_acquire); done != chunks;) {
    done = awaitChange(done_, done, spin_budget_);
  }
}

void ThreadPool::judge(Site& site, bool parallel, double seconds) {
  if (site.hold_left > 0) {
    --site.hold_left;
    if (parallel) {
      // A threaded loop that starts losing against its serial time goes to the caller:
      // the loss is summed with its gains, floored at zero (a CUSUM), so timing noise
      // around a real gain does not add up, and a gain banked earlier does not hide a
      // core that another process has taken since.
      site.loss = std::max(0.0, site.loss + seconds - site.serial_mean);
      if (site.loss > kLossLimit) {
        site.parallel = false;
        site.hold = kFirstHold;
        site.hold_left = kFirstHold;
        site.loss = 0.0;
        ++stats_.fallbacks;
      }
    }
    return;
  }
  (parallel ? site.probe_parallel : site.probe_serial) += seconds;
  ++site.probe_runs;
  const std::uint32_t each = site.probe_runs / 2;
  // Compared over equal numbers of runs: after each serial run.
  const bool lostTooMuch = !parallel && site.probe_parallel - site.probe_serial > kLossLimit;
  if (!lostTooMuch && site.probe_runs < 2 * kProbeRunsEach) return;
  ++stats_.probes;
  const bool pays = !lostTooMuch && site.probe_parallel <= kPayingFraction * site.probe_serial;
  site.hold = pays == site.parallel && site.hold > 0 ? std::min(2 * site.hold, kMaxHold) : kFirstHold;
  if (!pays && site.parallel) ++stats_.fallbacks;
  site.parallel = pays;
  site.hold_left = site.hold;
  site.serial_mean = site.probe_serial / std::max<std::uint32_t>(each, 1);
  site.loss = 0.0;
  site.probe_runs = 0;
  site.probe_serial = 0.0;
  site.probe_parallel = 0.0;
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

void ThreadPool::workerLoop() {
  std::uint32_t seen = 0;
  for (;;) {
    seen = awaitChange(generation_, seen, spin_budget_);
    if (stop_.load(std::memory_order_relaxed)) return;
    drain();
  }
}

}  // namespace demlink::core
