// SimulationWorker: the calls posted to a simulation's thread run there one at a time, in
// the order posted, each reported once; with a spin budget and a free CPU the thread takes
// a call that comes soon after the last one while spinning, without blocking.
#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <condition_variable>
#include <filesystem>
#include <memory>
#include <mutex>
#include <thread>
#include <vector>

#include "demlink/core/parallel/spin_history.hpp"
#include "demlink/core/parallel/spin_wait.hpp"
#include "demlink/server/cosim/simulation_worker.hpp"

namespace demlink::server::test {
namespace {

/// Posts `calls` calls, each `gap` after the report of the one before (a client exchanging
/// back to back), and returns the order in which they ran and the thread they ran on.
struct Outcome {
  std::vector<int> order;
  std::vector<std::thread::id> threads;
  std::uint64_t reports = 0;
};

Outcome postBackToBack(std::chrono::nanoseconds spin, int calls, std::chrono::microseconds gap) {
  CosimOptions options;
  options.output_root = std::filesystem::temp_directory_path() / "demlink_test_simulation_worker";
  Outcome outcome;
  std::mutex mutex;
  std::condition_variable reported;
  std::uint64_t done = 0;
  SimulationWorker worker(
      std::make_unique<CosimHost>(options),
      [&](std::vector<Outgoing>, CosimHost::Status, bool, std::uint64_t callsDone) {
        const std::lock_guard lock(mutex);
        done = callsDone;
        ++outcome.reports;
        reported.notify_all();
      },
      spin);
  for (int k = 0; k < calls; ++k) {
    std::this_thread::sleep_for(gap);
    worker.post([&outcome, k](CosimHost&) {
      outcome.order.push_back(k);
      outcome.threads.push_back(std::this_thread::get_id());
      return std::vector<Outgoing>{};
    });
    std::unique_lock lock(mutex);
    EXPECT_TRUE(reported.wait_for(lock, std::chrono::seconds(10), [&] { return done == static_cast<std::uint64_t>(k + 1); }))
        << "call " << k << " was not reported";
  }
  return outcome;
}

void expectInOrderOnOneOtherThread(const Outcome& outcome, int calls) {
  ASSERT_EQ(outcome.order.size(), static_cast<std::size_t>(calls));
  for (int k = 0; k < calls; ++k) EXPECT_EQ(outcome.order[static_cast<std::size_t>(k)], k);
  for (const std::thread::id id : outcome.threads) {
    EXPECT_EQ(id, outcome.threads.front());
    EXPECT_NE(id, std::this_thread::get_id());
  }
  EXPECT_EQ(outcome.reports, static_cast<std::uint64_t>(calls));
}

TEST(SimulationWorker, RunsCallsInOrderBlockingBetweenThem) {
  expectInOrderOnOneOtherThread(postBackToBack(std::chrono::nanoseconds::zero(), 200, std::chrono::microseconds(50)), 200);
}

TEST(SimulationWorker, TakesCallsThatComeWithinTheBudgetWhileSpinning) {
  core::SpinGate& gate = core::SpinGate::instance();
  gate.pinFreeCpus(4);  // the gate admits the spinner whatever else the machine runs
  const core::SpinStats before = gate.stats();
  // The poster pauses before each call, so the thread is waiting when it comes; the budget
  // is far beyond the pause, so a poster this machine deschedules still comes within it.
  const Outcome outcome = postBackToBack(std::chrono::milliseconds(20), 200, std::chrono::microseconds(100));
  const core::SpinStats after = gate.stats();
  gate.pinFreeCpus(-1);
  expectInOrderOnOneOtherThread(outcome, 200);
  // Most of the calls after the first came while the thread spun (a few may miss when this
  // machine deschedules the poster for longer than the budget).
  EXPECT_GT(after.ready_spinning - before.ready_spinning, 100u)
      << "blocked after a spin: " << after.blocked_after_spin - before.blocked_after_spin
      << ", refused: " << after.refused - before.refused << ", asleep: " << core::SpinHistory::stats().partner_asleep;
}

}  // namespace
}  // namespace demlink::server::test
