// The spin-then-block rule (spin_wait.hpp): the gate's admission rule and spinFor's result
// (the thread pool's waits with and without spinning: test_thread_pool.cpp).
#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <fstream>
#include <thread>

#include "demlink/core/parallel/spin_wait.hpp"

namespace demlink::core {
namespace {

using Party = SpinGate::Party;

TEST(SpinGate, LeavesOneFreeCpuToThePartyWaitedFor) {
  // 2 idle CPUs, no DEM pool: one exchange spinner, not two.
  EXPECT_TRUE(SpinGate::admits(Party::kExchange, 2, 0, 0, 0, 0));
  EXPECT_FALSE(SpinGate::admits(Party::kExchange, 2, 1, 0, 0, 0));
  // One CPU busy with another process: none.
  EXPECT_FALSE(SpinGate::admits(Party::kExchange, 1, 0, 0, 0, 0));
  // A 2-thread DEM pool (one worker) on 2 free CPUs: the worker's core is not taken.
  EXPECT_FALSE(SpinGate::admits(Party::kExchange, 2, 0, 2, 1, 0));
  EXPECT_TRUE(SpinGate::admits(Party::kExchange, 4, 1, 2, 1, 0));
}

TEST(SpinGate, KeepsNoCpuForAPartnerInTheSameProcess) {
  // A server loop and its one client in one process on 2 free CPUs: both parties have a
  // core, so both may spin (the second spinner too).
  EXPECT_TRUE(SpinGate::admits(Party::kExchange, 2, 1, 0, 0, 2, true));
  EXPECT_FALSE(SpinGate::admits(Party::kExchange, 2, 2, 0, 0, 2, true));
  // Still never more parties than free CPUs, nor a DEM worker's core.
  EXPECT_FALSE(SpinGate::admits(Party::kExchange, 2, 0, 0, 0, 5, true));
  EXPECT_FALSE(SpinGate::admits(Party::kExchange, 2, 1, 2, 1, 1, true));
}

TEST(SpinGate, RefusesWhenTheExchangePartiesOutnumberTheFreeCpus) {
  // A server loop and one client on 2 free CPUs: one of them may spin.
  EXPECT_TRUE(SpinGate::admits(Party::kExchange, 2, 0, 0, 0, 2));
  // A server loop and 4 (or 16) clients on 2 free CPUs: a spinner would hold a core one
  // of the others needs to run.
  EXPECT_FALSE(SpinGate::admits(Party::kExchange, 2, 0, 0, 0, 5));
  EXPECT_FALSE(SpinGate::admits(Party::kExchange, 2, 0, 0, 0, 17));
  // The same 5 parties on 8 free CPUs: they fit.
  EXPECT_TRUE(SpinGate::admits(Party::kExchange, 8, 0, 0, 0, 5));
  // A server loop beside a 2-thread DEM pool on 4 free CPUs: 1 party + 1 worker fit.
  EXPECT_TRUE(SpinGate::admits(Party::kExchange, 4, 0, 2, 1, 1));
  EXPECT_FALSE(SpinGate::admits(Party::kExchange, 4, 0, 2, 1, 4));
  // DEM pool threads do not count the exchange parties (the pool's own rule).
  EXPECT_TRUE(SpinGate::admits(Party::kDem, 2, 0, 2, 1, 5));
}

TEST(SpinGate, CountsOnlyOtherProcessesWorkAsBusy) {
  // Over 0.25 s the machine was busy 0.5 CPU-s, all of it this process's 2 threads: the
  // other processes keep no CPU busy, both CPUs are free (a gate that counted the
  // process's own threads would see none free and refuse every spin).
  EXPECT_DOUBLE_EQ(SpinGate::othersBusyOver(0.5, 0.5, 0.25), 0.0);
  EXPECT_EQ(SpinGate::freeCpusOf(2, SpinGate::othersBusyOver(0.5, 0.5, 0.25)), 2);
  // One busy loop elsewhere beside one busy thread here: one CPU free.
  EXPECT_DOUBLE_EQ(SpinGate::othersBusyOver(0.5, 0.25, 0.25), 1.0);
  EXPECT_EQ(SpinGate::freeCpusOf(2, 1.0), 1);
  // Accounting noise (the tick-sampled /proc/stat a little below the exact own time).
  EXPECT_DOUBLE_EQ(SpinGate::othersBusyOver(0.48, 0.5, 0.25), 0.0);
  EXPECT_EQ(SpinGate::freeCpusOf(2, 0.4), 2);
  EXPECT_EQ(SpinGate::freeCpusOf(2, 0.6), 1);
  // Far more load than CPUs: none free, never negative; no period: nothing measured.
  EXPECT_EQ(SpinGate::freeCpusOf(2, 13.0), 0);
  EXPECT_DOUBLE_EQ(SpinGate::othersBusyOver(1.0, 0.0, 0.0), 0.0);
}

TEST(SpinGate, DemThreadsSpinOnlyWhenAllFit) {
  EXPECT_TRUE(SpinGate::admits(Party::kDem, 2, 0, 2, 1, 0));
  EXPECT_FALSE(SpinGate::admits(Party::kDem, 1, 0, 2, 1, 0));  // beside one busy process
  EXPECT_FALSE(SpinGate::admits(Party::kDem, 0, 0, 1, 0, 0));
}

TEST(SpinGate, FreeCpusStayWithinTheUsableOnes) {
  const int free = SpinGate::instance().freeCpus();
  EXPECT_GE(free, 0);
  EXPECT_LE(free, static_cast<int>(usableCpus()));
  EXPECT_GE(SpinGate::instance().othersBusy(), 0.0);
}

TEST(SpinGate, MeasuresWithinTheFirstShortPeriod) {
  // The load average stands in only until the first 50 ms have been measured; then the
  // estimate stands for the full period.
  if (!std::ifstream("/proc/stat")) GTEST_SKIP() << "no /proc/stat: the load average stands in for good";
  SpinGate& gate = SpinGate::instance();
  (void)gate.freeCpus();
  std::this_thread::sleep_for(std::chrono::milliseconds(60));
  (void)gate.freeCpus();
  EXPECT_TRUE(gate.measured());
  EXPECT_EQ(gate.refreshPeriodNs(), 250'000'000);
}

TEST(SpinFor, ReturnsTrueOnceReadyAndFalseWithoutBudget) {
  SpinGate& gate = SpinGate::instance();
  gate.setForced(true);
  int polls = 0;
  EXPECT_TRUE(spinFor(Party::kExchange, std::chrono::seconds(5), [&] { return ++polls == 100; }));
  EXPECT_EQ(polls, 100);
  polls = 0;
  EXPECT_FALSE(spinFor(Party::kExchange, std::chrono::nanoseconds::zero(), [&] { return ++polls > 0; }));
  EXPECT_EQ(polls, 0);  // no budget: the caller blocks at once
  EXPECT_FALSE(spinFor(Party::kExchange, std::chrono::microseconds(20), [] { return false; }));
  gate.setForced(false);
  const SpinStats stats = gate.stats();
  EXPECT_GE(stats.ready_spinning, 1u);
  EXPECT_GE(stats.blocked_after_spin, 1u);
}

TEST(SpinFor, AnEventFromAnotherThreadEndsTheSpin) {
  SpinGate::instance().setForced(true);
  std::atomic<bool> flag{false};
  std::thread setter([&] { flag.store(true, std::memory_order_release); });
  // The budget is far longer than any thread start, so only a missed store could fail.
  const bool ready = spinFor(Party::kExchange, std::chrono::seconds(10), [&] { return flag.load(); });
  setter.join();
  SpinGate::instance().setForced(false);
  EXPECT_TRUE(ready);
}

}  // namespace
}  // namespace demlink::core
