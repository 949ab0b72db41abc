// The exchange waits' decision (spin_history.hpp): given a waiter's recent waits, spin or
// block. Times are made up (time points, no clock), so nothing here depends on speed.
#include <gtest/gtest.h>

#include <chrono>
#include <cstdint>
#include <optional>

#include "demlink/core/parallel/spin_history.hpp"
#include "demlink/core/parallel/spin_wait.hpp"

namespace demlink::core {
namespace {

using Advice = SpinHistory::Advice;
using std::chrono::microseconds;
using std::chrono::nanoseconds;
constexpr nanoseconds kBudget = microseconds(50);

TEST(SpinHistoryRule, AWaiterAwayLongerThanTheBudgetFindsItsPartnerAsleepAndBlocks) {
  // The partner spun out its budget while this waiter was away: block, whatever the misses.
  EXPECT_EQ(SpinHistory::adviceFor(microseconds(51), 0, 0, kBudget), Advice::kBlockPartnerAsleep);
  EXPECT_EQ(SpinHistory::adviceFor(microseconds(1000), 0, SpinHistory::kRetryEvery, kBudget),
            Advice::kBlockPartnerAsleep);
  // Back within the budget (or no event yet): spin.
  EXPECT_EQ(SpinHistory::adviceFor(microseconds(50), 0, 0, kBudget), Advice::kSpin);
  EXPECT_EQ(SpinHistory::adviceFor(microseconds(3), 0, 0, kBudget), Advice::kSpin);
  EXPECT_EQ(SpinHistory::adviceFor(std::nullopt, 0, 0, kBudget), Advice::kSpin);
}

TEST(SpinHistoryRule, LateWaitsInARowBackOffWithARetryEveryFewWaits) {
  for (std::uint32_t misses = 0; misses < SpinHistory::kMissesBeforeBackOff; ++misses) {
    EXPECT_EQ(SpinHistory::adviceFor(microseconds(2), misses, 0, kBudget), Advice::kSpin) << misses;
  }
  const std::uint32_t late = SpinHistory::kMissesBeforeBackOff;
  EXPECT_EQ(SpinHistory::adviceFor(microseconds(2), late, 0, kBudget), Advice::kBlockLate);
  EXPECT_EQ(SpinHistory::adviceFor(microseconds(2), late, SpinHistory::kRetryEvery - 2, kBudget), Advice::kBlockLate);
  EXPECT_EQ(SpinHistory::adviceFor(microseconds(2), late, SpinHistory::kRetryEvery - 1, kBudget), Advice::kSpin);
}

/// A waiter's waits replayed on made-up times: each wait starts `away` after the last
/// event and its event comes `wait` after it starts; a spin sees it when it comes within
/// the budget, otherwise the waiter blocks (and sees it then).
struct Replay {
  SpinHistory history;
  SpinHistory::Clock::time_point now{};
  int spins = 0, asleep = 0, late = 0;

  void wait(microseconds away, microseconds wait) {
    now += away;
    const Advice advice = history.begin(now, kBudget);
    now += wait;
    if (advice == Advice::kSpin) {
      ++spins;
      if (wait <= kBudget) {
        history.arrived(now, true);
        return;
      }
      history.spunOut();
    }
    if (advice == Advice::kBlockPartnerAsleep) ++asleep;
    if (advice == Advice::kBlockLate) ++late;
    history.arrived(now, false);
  }
};

TEST(SpinHistoryRule, ABackToBackClientAndItsServerKeepSpinning) {
  Replay client, server;
  for (int k = 0; k < 1000; ++k) {
    client.wait(microseconds(3), microseconds(20));  // the answer comes 20 us after the package
    server.wait(microseconds(10), microseconds(5));  // the next package 5 us after the answer
  }
  EXPECT_EQ(client.spins, 1000);
  EXPECT_EQ(server.spins, 1000);
}

TEST(SpinHistoryRule, AClientPacedAtOneMillisecondBlocksAtOnceAndItsServerBacksOff) {
  Replay client, server;
  for (int k = 0; k < 3200; ++k) {
    // The client sleeps ~1 ms between exchanges; the server's wait lasts that long.
    client.wait(microseconds(960), microseconds(35));
    server.wait(microseconds(10), microseconds(985));
  }
  // The client spins only for its first answer (no event seen yet), then never: its
  // server has blocked long before each package.
  EXPECT_EQ(client.spins, 1);
  EXPECT_EQ(client.asleep, 3199);
  // The server spins out kMissesBeforeBackOff times, then once per kRetryEvery waits.
  EXPECT_LE(server.spins, static_cast<int>(SpinHistory::kMissesBeforeBackOff + 3200 / SpinHistory::kRetryEvery + 1));
  EXPECT_GE(server.late, 3200 - server.spins);
}

TEST(SpinHistoryRule, ABlockedWaitWithinTheBudgetEndsTheBackOffAndOnlyFarLateBlockedWaitsCount) {
  Replay server;
  for (std::uint32_t k = 0; k < SpinHistory::kMissesBeforeBackOff; ++k) server.wait(microseconds(5), microseconds(900));
  ASSERT_EQ(server.history.misses(), SpinHistory::kMissesBeforeBackOff);
  // Blocked, its event 2 budgets late: a wake-up may explain that, so no new evidence.
  server.wait(microseconds(5), microseconds(100));
  EXPECT_EQ(server.history.misses(), SpinHistory::kMissesBeforeBackOff);
  EXPECT_EQ(server.late, 1);
  // Blocked, far late (more than kLateFactor budgets): one more miss.
  server.wait(microseconds(5), microseconds(500));
  EXPECT_EQ(server.history.misses(), SpinHistory::kMissesBeforeBackOff + 1);
  // Blocked, yet within the budget wake-up included: the client is back to back, spin again.
  server.wait(microseconds(5), microseconds(30));
  EXPECT_EQ(server.history.misses(), 0u);
  const int spinsBefore = server.spins;
  server.wait(microseconds(5), microseconds(10));
  EXPECT_EQ(server.spins, spinsBefore + 1);
}

TEST(SpinHistoryRule, AfterThePartnerWasAsleepAWaiterBackWithinTheBudgetSpinsAgain) {
  Replay client;
  client.wait(microseconds(5), microseconds(20));
  ASSERT_EQ(client.spins, 1);
  client.wait(microseconds(1000), microseconds(40));
  EXPECT_EQ(client.asleep, 1);
  client.wait(microseconds(5), microseconds(20));
  EXPECT_EQ(client.spins, 2);
}

TEST(SpinHistory, SpinForCountsASpinThatRanOutAndNotOneTheBudgetRefused) {
  SpinGate::instance().setForced(true);
  SpinHistory history;
  int polls = 0;
  const auto late = [&] {
    ++polls;
    return false;
  };
  for (std::uint32_t k = 0; k < SpinHistory::kMissesBeforeBackOff; ++k) {
    polls = 0;
    EXPECT_FALSE(spinFor(history, SpinGate::Party::kExchange, microseconds(20), late));
    EXPECT_GT(polls, 0) << "spin " << k;
    history.arrived(SpinHistory::Clock::now(), false);
  }
  EXPECT_EQ(history.misses(), SpinHistory::kMissesBeforeBackOff);
  // Backed off: the next wait is not polled.
  polls = 0;
  EXPECT_FALSE(spinFor(history, SpinGate::Party::kExchange, microseconds(20), late));
  EXPECT_EQ(polls, 0);
  SpinGate::instance().setForced(false);

  // Spinning off (budget 0): never polled, and a blocked wait within no budget is no miss.
  SpinHistory off;
  for (int k = 0; k < 10; ++k) {
    EXPECT_FALSE(spinFor(off, SpinGate::Party::kExchange, nanoseconds::zero(), late));
    off.arrived(SpinHistory::Clock::now(), false);
  }
  EXPECT_EQ(off.misses(), 0u);
}

}  // namespace
}  // namespace demlink::core
