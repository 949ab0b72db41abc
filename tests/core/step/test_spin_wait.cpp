// The spin-then-block rule (spin_wait.hpp): the gate's admission rule and spinFor's result
// (the thread pool's waits with and without spinning: test_thread_pool.cpp).
#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <thread>

#include "demlink/core/step/spin_wait.hpp"

namespace demlink::core {
namespace {

using Party = SpinGate::Party;

TEST(SpinGate, LeavesOneFreeCpuToThePartyWaitedFor) {
  // 2 idle CPUs, no DEM pool: one exchange spinner, not two.
  EXPECT_TRUE(SpinGate::admits(Party::kExchange, 2, 0, 0, 0));
  EXPECT_FALSE(SpinGate::admits(Party::kExchange, 2, 1, 0, 0));
  // One CPU busy with another process: none.
  EXPECT_FALSE(SpinGate::admits(Party::kExchange, 1, 0, 0, 0));
  // A 2-thread DEM pool (one worker) on 2 free CPUs: the worker's core is not taken.
  EXPECT_FALSE(SpinGate::admits(Party::kExchange, 2, 0, 2, 1));
  EXPECT_TRUE(SpinGate::admits(Party::kExchange, 4, 1, 2, 1));
}

TEST(SpinGate, DemThreadsSpinOnlyWhenAllFit) {
  EXPECT_TRUE(SpinGate::admits(Party::kDem, 2, 0, 2, 1));
  EXPECT_FALSE(SpinGate::admits(Party::kDem, 1, 0, 2, 1));  // beside one busy process
  EXPECT_FALSE(SpinGate::admits(Party::kDem, 0, 0, 1, 0));
}

TEST(SpinGate, FreeCpusStayWithinTheUsableOnes) {
  const int free = SpinGate::instance().freeCpus();
  EXPECT_GE(free, 0);
  EXPECT_LE(free, static_cast<int>(usableCpus()));
  EXPECT_GE(SpinGate::instance().othersBusy(), 0.0);
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
