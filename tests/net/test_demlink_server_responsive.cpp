/// demlink-server stays responsive whatever one simulation does: each simulation steps on
/// its own thread, so a Hello is answered while an interval of the documented cap (1e8
/// steps) is stepped, SIGTERM cuts that interval short at a step boundary (outputs
/// flushed, SERVER_SHUTDOWN to its client, exit 0), and a second simulation exchanges
/// promptly beside a stalled one, even when only one may step at a time.
#include <gtest/gtest.h>
#include <signal.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <string>
#include <thread>
#include <vector>

#include "child_process.hpp"
#include "demlink/server/scene/scene_loader.hpp"
#include "scene_messages.hpp"
#include "test_client.hpp"

namespace demlink::server::test {
namespace {

using Seconds = std::chrono::duration<double>;

/// The process as a child on an ephemeral port.
struct Server {
  explicit Server(std::vector<std::string> arguments) : child(DEMLINK_SERVER_EXE, std::move(arguments)) {}
  [[nodiscard]] std::uint16_t port() const { return static_cast<std::uint16_t>(child.port); }
  integration::ServerChild child;
};

std::optional<v1::ServerMessage> hello(TestClient& client, const std::string& name, const std::string& simulation) {
  v1::ClientMessage message;
  message.mutable_hello()->set_protocol_version(v1::PROTOCOL_VERSION_CURRENT);
  message.mutable_hello()->set_client_name(name);
  message.mutable_hello()->set_simulation(simulation);
  client.send(message);
  return client.receive(10s);
}


std::uint32_t boxId(const v1::Compiled& compiled) {
  for (const v1::CompiledComponent& c : compiled.all_components()) {
    if (c.name() == "box") return c.id();
  }
  return 0;
}

/// A box exchanged every 1e3 s at dt = 1e-5 s: 1e8 steps per interval (the documented cap)
/// over a 10 x 10 x 10 lattice; its client sends the step-0 package, and the server steps
/// for longer than any test lasts.
void startHugeInterval(TestClient& client) {
  ASSERT_TRUE(hello(client, "huge", "huge").has_value());
  declareAll(client, R"({"components": [
    {"name": "box", "communication_interval": 1000, "simulation_box": {"time_step": 1e-5,
      "coupling": {"expected_count": 4}}},
    {"name": "glass", "material": {"density": 2500, "youngs_modulus": 5e6}},
    {"name": "floor", "plane": {"normal": {"z": 1}, "material": "glass"}},
    {"name": "spheres", "particle_lattice": {"material": "glass", "radius": 0.002, "spacing": 0.0041,
      "origin": {"x": 0.01, "y": 0.01, "z": 0.003}, "counts": {"nx": 10, "ny": 10, "nz": 10}}}]})");
  const std::optional<v1::ServerMessage> compiled = client.receive(60s);
  ASSERT_TRUE(compiled.has_value() && compiled->has_compiled()) << (compiled ? compiled->DebugString() : "none");
  const v1::CompiledComponent& box = compiled->compiled().all_components(0);
  ASSERT_EQ(compiled->compiled().components_size(), 4);
  ASSERT_EQ(boxId(compiled->compiled()) > 0, true);
  std::uint64_t interval = 0;
  for (const v1::CompiledComponent& c : compiled->compiled().all_components()) {
    if (c.name() == "box") interval = c.interval_steps();
  }
  ASSERT_EQ(interval, 100000000u) << box.DebugString();
  client.send(package(boxId(compiled->compiled()), 0));
  std::this_thread::sleep_for(300ms);  // the interval is under way
}

TEST(DemlinkServerResponsive, HelloIsAnsweredWhileAnIntervalOfTheCapSteps) {
  Server server({"--output", ::testing::TempDir() + "demlink_responsive_hello"});
  ASSERT_GT(server.port(), 0) << server.child.announced;
  TestClient huge(server.port());
  startHugeInterval(huge);
  if (::testing::Test::HasFatalFailure()) return;
  std::vector<double> waits;
  for (int k = 0; k < 5; ++k) {
    TestClient other(server.port());
    const auto sent = TestClock::now();
    const std::optional<v1::ServerMessage> welcome = hello(other, "other", "other " + std::to_string(k));
    waits.push_back(Seconds(TestClock::now() - sent).count());
    ASSERT_TRUE(welcome.has_value() && welcome->has_welcome()) << (welcome ? welcome->DebugString() : "none");
    // A stranger that wants to join the stepping simulation is told at once that it runs.
    TestClient late(server.port());
    const std::optional<v1::ServerMessage> refused = hello(late, "late", "huge");
    ASSERT_TRUE(refused.has_value() && refused->has_error()) << (refused ? refused->DebugString() : "none");
    EXPECT_EQ(refused->error().code(), v1::Error::OUT_OF_ORDER);
    EXPECT_NE(refused->error().message().find("is running"), std::string::npos) << refused->error().message();
  }
  std::sort(waits.begin(), waits.end());
  std::printf("Hello -> Welcome while a 1e8-step interval steps: median %.2f ms, max %.2f ms (5 tries)\n",
              waits[2] * 1e3, waits.back() * 1e3);
  // 100 ms is the target on an idle machine; the bound leaves room for a loaded one.
  EXPECT_LT(waits[2], 0.5) << "the network loop waited for the simulation";
}

TEST(DemlinkServerResponsive, SigtermCutsAnIntervalOfTheCapShortAndFlushesTheOutputs) {
  const std::filesystem::path output = std::filesystem::path(::testing::TempDir()) / "demlink_responsive_sigterm";
  std::filesystem::remove_all(output);
  Server server({"--output", output.string()});
  ASSERT_GT(server.port(), 0) << server.child.announced;
  TestClient huge(server.port());
  startHugeInterval(huge);
  if (::testing::Test::HasFatalFailure()) return;
  const auto signalled = TestClock::now();
  server.child.child.signal(SIGTERM);
  const int exitCode = server.child.child.waitForExit(20s);
  const double took = Seconds(TestClock::now() - signalled).count();
  std::printf("SIGTERM during a 1e8-step interval: exit %d after %.3f s\n", exitCode, took);
  EXPECT_EQ(exitCode, 0);
  // 2 s is the promise; the bound leaves room for a loaded machine writing the outputs.
  EXPECT_LT(took, 5.0);
  const std::optional<v1::ServerMessage> shutdown = huge.receive(5s);
  ASSERT_TRUE(shutdown.has_value() && shutdown->has_error()) << (shutdown ? shutdown->DebugString() : "none");
  EXPECT_EQ(shutdown->error().code(), v1::Error::SERVER_SHUTDOWN);
  const std::filesystem::path sim = output / "sim_001";
  EXPECT_TRUE(std::filesystem::is_regular_file(sim / "particles_final.csv"));
  EXPECT_TRUE(std::filesystem::is_regular_file(sim / "checkpoint_final.bin"));
}

/// One client runs a box exchanged every 10 steps to its end step (100 steps); returns the
/// slowest answer [s].
double runPromptSimulation(std::uint16_t port) {
  TestClient client(port);
  EXPECT_TRUE(hello(client, "prompt", "prompt").has_value());
  declareAll(client, R"({"components": [
    {"name": "box", "communication_interval": 1e-4, "simulation_box": {"time_step": 1e-5, "end_time": 1e-3,
      "coupling": {"expected_count": 4}}},
    {"name": "glass", "material": {"density": 2500, "youngs_modulus": 5e6}},
    {"name": "floor", "plane": {"normal": {"z": 1}, "material": "glass"}},
    {"name": "spheres", "particle_lattice": {"material": "glass", "radius": 0.002, "spacing": 0.006,
      "origin": {"x": 0.01, "y": 0.01, "z": 0.003}, "counts": {"nx": 2, "ny": 2, "nz": 2}}}]})");
  const std::optional<v1::ServerMessage> compiled = client.receive(30s);
  EXPECT_TRUE(compiled.has_value() && compiled->has_compiled()) << (compiled ? compiled->DebugString() : "none");
  if (!compiled || !compiled->has_compiled()) return 1e9;
  const std::uint32_t box = boxId(compiled->compiled());
  double slowest = 0.0;
  std::uint64_t step = 0;
  while (step < compiled->compiled().end_step()) {
    const auto sent = TestClock::now();
    client.send(package(box, step));
    const std::optional<v1::ServerMessage> answer = client.receive(30s);
    slowest = std::max(slowest, Seconds(TestClock::now() - sent).count());
    EXPECT_TRUE(answer.has_value() && answer->has_data()) << (answer ? answer->DebugString() : "none");
    if (!answer || !answer->has_data()) return 1e9;
    step = answer->data().step();
  }
  const std::optional<v1::ServerMessage> finished = client.receive(10s);
  EXPECT_TRUE(finished.has_value() && finished->has_finished()) << (finished ? finished->DebugString() : "none");
  return slowest;
}

TEST(DemlinkServerResponsive, ASecondSimulationExchangesPromptlyBesideAStalledOne) {
  // One stepping turn for both: the stalled one must give its turn away between its steps.
  Server server({"--max-stepping", "1", "--output", ::testing::TempDir() + "demlink_responsive_two"});
  ASSERT_GT(server.port(), 0) << server.child.announced;
  TestClient huge(server.port());
  startHugeInterval(huge);
  if (::testing::Test::HasFatalFailure()) return;
  const auto start = TestClock::now();
  const double slowest = runPromptSimulation(server.port());
  const double total = Seconds(TestClock::now() - start).count();
  std::printf("10 exchanges beside a stalled simulation (--max-stepping 1): slowest answer %.1f ms, all %.2f s\n",
              slowest * 1e3, total);
  // A turn is given away after 50 ms of stepping: each answer waits at most about that.
  EXPECT_LT(slowest, 2.0);
}

}  // namespace
}  // namespace demlink::server::test
