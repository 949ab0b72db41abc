/// demlink-bench-host: what this machine gives a second thread, measured on the kinds of
/// work a DEM step is made of. The thread targets (two threads >= 1.8x one on two idle
/// cores) assume a second core that doubles every kind of work; a virtual machine's two
/// CPUs may not (docs/benchmarks.md, "Threads, size distributions, memory").
///
/// For one and for two threads (each pinned to its own CPU when the process may use two),
/// each thread working on its own data, it reports every thread's throughput and the
/// speed-up of the pair (both threads' work over one thread's, per second):
///   compute   independent multiply-adds in registers (the pair kernel's arithmetic);
///   stream    a kick-like pass (reads three arrays, adds, writes two back) over a working
///             set per thread of 32 KiB (L1), 256 KiB and 768 KiB (L2), 4 MiB (L3) and
///             64 MiB (main memory);
///   hand-over the round trip of one cache line written in turn by the two threads (what
///             each parallel loop's start and join cost at least).
/// Usage: demlink-bench-host [--seconds S]   (S: time per measurement, default 0.2)
#include <pthread.h>
#include <sched.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <functional>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include "demlink/cli/command_line.hpp"

namespace {

using Clock = std::chrono::steady_clock;

/// The CPUs this process may run on, in order.
std::vector<int> allowedCpus() {
  std::vector<int> cpus;
  cpu_set_t set;
  CPU_ZERO(&set);
  if (sched_getaffinity(0, sizeof set, &set) == 0) {
    for (int c = 0; c < CPU_SETSIZE; ++c) {
      if (CPU_ISSET(c, &set)) cpus.push_back(c);
    }
  }
  return cpus;
}

void pinTo(int cpu) {
  if (cpu < 0) return;
  cpu_set_t set;
  CPU_ZERO(&set);
  CPU_SET(cpu, &set);
  pthread_setaffinity_np(pthread_self(), sizeof set, &set);
}

/// Keeps a result alive so the compiler cannot drop the work.
std::atomic<double> g_sink{0.0};

/// Runs work(rounds) on `threads` threads at once (each pinned to its own CPU, each timing
/// itself after a first round that touches its data and a start together); returns each
/// thread's work units per second.
std::vector<double> ratePerThread(int threads, const std::vector<int>& cpus, double seconds,
                                  const std::function<double(long)>& work, double unitsPerRound) {
  // Rounds for `seconds` on one thread, from a short calibration.
  long rounds = 1;
  for (;;) {
    const auto start = Clock::now();
    g_sink = g_sink + work(rounds);
    const double took = std::chrono::duration<double>(Clock::now() - start).count();
    if (took > 0.02) {
      rounds = std::max<long>(1, static_cast<long>(static_cast<double>(rounds) * seconds / took));
      break;
    }
    rounds *= 2;
  }
  std::vector<double> rate(threads, 0.0);
  std::atomic<int> ready{0};
  std::vector<std::thread> pool;
  for (int t = 0; t < threads; ++t) {
    pool.emplace_back([&, t] {
      pinTo(t < static_cast<int>(cpus.size()) ? cpus[t] : -1);
      g_sink = g_sink + work(1);  // first touch of this thread's data
      ready.fetch_add(1);
      while (ready.load() < threads) {
      }
      const auto start = Clock::now();
      g_sink = g_sink + work(rounds);
      const double took = std::chrono::duration<double>(Clock::now() - start).count();
      rate[t] = unitsPerRound * static_cast<double>(rounds) / took;
    });
  }
  for (std::thread& thread : pool) thread.join();
  return rate;
}

/// An empty asm that claims to change x: the compiler keeps every step of a chain (without
/// it, GCC folded the whole loop away).
inline void keepInRegister(double& x) {
#if defined(__x86_64__) || defined(__i386__)
  asm volatile("" : "+x"(x));
#elif defined(__aarch64__)
  asm volatile("" : "+w"(x));
#else
  asm volatile("" : "+m"(x));
#endif
}

/// Independent multiply-add chains, 8 at a time: 16 flops per iteration.
double computeWork(long rounds) {
  double a[8];
  for (int k = 0; k < 8; ++k) a[k] = 1.0 + 1e-9 * k;
  const double b = 0.999999999;
  const double c = 1e-9;
  for (long r = 0; r < rounds * 1000; ++r) {
    for (double& x : a) {
      x = x * b + c;
      keepInRegister(x);
    }
  }
  double sum = 0.0;
  for (const double x : a) sum += x;
  return sum;
}

/// A kick-like pass over `n` elements of thread-local arrays: v += f * m; x += v * dt.
struct StreamData {
  explicit StreamData(std::size_t n) : x(n, 0.0), v(n, 0.0), f(n, 1e-9), m(n, 1.0) {}
  std::vector<double> x, v, f, m;
  double pass(long rounds) {
    for (long r = 0; r < rounds; ++r) {
      for (std::size_t i = 0; i < x.size(); ++i) {
        v[i] += f[i] * m[i];
        x[i] += v[i] * 1e-6;
      }
    }
    return x[x.size() / 2];
  }
};

/// Round trips of one cache line between two threads on two CPUs [s per round trip].
double handOverRoundTrip(const std::vector<int>& cpus, double seconds) {
  alignas(64) static std::atomic<long> line{0};
  line = 0;
  std::atomic<bool> stop{false};
  std::thread partner([&] {
    pinTo(cpus.size() > 1 ? cpus[1] : -1);
    for (long expect = 1; !stop.load(std::memory_order_relaxed); expect += 2) {
      while (line.load(std::memory_order_acquire) != expect) {
        if (stop.load(std::memory_order_relaxed)) return;
      }
      line.store(expect + 1, std::memory_order_release);
    }
  });
  pinTo(cpus.empty() ? -1 : cpus[0]);
  long trips = 0;
  const auto start = Clock::now();
  double took = 0.0;
  while (took < seconds) {
    for (int k = 0; k < 1000; ++k, ++trips) {
      line.store(2 * trips + 1, std::memory_order_release);
      while (line.load(std::memory_order_acquire) != 2 * trips + 2) {
      }
    }
    took = std::chrono::duration<double>(Clock::now() - start).count();
  }
  stop = true;
  partner.join();
  return took / static_cast<double>(trips);
}

void report(const char* what, const char* unit, const std::vector<double>& one, const std::vector<double>& two) {
  const double sumTwo = two.size() > 1 ? two[0] + two[1] : 0.0;
  std::printf("%-26s 1 thread %9.2f %s   2 threads %9.2f + %9.2f %s   speed-up %.2f\n", what, one[0], unit,
              two.size() > 1 ? two[0] : 0.0, two.size() > 1 ? two[1] : 0.0, unit, sumTwo / one[0]);
}

}  // namespace

int main(int argc, char** argv) {
  double seconds = 0.2;
  CLI::App app("What this machine gives a second thread, on the kinds of work a DEM step is made of.",
               "demlink-bench-host");
  demlink::cli::addValue(app, "--seconds", "time per measurement [s], in (0, 60] (default 0.2)",
                         [&seconds](const std::string& text) {
                           const double value = demlink::cli::number("--seconds", text);
                           if (!(value > 0.0 && value <= 60.0)) {
                             demlink::cli::refuse("--seconds", text, "must be in (0, 60]");
                           }
                           seconds = value;
                         })
      ->type_name("S");
  if (const std::optional<int> exitCode = demlink::cli::parse(app, argc, argv)) return *exitCode;
  const std::vector<int> cpus = allowedCpus();
  std::printf("CPUs this process may use: %zu; threads pinned to CPUs", cpus.size());
  for (std::size_t k = 0; k < std::min<std::size_t>(2, cpus.size()); ++k) std::printf(" %d", cpus[k]);
  std::printf("\n");
  if (cpus.size() < 2) std::printf("note: fewer than two CPUs; two threads share one\n");

  report("compute [Gflop/s]", "", ratePerThread(1, cpus, seconds, computeWork, 16e-6),
         ratePerThread(2, cpus, seconds, computeWork, 16e-6));
  for (const std::size_t kib : {32u, 256u, 768u, 4096u, 65536u}) {
    const std::size_t n = kib * 1024 / (4 * sizeof(double));
    // Each thread makes its own arrays (first touched by the thread that streams them).
    const auto work = [n](long rounds) {
      thread_local std::vector<StreamData> data;
      if (data.empty() || data.front().x.size() != n) {
        data.clear();
        data.emplace_back(n);
      }
      return data.front().pass(rounds);
    };
    // Bytes moved per element: four read, two written.
    const double gbPerRound = static_cast<double>(n) * 6 * sizeof(double) * 1e-9;
    char label[64];
    std::snprintf(label, sizeof label, "stream %6zu KiB [GB/s]", kib);
    report(label, "", ratePerThread(1, cpus, seconds, work, gbPerRound), ratePerThread(2, cpus, seconds, work, gbPerRound));
  }
  if (cpus.size() >= 2) {
    std::printf("%-26s %.0f ns\n", "hand-over round trip", 1e9 * handOverRoundTrip(cpus, seconds));
  }
  return 0;
}
