// Assembling a simulation cannot hold the server: a set that never completes ends after the
// assembly timeout with TIMEOUT naming what is missing; clients are grouped by
// Hello.simulation so a stray client cannot join (or break) another group's assembly; a
// scene that could never advance is refused at compile time.
#include <gtest/gtest.h>

#include "cosim_test_support.hpp"
#include "demlink/server/cosim/session_replay.hpp"

namespace demlink::server::test {
namespace {

/// A Hello refused without affecting the simulation: one fatal Error naming the field, closed.
void expectRefused(CosimHarness& h, ConnectionId id, const std::string& messagePart) {
  const std::vector<v1::Error> errors = h.errors(id);
  ASSERT_EQ(errors.size(), 1u);
  EXPECT_EQ(errors[0].code(), v1::Error::OUT_OF_ORDER) << errors[0].message();
  EXPECT_EQ(errors[0].field(), "hello.simulation");
  EXPECT_TRUE(errors[0].fatal());
  EXPECT_NE(errors[0].message().find(messagePart), std::string::npos) << errors[0].message();
  EXPECT_TRUE(h.closed(id));
}

/// The one Error `id` received: fatal, with `code` and `field`, followed by Finished and close.
void expectEndedWith(CosimHarness& h, ConnectionId id, v1::Error::Code code, const std::string& field,
                     const std::string& messagePart) {
  const std::vector<v1::Error> errors = h.errors(id);
  ASSERT_EQ(errors.size(), 1u);
  EXPECT_EQ(errors[0].code(), code) << errors[0].message();
  EXPECT_EQ(errors[0].field(), field);
  EXPECT_TRUE(errors[0].fatal());
  EXPECT_NE(errors[0].message().find(messagePart), std::string::npos) << errors[0].message();
  EXPECT_TRUE(h.finished(id));
  EXPECT_TRUE(h.closed(id));
}

bool welcomed(CosimHarness& h, ConnectionId id) {
  return !h.inbox(id).empty() && h.inbox(id).front().has_welcome();
}

TEST(CosimAssembly, AnIncompleteSetEndsAfterTheAssemblyTimeout) {
  ScratchDir dir;
  CosimHarness h(dir.path());
  const SteadyClock::time_point start = h.now();
  h.hello(1, "alpha");
  h.declare(1, boxJson(1e-5, 0.0, R"("coupling": {"expected_count": 100})", 2e-5));
  h.advanceClock(10.0);
  h.hello(2, "beta");  // joins the same (unnamed) simulation; the clock still counts from alpha
  ASSERT_TRUE(h.host().nextDeadline().has_value());
  EXPECT_EQ(*h.host().nextDeadline(), start + std::chrono::seconds(60));
  h.advanceClock(49.0);
  h.poll();
  EXPECT_TRUE(h.errors(1).empty()) << "59 s: still assembling";
  h.advanceClock(2.0);
  h.poll();
  for (const ConnectionId id : {ConnectionId{1}, ConnectionId{2}}) {
    expectEndedWith(h, id, v1::Error::TIMEOUT, "box.simulation_box.coupling.expected_count",
                    "was not compiled within 60 s of its first client: 1 of the 100 expected components declared");
  }
  EXPECT_EQ(h.host().simulationsFinished(), 1u);
  EXPECT_FALSE(h.host().nextDeadline().has_value());
  h.hello(3, "gamma");
  ASSERT_TRUE(welcomed(h, 3));
  EXPECT_EQ(h.inbox(3).front().welcome().simulation_number(), 2u) << "the next simulation is open";
}

TEST(CosimAssembly, MissingExpectedNamesAreListed) {
  ScratchDir dir;
  CosimHarness h(dir.path());
  h.hello(1, "alpha");
  h.declare(1, boxJson(1e-5, 0.0, R"("coupling": {"expected_names": ["glass", "bucket", "truck"]})", 2e-5));
  h.declare(1, smallBedJson()[0]);
  h.advanceClock(61.0);
  h.poll();
  expectEndedWith(h, 1, v1::Error::TIMEOUT, "box.simulation_box.coupling.expected_names",
                  "not declared yet: \"bucket\", \"truck\"");
}

TEST(CosimAssembly, ZeroDisablesTheAssemblyTimeout) {
  ScratchDir dir;
  CosimOptions options = CosimHarness::options(dir.path(), {}, {});
  options.assembly_timeout_s = 0.0;
  CosimHost host(options);
  v1::Hello hello;
  hello.set_protocol_version(1);
  const SteadyClock::time_point now = SteadyClock::now();
  ASSERT_EQ(host.connected(1, hello, now).size(), 1u);
  v1::ClientMessage declare;
  *declare.mutable_declare()->mutable_component() =
      declarationOf(boxJson(1e-5, 0.0, R"("coupling": {"expected_count": 100})", 2e-5));
  EXPECT_TRUE(host.received(1, declare, now).empty());
  EXPECT_FALSE(host.nextDeadline().has_value()) << "a count is expected (no quiet period), no assembly timeout";
  EXPECT_TRUE(host.poll(now + std::chrono::hours(24)).empty());
}

TEST(CosimAssembly, ClientsAreGroupedByTheirSimulationName) {
  ScratchDir dir;
  CosimHarness h(dir.path());
  h.hello(1, "alpha", "pit");
  h.hello(2, "stray", "other");
  expectRefused(h, 2, "simulation 1 of \"pit\" is being assembled");
  h.hello(3, "unnamed");
  expectRefused(h, 3, "this client asked for \"\"");
  h.hello(4, "beta", "pit");
  ASSERT_TRUE(welcomed(h, 4));
  h.declare(1, boxJson(1e-5, 1e-4, R"("coupling": {"expected_count": 3})", 2e-5));
  h.declare(1, smallBedJson()[0]);
  h.declare(4, R"({"name": "view", "communication_interval": 4e-5, "particle_view": {}})");
  ASSERT_TRUE(h.compiled(1));
  ASSERT_TRUE(h.compiled(4));
  EXPECT_EQ(h.host().simulationsFinished(), 0u) << "the refused clients ended nothing";
  h.bye(1);
  h.bye(4);
  EXPECT_EQ(h.host().simulationsFinished(), 1u);
  h.hello(5, "stray again", "other");
  EXPECT_TRUE(welcomed(h, 5)) << "once the server is free, any name starts the next simulation";
}

TEST(CosimAssembly, ARunThatCouldNeverAdvanceIsRefusedAtCompile) {
  ScratchDir dir;
  CosimHarness h(dir.path());
  h.hello(1, "alpha");
  h.declare(1, boxJson(1e-5, 0.0, R"("coupling": {"expected_count": 2})"));  // end 0, not exchanged
  h.declare(1, smallBedJson()[0]);
  expectEndedWith(h, 1, v1::Error::INVALID_DECLARATION, "box.simulation_box.end_time", "could never advance");
  EXPECT_EQ(h.errors(1)[0].component(), "box");
  EXPECT_FALSE(h.host().simulationRunning());
  h.hello(2, "beta");
  EXPECT_TRUE(welcomed(h, 2));
}

/// The last client that exchanges anything says Bye while one that only declared stays:
/// with no end time the world could never advance again, so the simulation ends.
TEST(CosimAssembly, ARunThatCanNoLongerAdvanceEndsWhenTheLastExchangingClientLeaves) {
  ScratchDir dir;
  CosimHarness h(dir.path());
  h.hello(1, "alpha");
  h.hello(2, "beta");
  h.declare(1, boxJson(1e-5, 0.0, R"("coupling": {"expected_count": 2})", 2e-5));
  h.declare(2, smallBedJson()[0]);  // declared, not exchanged
  ASSERT_TRUE(h.compiled(2));
  h.bye(1);
  EXPECT_FALSE(h.host().simulationRunning());
  ASSERT_TRUE(h.finished(2));
  EXPECT_EQ(h.finished(2)->reason(), "no component is exchanged any more and there is no end time");
  EXPECT_TRUE(h.closed(2));
}

TEST(CosimAssembly, TheAssemblyTimeoutIsReplayed) {
  ScratchDir dir;
  const std::filesystem::path record = dir.path() / "session.dlrec";
  {
    CosimHarness h(dir.path() / "live", {}, record);
    h.hello(1, "alpha");
    h.declare(1, boxJson(1e-5, 0.0, R"("coupling": {"expected_count": 100})", 2e-5));
    h.advanceClock(61.0);
    h.poll();
    ASSERT_EQ(h.host().simulationsFinished(), 1u);
  }
  const ReplayResult replayed = replaySession(record, CosimHarness::options(dir.path() / "replay", {}, {}));
  EXPECT_EQ(replayed.simulations, 1u);
  ASSERT_EQ(replayed.errors.size(), 1u);
  EXPECT_EQ(replayed.errors[0].code(), v1::Error::TIMEOUT);
  EXPECT_EQ(replayed.errors[0].field(), "box.simulation_box.coupling.expected_count");
}

}  // namespace
}  // namespace demlink::server::test
