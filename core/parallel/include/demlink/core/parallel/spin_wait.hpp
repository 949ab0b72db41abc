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
/// work needs, or that work waits for a scheduler time slice (milliseconds). The gate
/// counts the free CPUs: the CPUs this process may run on (sched_getaffinity) less the
/// ones other processes keep busy. "Other processes" is measured, not guessed from the
/// load average (which counts this process's own threads): the machine's busy CPU time
/// (/proc/stat) less this process's CPU time, per wall second, over the last quarter
/// second or more; before the first such period (50 ms after the gate's first use), or
/// where /proc/stat cannot be read, the 1-minute load average stands in.
/// Then:
/// - the DEM thread pool's threads spin only while all of them fit in the free CPUs
///   (2 threads: both CPUs free; beside one busy process, none spins);
/// - an exchange wait (server network loop, client receive) spins only while the
///   process's exchange spinners, itself included, plus the DEM pools' workers, stay
///   below the free CPUs: one CPU is always left to the party being waited for, and a
///   spinner never takes a core a DEM worker needs (2 free CPUs and one DEM thread: one
///   exchange spinner at a time; two DEM threads: none);
/// - and only while the process's exchange parties (live client connections, running
///   server network loops), plus the DEM pools' workers, fit in the free CPUs: with
///   more threads taking turns in the exchanges than free cores (a server and 4
///   clients on 2 CPUs), a spinner holds a core that one of them needs to run, and
///   every round trip gets longer.
/// A partner in another process that spins counts as busy there, so across processes
/// the rule errs towards blocking.
///
/// Header-only (std and POSIX, or the Win32 API in the client's win64 build, where
/// GetSystemTimes stands for /proc/stat), so the client library uses the same rule without
/// linking the DEM core; the gate and the statistics are one per process.
#if defined(_WIN32)
#include <windows.h>
#else
#include <sched.h>
#include <time.h>
#include <unistd.h>
#endif

#include <algorithm>
#include <atomic>
#include <bit>
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
#if defined(_WIN32)
  DWORD_PTR process = 0;
  DWORD_PTR system = 0;
  if (GetProcessAffinityMask(GetCurrentProcess(), &process, &system)) cpus = static_cast<std::uint32_t>(std::popcount(process));
#else
  cpu_set_t set;
  CPU_ZERO(&set);
  if (sched_getaffinity(0, sizeof set, &set) == 0) cpus = static_cast<std::uint32_t>(CPU_COUNT(&set));
#endif
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

  /// Who waits: a DEM pool thread, or an exchange (network) wait.
  enum class Party { kDem, kExchange };

  /// Takes a spinner's place when the rule of the file comment admits one more of
  /// `party`; false (and nothing taken) otherwise. Every true needs a leave(party).
  bool enter(Party party) {
    const bool forced = forced_.load(std::memory_order_relaxed);
    const int free = forced ? 0 : freeCpus();
    if (party == Party::kDem) return forced || admits(party, free, 0, dem_threads_.load(std::memory_order_relaxed), 0, 0);
    const int workers = dem_workers_.load(std::memory_order_relaxed);
    const int parties = exchange_parties_.load(std::memory_order_relaxed);
    const int loops = server_loops_.load(std::memory_order_relaxed);
    const bool partnersInside = loops > 0 && parties > loops;
    int now = spinners_.load(std::memory_order_relaxed);
    do {
      if (!forced && !admits(party, free, now, 0, workers, parties, partnersInside)) return false;
    } while (!spinners_.compare_exchange_weak(now, now + 1, std::memory_order_relaxed));
    return true;
  }

  /// The rule: may one more `party` spin, with `free` free CPUs, `spinners` exchange
  /// waits spinning already, `demThreads` threads and `demWorkers` workers in DEM pools,
  /// and `exchangeParties` exchange parties (addExchangeParty) in the process;
  /// `partnersInside`: the parties' partners are in this process too (a server loop and
  /// client connections: benchmarks, tests), so no CPU is kept for a partner elsewhere.
  [[nodiscard]] static bool admits(Party party, int free, int spinners, int demThreads, int demWorkers,
                                   int exchangeParties, bool partnersInside = false) {
    if (party == Party::kDem) return demThreads <= free;
    const int keptForPartner = partnersInside ? 0 : 1;
    return spinners + 1 + demWorkers + keptForPartner <= free && exchangeParties + demWorkers <= free;
  }
  void leave(Party party) {
    if (party == Party::kExchange) spinners_.fetch_sub(1, std::memory_order_relaxed);
  }

  /// Benchmarks only: admit every spinner, whatever the free CPUs (shows what spinning
  /// gains where the gate would refuse it, e.g. on a machine shared with other work).
  void setForced(bool forced) { forced_.store(forced, std::memory_order_relaxed); }
  /// Tests only: freeCpus() answers `free` from now on, whatever the machine does
  /// (negative: measured again).
  void pinFreeCpus(int free) { pinned_free_.store(free, std::memory_order_relaxed); }

  /// A DEM pool of `threads` threads (its caller included) starts (+) or ends (-).
  void addDemPool(int threads) {
    dem_threads_.fetch_add(threads, std::memory_order_relaxed);
    dem_workers_.fetch_add(threads > 0 ? threads - 1 : threads + 1, std::memory_order_relaxed);
  }

  /// An exchange party (a client connection, a server network loop) starts (+1) or ends (-1).
  void addExchangeParty(int parties) { exchange_parties_.fetch_add(parties, std::memory_order_relaxed); }
  /// Of those, a server network loop starts (+1) or ends (-1): with one and a client
  /// connection in the process, the exchange partners are both here (admits).
  void addServerLoop(int loops) { server_loops_.fetch_add(loops, std::memory_order_relaxed); }

  /// Usable CPUs less those busy with other processes (rounded), refreshed at most
  /// every refreshPeriodNs() by whichever waiter finds it stale.
  int freeCpus() {
    if (const int pinned = pinned_free_.load(std::memory_order_relaxed); pinned >= 0) return pinned;
    const std::int64_t now = monotonicNs();
    if (now - refreshed_ns_.load(std::memory_order_relaxed) >= refreshPeriodNs()) refresh(now);
    return free_cpus_.load(std::memory_order_relaxed);
  }
  /// How long an estimate stands [ns]: kRefreshPeriodNs once measured; while it is still the
  /// load average's, kFirstRefreshPeriodNs. Why shorter: the load average counts this
  /// process's own recent work (and that of runs just before it), so it often sees a CPU
  /// busy that is free; standing for a full period, it would keep a pool's workers asleep
  /// through a large part of a short run.
  [[nodiscard]] std::int64_t refreshPeriodNs() const { return measured() ? kRefreshPeriodNs : kFirstRefreshPeriodNs; }
  /// Whether the estimate was measured (/proc/stat), not taken from the load average.
  [[nodiscard]] bool measured() const { return measured_.load(std::memory_order_relaxed); }

  /// CPUs other processes kept busy over a period of `wallSeconds`, in which all CPUs
  /// were busy for `machineBusySeconds` (/proc/stat) and this process ran for
  /// `ownSeconds` (all its threads) [-]; at least 0.
  [[nodiscard]] static double othersBusyOver(double machineBusySeconds, double ownSeconds, double wallSeconds) {
    if (!(wallSeconds > 0.0)) return 0.0;
    return std::max(0.0, (machineBusySeconds - ownSeconds) / wallSeconds);
  }
  /// Free CPUs of `cpus` usable ones when other processes keep `othersBusy` CPUs busy
  /// (rounded to the nearest whole CPU), in [0, cpus].
  [[nodiscard]] static int freeCpusOf(std::uint32_t cpus, double othersBusy) {
    const double total = static_cast<double>(cpus);
    return static_cast<int>(total - std::round(std::clamp(othersBusy, 0.0, total)));
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
  /// The first measurement's period: /proc/stat counts in 10 ms ticks, so 50 ms on 2 CPUs
  /// resolves a busy CPU to about a fifth.
  static constexpr std::int64_t kFirstRefreshPeriodNs = 50'000'000;

  SpinGate() : cpus_(usableCpus()) {
    free_cpus_.store(static_cast<int>(cpus_), std::memory_order_relaxed);
    refresh(monotonicNs());
  }

  static std::int64_t monotonicNs() {
    return std::chrono::duration_cast<std::chrono::nanoseconds>(std::chrono::steady_clock::now().time_since_epoch())
        .count();
  }
#if defined(_WIN32)
  /// A FILETIME duration (100 ns units) [s].
  static double seconds(const FILETIME& time) {
    return 1e-7 * static_cast<double>((static_cast<std::uint64_t>(time.dwHighDateTime) << 32) | time.dwLowDateTime);
  }
  static double processCpuSeconds() {
    FILETIME created{}, exited{}, kernel{}, user{};
    if (!GetProcessTimes(GetCurrentProcess(), &created, &exited, &kernel, &user)) return 0.0;
    return seconds(kernel) + seconds(user);
  }
  /// All CPUs' busy time [s] (kernel time includes idle time); negative when unknown.
  static double systemBusySeconds() {
    FILETIME idle{}, kernel{}, user{};
    if (!GetSystemTimes(&idle, &kernel, &user)) return -1.0;
    return seconds(kernel) + seconds(user) - seconds(idle);
  }
#else
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
#endif

  void refresh(std::int64_t now) {
    std::unique_lock lock(mutex_, std::try_to_lock);
    if (!lock.owns_lock()) return;
    if (now - refreshed_ns_.load(std::memory_order_relaxed) < refreshPeriodNs()) return;
    const double busy = systemBusySeconds();
    const double own = processCpuSeconds();
    double others = 0.0;
    if (busy >= 0.0 && last_busy_ >= 0.0) {
      others = othersBusyOver(busy - last_busy_, own - last_own_, 1e-9 * static_cast<double>(now - last_ns_));
      measured_.store(true, std::memory_order_relaxed);
    } else {
      // No earlier sample (the first call) or no /proc/stat: the load average, which at a
      // process's start holds little of its own work.
      others = std::max(0.0, loadAverage());
    }
    last_busy_ = busy;
    last_own_ = own;
    last_ns_ = now;
    others_busy_.store(others, std::memory_order_relaxed);
    free_cpus_.store(freeCpusOf(cpus_, others), std::memory_order_relaxed);
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
  std::atomic<bool> measured_{false};  ///< the estimate came from /proc/stat, not the load average
  std::atomic<bool> forced_{false};
  std::atomic<int> pinned_free_{-1};  ///< pinFreeCpus
  std::atomic<int> spinners_{0};     ///< exchange waits spinning now
  std::atomic<int> exchange_parties_{0};  ///< live client connections and server loops
  std::atomic<int> server_loops_{0};      ///< running server network loops (also parties)
  std::atomic<int> dem_threads_{0};  ///< threads of the live DEM pools
  std::atomic<int> dem_workers_{0};  ///< the same less each pool's caller
  std::atomic<std::uint64_t> ready_{0};
  std::atomic<std::uint64_t> blocked_{0};
  std::atomic<std::uint64_t> refused_{0};
};

namespace spin_detail {
/// The process's default budget [ns]: DEMLINK_SPIN_WAIT_US when set and valid (0..10000
/// microseconds), otherwise kDefaultSpinBudget; setDefaultSpinBudget() replaces it.
inline std::atomic<std::int64_t>& defaultBudgetNs() {
  static std::atomic<std::int64_t> budget = [] {
    const char* text = std::getenv("DEMLINK_SPIN_WAIT_US");
    std::int64_t ns = kDefaultSpinBudget.count();
    if (text != nullptr && *text != '\0') {
      char* end = nullptr;
      const double us = std::strtod(text, &end);
      if (end != text && *end == '\0' && std::isfinite(us) && us >= 0.0 &&
          us * 1e3 <= static_cast<double>(kMaxSpinBudget.count())) {
        ns = static_cast<std::int64_t>(us * 1e3);
      }
    }
    return ns;
  }();
  return budget;
}
}  // namespace spin_detail

/// The spin budget of waits whose owner was given none: the DEM thread pool's, the
/// server's network loop's (demlink-server --spin-wait-us sets it), the client's
/// (ConnectOptions::spin_wait unset, and so the C ABI's). DEMLINK_SPIN_WAIT_US in the
/// environment (microseconds, 0 = off) replaces kDefaultSpinBudget.
inline std::chrono::nanoseconds defaultSpinBudget() {
  return std::chrono::nanoseconds(spin_detail::defaultBudgetNs().load(std::memory_order_relaxed));
}
/// Sets defaultSpinBudget() for waits created from now on (clamped to [0, kMaxSpinBudget]).
inline void setDefaultSpinBudget(std::chrono::nanoseconds budget) {
  spin_detail::defaultBudgetNs().store(std::clamp(budget, std::chrono::nanoseconds::zero(), kMaxSpinBudget).count(),
                                       std::memory_order_relaxed);
}

/// The spin half of spin-then-block: polls ready() for at most `budget` when the gate
/// admits a spinner of `party`. True: ready() returned true (the caller need not block). False:
/// the caller blocks in its own way (futex, epoll, recv) and re-checks its event.
template <class Ready>
bool spinFor(SpinGate::Party party, std::chrono::nanoseconds budget, Ready&& ready) {
  if (budget.count() <= 0) return false;
  SpinGate& gate = SpinGate::instance();
  if (!gate.enter(party)) {
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
  gate.leave(party);
  gate.count(done);
  return done;
}

}  // namespace demlink::core
