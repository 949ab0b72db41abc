// The thread pool survives the operating system refusing a thread: the threads it had
// started are joined and a ThreadStartError says how many ran, instead of std::terminate
// ("terminate called without an active exception") from a destroyed joinable thread.
#include <gtest/gtest.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <atomic>
#include <chrono>
#include <cmath>
#include <fstream>
#include <mutex>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include "demlink/core/parallel/parallel_loops.hpp"
#include "demlink/core/parallel/spin_wait.hpp"
#include "demlink/core/parallel/thread_pool.hpp"

namespace demlink::core {
namespace {

/// This process's virtual memory size [bytes] (VmSize in /proc/self/status).
long virtualBytes() {
  std::ifstream status("/proc/self/status");
  std::string line;
  while (std::getline(status, line)) {
    if (line.rfind("VmSize:", 0) == 0) return std::stol(line.substr(7)) * 1024;
  }
  return -1;
}

TEST(ThreadPool, RunsEveryPartOnce) {
  ThreadPool pool(2);
  std::atomic<int> sum{0};
  pool.run(100, [&](std::uint32_t part) { sum += static_cast<int>(part); });
  EXPECT_EQ(sum.load(), 99 * 100 / 2);
}

TEST(ThreadPool, ClaimsEveryChunkExactlyOnceOverManyLoops) {
  // More threads than cores and thousands of back-to-back loops of varying size: a
  // chunk claimed twice or skipped (a stale ticket, a late worker) shows in the counts.
  ThreadPool pool(4);
  std::vector<std::atomic<int>> runs(997);
  for (int loop = 0; loop < 3000; ++loop) {
    const auto chunks = static_cast<std::uint32_t>(2 + (loop * 37) % 995);
    pool.run(chunks, [&](std::uint32_t chunk) { runs[chunk].fetch_add(1, std::memory_order_relaxed); });
  }
  std::vector<int> expected(runs.size(), 0);
  for (int loop = 0; loop < 3000; ++loop) {
    for (std::uint32_t c = 0; c < static_cast<std::uint32_t>(2 + (loop * 37) % 995); ++c) ++expected[c];
  }
  for (std::size_t c = 0; c < runs.size(); ++c) ASSERT_EQ(runs[c].load(), expected[c]) << "chunk " << c;
  const ThreadPoolStats stats = pool.stats();
  EXPECT_EQ(stats.parallel_runs + stats.serial_runs, 3000u);
  std::uint64_t offered = 0;
  for (int loop = 0; loop < 3000; ++loop) offered += 2 + (loop * 37) % 995;
  EXPECT_LE(stats.caller_chunks + stats.worker_chunks, offered);
  EXPECT_GE(stats.parallel_runs, 1u);  // the first run of a loop is always offered
}

TEST(ThreadPool, EachThreadStartsAtTheFrontOfItsHomeRange) {
  // 2 threads, 8 chunks: the caller's home range is chunks 0-3, the worker's 4-7. Each
  // thread claims its own range front first, then steals from the other's back: the
  // caller's first chunk is always 0, and the worker's first chunk, when it comes in time
  // to find its range untouched by the caller's stealing, is 4. With one shared ticket
  // the chunks fell to whichever thread came first, and each loop found half of its data
  // in the other core's cache.
  ThreadPool pool(2);
  const std::thread::id caller = std::this_thread::get_id();
  int workerLoops = 0;
  for (int loop = 0; loop < 20; ++loop) {
    std::mutex mutex;
    std::vector<std::pair<std::thread::id, std::uint32_t>> order;
    pool.run(8, [&](std::uint32_t chunk) {
      {
        const std::lock_guard lock(mutex);
        order.emplace_back(std::this_thread::get_id(), chunk);
      }
      std::this_thread::sleep_for(std::chrono::microseconds(300));
    });
    ASSERT_EQ(order.size(), 8u);
    std::optional<std::uint32_t> callerFirst, workerFirst;
    for (const auto& [thread, chunk] : order) {
      std::optional<std::uint32_t>& first = thread == caller ? callerFirst : workerFirst;
      if (!first) first = chunk;
    }
    ASSERT_TRUE(callerFirst.has_value());
    EXPECT_EQ(*callerFirst, 0u) << "loop " << loop;
    if (workerFirst && *workerFirst >= 4) {  // its own range, not a stolen caller chunk
      ++workerLoops;
      EXPECT_EQ(*workerFirst, 4u) << "loop " << loop;
    }
  }
  // Each chunk sleeps 300 us, so a loop lasts >= 1.2 ms even if the caller runs it alone:
  // time enough for the worker to wake and take part in some of the loops.
  EXPECT_GE(workerLoops, 1);
}

TEST(ThreadPool, OffersLoopsToAwakeWorkersAndToSleepingOnesWhenCoresAreFree) {
  const double busyWorth = ThreadPool::kWakeWorthBusySeconds;
  // One chunk: nothing to share.
  EXPECT_FALSE(ThreadPool::offersToWorkers(1, true, 1.0, true));
  // A worker spinning between loops takes a share of any loop of 2+ chunks.
  EXPECT_TRUE(ThreadPool::offersToWorkers(2, true, 1e-6, false));
  // Sleeping workers with free cores: woken for any loop, however short (they spin
  // between loops afterwards).
  EXPECT_TRUE(ThreadPool::offersToWorkers(5, false, -1.0, true));
  EXPECT_TRUE(ThreadPool::offersToWorkers(5, false, 1e-6, true));
  // Sleeping workers without free cores: only for a loop not run yet or one of
  // kWakeWorthBusySeconds or more.
  EXPECT_TRUE(ThreadPool::offersToWorkers(5, false, -1.0, false));
  EXPECT_FALSE(ThreadPool::offersToWorkers(5, false, 150e-6, false));
  EXPECT_FALSE(ThreadPool::offersToWorkers(5, false, 0.5 * busyWorth, false));
  EXPECT_TRUE(ThreadPool::offersToWorkers(5, false, busyWorth, false));
}

TEST(ThreadPool, WakesSleepingWorkersForLongLoopsOrWhenCoresAreFree) {
  // No spin budget: workers sleep between loops. Chunks that sleep 1 ms hold at least
  // 8 ms of work however loaded the machine is: every run is offered, and the worker
  // runs some chunks (the caller sleeps in its own, so the woken worker claims others).
  ThreadPool pool(2, std::chrono::nanoseconds::zero());
  for (int loop = 0; loop < 5; ++loop) {
    pool.run(8, [](std::uint32_t) { std::this_thread::sleep_for(std::chrono::milliseconds(1)); });
  }
  ThreadPoolStats stats = pool.stats();
  EXPECT_EQ(stats.parallel_runs, 5u);
  EXPECT_EQ(stats.serial_runs, 0u);
  EXPECT_EQ(stats.caller_chunks + stats.worker_chunks, 40u);
  EXPECT_GE(stats.worker_chunks, 1u);
  // Empty chunks, the gate seeing no free CPU: after its first run (offered, as nothing
  // is known yet) the loop is far shorter than kWakeWorthBusySeconds, and the caller runs
  // it alone.
  SpinGate& gate = SpinGate::instance();
  gate.pinFreeCpus(0);
  std::atomic<int> ran{0};
  const auto emptyLoops = [&](int loops) {
    for (int loop = 0; loop < loops; ++loop) pool.run(4, [&](std::uint32_t) { ran.fetch_add(1); });
  };
  emptyLoops(50);
  EXPECT_EQ(ran.load(), 200);
  stats = pool.stats();
  EXPECT_GE(stats.serial_runs, 49u);
  // The gate seeing a free CPU for each of the pool's threads: every loop is offered.
  gate.pinFreeCpus(2);
  emptyLoops(50);
  gate.pinFreeCpus(-1);
  EXPECT_EQ(ran.load(), 400);
  const ThreadPoolStats freed = pool.stats();
  EXPECT_EQ(freed.serial_runs, stats.serial_runs);
  EXPECT_EQ(freed.parallel_runs, stats.parallel_runs + 50);
}

TEST(ThreadPool, ChunkOrderedReductionIsIndependentOfThreadCount) {
  // Partial sums per chunk, combined in chunk order: the same bits for 1..4 threads
  // (a sum in thread order would differ in the last bits: the terms span 1e-9..1e9).
  const std::size_t n = 200000;
  std::vector<double> terms(n);
  for (std::size_t i = 0; i < n; ++i) {
    terms[i] = std::pow(10.0, static_cast<double>(i % 19) - 9.0) * (1.0 + 1e-3 * static_cast<double>(i));
  }
  const auto total = [&](ThreadPool* pool) {
    const std::uint32_t chunks = chunkCount(n);
    std::vector<double> partial(chunks, 0.0);
    parallelParts(pool, chunks, [&](std::uint32_t c) {
      for (std::size_t i = chunkBegin(n, chunks, c); i < chunkBegin(n, chunks, c + 1); ++i) partial[c] += terms[i];
    });
    double sum = 0.0;
    for (const double p : partial) sum += p;
    return sum;
  };
  const double serial = total(nullptr);
  // Waits that spin (1 ms, every spinner admitted) or block at once: the same bits,
  // whichever thread claimed which chunk.
  SpinGate::instance().setForced(true);
  for (const auto budget : {std::chrono::nanoseconds(1'000'000), std::chrono::nanoseconds::zero()}) {
    for (std::uint32_t threads = 1; threads <= 4; ++threads) {
      ThreadPool pool(threads, budget);
      for (int repeat = 0; repeat < 40; ++repeat) {
        ASSERT_EQ(total(&pool), serial) << threads << " threads, spin " << budget.count() << " ns";
      }
    }
  }
  SpinGate::instance().setForced(false);
}

TEST(ThreadPool, AThreadTheSystemRefusesIsAnErrorNotTerminate) {
  // In a child process: an address-space limit leaves room for about two 8 MiB thread
  // stacks, then 64 threads are asked for. Exit 0: ThreadStartError caught with some
  // threads started and joined; a signal (SIGABRT from std::terminate) fails the test.
  const pid_t child = fork();
  ASSERT_GE(child, 0);
  if (child == 0) {
    const long now = virtualBytes();
    rlimit limit{};
    limit.rlim_cur = limit.rlim_max = static_cast<rlim_t>(now + (20L << 20));
    if (now <= 0 || setrlimit(RLIMIT_AS, &limit) != 0) _exit(3);
    try {
      ThreadPool pool(64);
      _exit(4);  // every thread started: the limit did not bite
    } catch (const ThreadStartError& error) {
      const bool sensible = error.started() >= 1 && error.started() < 64 &&
                            std::string(error.what()).find("of 64 threads") != std::string::npos;
      _exit(sensible ? 0 : 5);
    }
  }
  int status = 0;
  ASSERT_EQ(waitpid(child, &status, 0), child);
  ASSERT_TRUE(WIFEXITED(status)) << "the child died of signal " << (WIFSIGNALED(status) ? WTERMSIG(status) : 0);
  EXPECT_EQ(WEXITSTATUS(status), 0);
}

}  // namespace
}  // namespace demlink::core
