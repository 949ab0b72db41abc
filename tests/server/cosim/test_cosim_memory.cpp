// Several simulations share one particle-memory budget: each compiled native simulation
// holds its estimate (particles and deformable nodes at kBytesPerParticle) until it ends,
// and a compile past the budget is refused with SERVER_BUSY saying what the others hold.
#include <gtest/gtest.h>

#include <memory>

#include "cosim_test_support.hpp"
#include "demlink/server/cosim/particle_memory_ledger.hpp"

namespace demlink::server::test {
namespace {

TEST(ParticleMemoryLedger, ReservationsHoldTheirBytesUntilDestroyed) {
  const auto ledger = std::make_shared<ParticleMemoryLedger>(1000);
  std::optional<ParticleMemoryLedger::Reservation> a = ParticleMemoryLedger::reserve(ledger, 600);
  ASSERT_TRUE(a.has_value());
  EXPECT_EQ(ledger->held(), 600u);
  EXPECT_FALSE(ParticleMemoryLedger::reserve(ledger, 401).has_value());  // 1001 > 1000
  {
    std::optional<ParticleMemoryLedger::Reservation> b = ParticleMemoryLedger::reserve(ledger, 400);
    ASSERT_TRUE(b.has_value());
    EXPECT_EQ(ledger->held(), 1000u);
    ParticleMemoryLedger::Reservation moved(std::move(*b));  // the bytes move with it, once
    b.reset();
    EXPECT_EQ(ledger->held(), 1000u);
  }
  EXPECT_EQ(ledger->held(), 600u);
  a.reset();
  EXPECT_EQ(ledger->held(), 0u);
}

/// Connection `id` on `h` declares a box ending after 10 steps and a 3 x 3 layer of spheres.
void declareSmallRun(CosimHarness& h, ConnectionId id) {
  h.hello(id, "bed " + std::to_string(id));
  h.declare(id, boxJson(1e-5, 1e-4, R"("coupling": {"expected_count": 4})", 5e-5));
  for (const std::string& c : smallBedJson()) h.declare(id, c);
}

TEST(CosimMemory, SimulationsShareOneParticleMemoryBudget) {
  ScratchDir dir;
  constexpr std::uint64_t kOneBed = 9 * kBytesPerParticle;  // smallBedJson(): a 3 x 3 layer
  const auto ledger = std::make_shared<ParticleMemoryLedger>(kOneBed + kOneBed / 2);
  const auto hostWith = [&](const char* folder) {
    CosimOptions o = CosimHarness::options(dir.path() / folder, {}, {});
    o.particle_memory = ledger;
    return std::make_unique<CosimHarness>(o);
  };
  const std::unique_ptr<CosimHarness> first = hostWith("first");
  const std::unique_ptr<CosimHarness> second = hostWith("second");
  declareSmallRun(*first, 1);
  ASSERT_TRUE(first->compiled(1)) << (first->errors(1).empty() ? "" : first->errors(1).front().message());
  EXPECT_EQ(ledger->held(), kOneBed);

  // While the first runs, a second bed would take the total past the budget.
  declareSmallRun(*second, 2);
  EXPECT_FALSE(second->compiled(2));
  const std::vector<v1::Error> refused = second->errors(2);
  ASSERT_FALSE(refused.empty());
  EXPECT_EQ(refused.back().code(), v1::Error::SERVER_BUSY);
  EXPECT_NE(refused.back().message().find("simulations running now hold"), std::string::npos)
      << refused.back().message();
  EXPECT_EQ(ledger->held(), kOneBed) << "a refused simulation holds nothing";

  // Once the first has ended, its memory is free for the next.
  runToTheEnd(*first, 1);
  ASSERT_TRUE(first->finished(1));
  EXPECT_EQ(ledger->held(), 0u);
  declareSmallRun(*second, 3);
  EXPECT_TRUE(second->compiled(3)) << (second->errors(3).empty() ? "" : second->errors(3).back().message());
  EXPECT_EQ(ledger->held(), kOneBed);
}

}  // namespace
}  // namespace demlink::server::test
