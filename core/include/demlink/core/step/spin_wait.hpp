#pragma once
/// The one spin-then-block rule of every wait that is on the critical path: the thread
/// pool's workers between loops and its caller at a join (thread_pool.cpp), the server's
/// network loop between packages (TcpServer::run) and the C++ client's receive (and the
/// C ABI built on it).
///
/// Why: a thread blocked in the kernel (futex, epoll_wait, recv) takes tens of
/// microseconds to run again after its event, more under a hypervisor, where the wake-up
/// is an inter-processor interrupt. A step of a few hundred microseconds or a loopback
/// round trip of a few microseconds is dominated by that. A waiter that polls its event
/// for a short, bounded time first continues within a microsecond when the event comes
/// soon, and gives its core away when it does not.
///
/// Why a gate: a spinning thread holds a core. It must never hold one that computing
/// work needs, or that work waits for a scheduler time slice (milliseconds). So a wait
/// spins only while the threads of this process that spin, itself included, are fewer
/// than the free CPUs: the CPUs this process may run on (sched_getaffinity) less the ones
/// other processes keep busy. "Other processes" is measured, not guessed from the load
/// average (which counts this process's own threads): the machine's busy CPU time
/// (/proc/stat) less this process's CPU time, per wall second, over the last quarter
/// second or more. At least one free CPU is thus always left to a party that computes:
/// 2 idle CPUs allow one spinner at a time, 2 CPUs with one busy process allow none.
/// Where /proc/stat cannot be read, the 1-minute load average stands in for the others.
///
/// Header-only (std and POSIX only), so the client library uses the same rule without
/// linking the DEM core; the gate and the statistics are one per process.
#include <sched.h>
#include <time.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <mutex>
#include <thread>

namespace demlink::core {

/// Spin budget of a wait when nothing else is asked for [ns]: longer than a loopback
/// round trip with a short step (~10-20 us), short next to a blocked wake-up's cost.
inline constexpr std::chrono::nanoseconds kDefaultSpinBudget{50'000};
/// Largest accepted budget [ns] (a spinning thread is bounded by it).
inline constexpr std::chrono::nanoseconds kMaxSpinBudget{10'000'000};

/// Lets a spinning hardware thread yield execution resources to its sibling.
inline void cpuRelax() {
#if defined(__x86_64__) || defined(__i386__)
  __builtin_ia32_pause();
#elif defined(__aarch64__)
  asm volatile("yield");
#endif
}

/// CPUs this process may run on (sched_getaffinity; std::thread::hardware_concurrency
/// when unknown), at least 1.
inline std::uint32_t usableCpus() {
  std::uint32_t cpus = 0;
  cpu_set_t set;
  CPU_ZERO(&set);
  if (sched_getaffinity(0, sizeof set, &set) == 0) cpus = static_cast<std::uint32_t>(CPU_COUNT(&set));
  if (cpus == 0) cpus = std::thread::hardware_concurrency();
  return std::max<std::uint32_t>(cpus, 1);
}

/// The 1-minute load average; negative when unknown.
inline double loadAverage() {
  double load = -1.0;
  std::ifstream loadavg("/proc/loadavg");
  if (!(loadavg >> load)) return -1.0;
  return load;
}

/// How the process's spin-then-block waits went (all threads, since start).
struct SpinStats {
  std::uint64_t ready_spinning = 0;  ///< waits whose event came while spinning
  std::uint64_t blocked_after_spin = 0;  ///< waits that spun their budget, then blocked
  std::uint64_t refused = 0;  ///< waits that blocked at once: no free CPU to spin on
};

/// The process-wide gate and statistics of spinning waits (see the file comment).
class SpinGate {
 public:
  static SpinGate& instance() {
    static SpinGate gate;
    return gate;
  }

  /// Takes a spinner's place when, with it, the process's spinners are fewer than the
  /// free CPUs; false (and nothing taken) otherwise.
  bool enter() {
    const int free = freeCpus();
    int now = spinners_.load(std::memory_order_relaxed);
    do {
      if (now + 1 >= free) return false;
    } while (!spinners_.compare_exchange_weak(now, now + 1, std::memory_order_relaxed));
    return true;
  }
  void leave() { spinners_.fetch_sub(1, std::memory_order_relaxed); }

  /// Usable CPUs less those busy with other processes (rounded), refreshed at most
  /// every kRefreshPeriod by whichever waiter finds it stale.
  int freeCpus() {
    const std::int64_t now = monotonicNs();
    if (now - refreshed_ns_.load(std::memory_order_relaxed) >= kRefreshPeriodNs) refresh(now);
    return free_cpus_.load(std::memory_order_relaxed);
  }

  /// CPUs other processes kept busy over the last measured period [-].
  [[nodiscard]] double othersBusy() const { return others_busy_.load(std::memory_order_relaxed); }

  [[nodiscard]] SpinStats stats() const {
    return {ready_.load(std::memory_order_relaxed), blocked_.load(std::memory_order_relaxed),
            refused_.load(std::memory_order_relaxed)};
  }
  void count(bool ready) { (ready ? ready_ : blocked_).fetch_add(1, std::memory_order_relaxed); }
  void countRefused() { refused_.fetch_add(1, std::memory_order_relaxed); }

 private:
  static constexpr std::int64_t kRefreshPeriodNs = 250'000'000;

  SpinGate() : cpus_(usableCpus()) {
    free_cpus_.store(static_cast<int>(cpus_), std::memory_order_relaxed);
    refresh(monotonicNs());
  }

  static std::int64_t monotonicNs() {
    return std::chrono::duration_cast<std::chrono::nanoseconds>(std::chrono::steady_clock::now().time_since_epoch())
        .count();
  }
  static double processCpuSeconds() {
    timespec ts{};
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
    return static_cast<double>(ts.tv_sec) + 1e-9 * static_cast<double>(ts.tv_nsec);
  }
  /// All CPUs' busy time (everything but idle and iowait) [s]; negative when unknown.
  static double systemBusySeconds() {
    std::FILE* file = std::fopen("/proc/stat", "r");
    if (file == nullptr) return -1.0;
    unsigned long long v[8] = {};
    const int got = std::fscanf(file, "cpu %llu %llu %llu %llu %llu %llu %llu %llu", &v[0], &v[1], &v[2], &v[3], &v[4],
                                &v[5], &v[6], &v[7]);
    std::fclose(file);
    if (got < 4) return -1.0;
    const double busy = static_cast<double>(v[0] + v[1] + v[2] + v[5] + v[6] + v[7]);
    static const long ticks = sysconf(_SC_CLK_TCK);
    return busy / static_cast<double>(ticks > 0 ? ticks : 100);
  }

  void refresh(std::int64_t now) {
    std::unique_lock lock(mutex_, std::try_to_lock);
    if (!lock.owns_lock()) return;
    if (now - refreshed_ns_.load(std::memory_order_relaxed) < kRefreshPeriodNs) return;
    const double busy = systemBusySeconds();
    const double own = processCpuSeconds();
    double others = 0.0;
    if (busy >= 0.0 && last_busy_ >= 0.0) {
      const double wall = 1e-9 * static_cast<double>(now - last_ns_);
      others = std::max(0.0, ((busy - last_busy_) - (own - last_own_)) / wall);
    } else if (busy < 0.0) {
      others = std::max(0.0, loadAverage());
    }
    last_busy_ = busy;
    last_own_ = own;
    last_ns_ = now;
    others_busy_.store(others, std::memory_order_relaxed);
    const double free = static_cast<double>(cpus_) - std::round(std::min(others, static_cast<double>(cpus_)));
    free_cpus_.store(static_cast<int>(free), std::memory_order_relaxed);
    refreshed_ns_.store(now, std::memory_order_relaxed);
  }

  const std::uint32_t cpus_;
  std::mutex mutex_;  ///< one refresher at a time
  double last_busy_ = -1.0;
  double last_own_ = 0.0;
  std::int64_t last_ns_ = 0;
  std::atomic<std::int64_t> refreshed_ns_{0};
  std::atomic<int> free_cpus_{1};
  std::atomic<double> others_busy_{0.0};
  std::atomic<int> spinners_{0};
  std::atomic<std::uint64_t> ready_{0};
  std::atomic<std::uint64_t> blocked_{0};
  std::atomic<std::uint64_t> refused_{0};
};

/// The spin budget a wait uses when its caller asks for none: DEMLINK_SPIN_WAIT_US from
/// the environment (microseconds; 0 turns spinning off) when set and valid, otherwise
/// kDefaultSpinBudget. Read once per process.
inline std::chrono::nanoseconds defaultSpinBudget() {
  static const std::chrono::nanoseconds budget = [] {
    const char* text = std::getenv("DEMLINK_SPIN_WAIT_US");
    if (text == nullptr || *text == '\0') return kDefaultSpinBudget;
    char* end = nullptr;
    const double us = std::strtod(text, &end);
    if (end == text || *end != '\0' || !std::isfinite(us) || us < 0.0 ||
        us * 1e3 > static_cast<double>(kMaxSpinBudget.count())) {
      return kDefaultSpinBudget;
    }
    return std::chrono::nanoseconds(static_cast<std::int64_t>(us * 1e3));
  }();
  return budget;
}

/// The spin half of spin-then-block: polls ready() for at most `budget` when the gate
/// admits a spinner. True: ready() returned true (the caller need not block). False:
/// the caller blocks in its own way (futex, epoll, recv) and re-checks its event.
template <class Ready>
bool spinFor(std::chrono::nanoseconds budget, Ready&& ready) {
  if (budget.count() <= 0) return false;
  SpinGate& gate = SpinGate::instance();
  if (!gate.enter()) {
    gate.countRefused();
    return false;
  }
  const auto deadline = std::chrono::steady_clock::now() + budget;
  bool done = false;
  for (;;) {
    if (ready()) {
      done = true;
      break;
    }
    cpuRelax();
    if (std::chrono::steady_clock::now() >= deadline) break;
  }
  gate.leave();
  gate.count(done);
  return done;
}

}  // namespace demlink::core
