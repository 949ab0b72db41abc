/// The demlink-server executable: bad options exit 2 naming the option and its value; a
/// started server prints its port and exits 0 on SIGINT.
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <array>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <thread>
#include <string>
#include <vector>

#include "demlink/server/net/asio.hpp"
#include "demlink/server/scene/scene_loader.hpp"
#include "child_process.hpp"
#include "scene_messages.hpp"
#include "test_client.hpp"

namespace demlink::server::test {
namespace {

struct Result {
  int exit_code = -1;
  std::string output;  ///< stdout and stderr
};

/// Runs demlink-server with `arguments` (each quoted) and collects its output.
Result runServer(const std::vector<std::string>& arguments) {
  std::string command;
  command.append("\"").append(DEMLINK_SERVER_EXE).append("\"");
  for (const std::string& argument : arguments) command.append(" \"").append(argument).append("\"");
  command.append(" 2>&1");
  Result result;
  FILE* pipe = popen(command.c_str(), "r");
  if (pipe == nullptr) return result;
  char buffer[512];
  while (std::fgets(buffer, sizeof buffer, pipe) != nullptr) result.output += buffer;
  const int status = pclose(pipe);
  if (status != -1 && WIFEXITED(status)) result.exit_code = WEXITSTATUS(status);
  return result;
}

TEST(DemlinkServerCli, BadOptionsExitTwoNamingOptionAndValue) {
  const std::vector<std::pair<std::vector<std::string>, std::string>> cases = {
      {{"--port", "http"}, "--port = http"},
      {{"--port=70000"}, "--port = 70000"},
      {{"--listen", "localhost:80"}, "--listen = localhost:80"},
      {{"--timeout", "-1"}, "--timeout = -1"},
      {{"--quiet-period", "nan"}, "--quiet-period = nan"},
      {{"--max-frame-bytes", "0"}, "--max-frame-bytes = 0"},
      {{"--spin-wait-us", "-1"}, "--spin-wait-us = -1"},
      {{"--spin-wait-us", "1e6"}, "--spin-wait-us = 1e6"},
      {{"--port"}, "--port: 1 required N missing"},  // CLI11's wording
      {{"--bogus"}, "--bogus: unknown option"},
      {{"--restore", "no/such/checkpoint.bin"}, "--restore = no/such/checkpoint.bin: no such file"},
      {{"--view", "0", "--view-max-connections", "0"}, "--view-max-connections = 0: not a whole number in 1..1024"},
      {{"--view", "0", "--view-max-rate", "-3"}, "--view-max-rate = -3: frames per second must be > 0 and <= 120"},
      {{"--view", "0", "--view-max-bytes-per-second", "1e2"}, "--view-max-bytes-per-second = 1e2: must be >= 1000"},
  };
  for (const auto& [arguments, expected] : cases) {
    const Result result = runServer(arguments);
    EXPECT_EQ(result.exit_code, 2) << arguments.front() << "\n" << result.output;
    EXPECT_NE(result.output.find("error: "), std::string::npos) << result.output;
    EXPECT_NE(result.output.find(expected), std::string::npos) << result.output;
  }
}

TEST(DemlinkServerCli, HelpExitsZero) {
  const Result result = runServer({"--help"});
  EXPECT_EQ(result.exit_code, 0);
  EXPECT_NE(result.output.find("--max-frame-bytes"), std::string::npos) << result.output;
  EXPECT_NE(result.output.find("--spin-wait-us"), std::string::npos) << result.output;
}

/// demlink-server as a child process on an ephemeral port (integration::ServerChild); the
/// port is read from its first line with a bounded wait, so a server that never starts fails
/// the test.
class ServerProcess {
 public:
  explicit ServerProcess(std::vector<std::string> arguments) : server_(DEMLINK_SERVER_EXE, std::move(arguments)) {}

  /// 0 if the first line did not announce a port.
  [[nodiscard]] std::uint16_t port() const { return static_cast<std::uint16_t>(server_.port); }
  [[nodiscard]] const std::string& firstLine() const { return server_.announced; }
  void signal(int number) const { server_.child.signal(number); }
  [[nodiscard]] pid_t pid() const { return server_.child.pid(); }
  /// Everything the server printed after its first line, up to its exit (or the timeout).
  std::string readOutput(std::chrono::milliseconds timeout) { return server_.child.readOutput(timeout); }
  /// The exit code, or -1 if the process did not exit within 3 s (it is then killed).
  int waitForExit() { return server_.child.waitForExit(std::chrono::seconds(3)); }

 private:
  integration::ServerChild server_;
};

TEST(DemlinkServerCli, ListensOnAnEphemeralPortAndExitsZeroOnSigint) {
  ServerProcess server({"--output", ::testing::TempDir() + "demlink_server_cli_sigint"});
  ASSERT_GT(server.port(), 0) << server.firstLine();
  {
    TestClient client(server.port());
    const std::optional<v1::ServerMessage> welcome = client.hello();
    ASSERT_TRUE(welcome.has_value());
    EXPECT_TRUE(welcome->has_welcome()) << welcome->DebugString();
  }
  server.signal(SIGINT);
  EXPECT_EQ(server.waitForExit(), 0) << "SIGINT must end the server cleanly within 3 s";
}


/// The view's caps come from the command line: --view-max-connections 1 refuses a second
/// connection with HTTP 503, and the page's hello carries --view-max-rate.
TEST(DemlinkServerCli, ViewCapsComeFromTheCommandLine) {
  integration::Child server({DEMLINK_SERVER_EXE, "--port", "0", "--output", ::testing::TempDir() + "demlink_view_caps",
                             "--view", "127.0.0.1:0", "--view-max-connections", "1", "--view-max-rate", "5"});
  const std::string listening = server.readLine(std::chrono::seconds(10));
  ASSERT_TRUE(listening.starts_with("demlink-server listening on ")) << listening;  // the port comes first
  const std::string viewLine = server.readLine(std::chrono::seconds(10));
  const std::string prefix = "demlink-server view at http://127.0.0.1:";
  ASSERT_TRUE(viewLine.starts_with(prefix)) << viewLine;
  const auto port = static_cast<std::uint16_t>(std::stoi(viewLine.substr(prefix.size())));
  asio::io_context io;
  const asio::ip::tcp::endpoint view(asio::ip::make_address("127.0.0.1"), port);
  asio::ip::tcp::socket page(io);
  page.connect(view);
  asio::write(page, asio::buffer(std::string(
                        "GET /ws HTTP/1.1\r\nHost: x\r\nUpgrade: websocket\r\nConnection: Upgrade\r\n"
                        "Sec-WebSocket-Key: dGhlIHNhbXBsZSBub25jZQ==\r\nSec-WebSocket-Version: 13\r\n\r\n")));
  // The handshake and the hello (unmasked text frames: their JSON shows in the bytes).
  std::string received;
  std::array<char, 4096> buffer{};
  while (received.find(R"("maxRate":)") == std::string::npos && received.size() < 65536) {
    received.append(buffer.data(), page.read_some(asio::buffer(buffer)));
  }
  EXPECT_NE(received.find("101 Switching Protocols"), std::string::npos) << received;
  EXPECT_NE(received.find(R"("maxRate":5})"), std::string::npos) << received;
  // The page holds the one connection allowed: the next is refused.
  asio::ip::tcp::socket second(io);
  second.connect(view);
  asio::write(second, asio::buffer(std::string("GET / HTTP/1.1\r\nHost: x\r\n\r\n")));
  std::string answer;
  asio::error_code error;
  while (!error) answer.append(buffer.data(), second.read_some(asio::buffer(buffer), error));
  EXPECT_TRUE(answer.starts_with("HTTP/1.1 503 Service Unavailable")) << answer;
  EXPECT_NE(answer.find("at most 1 connections"), std::string::npos) << answer;
  server.signal(SIGINT);
  EXPECT_EQ(server.waitForExit(std::chrono::seconds(5)), 0);
}

/// The id and interval of `name` in `compiled` (every component of the simulation).
std::pair<std::uint32_t, std::uint64_t> componentOf(const v1::Compiled& compiled, const std::string& name) {
  for (const v1::CompiledComponent& component : compiled.all_components()) {
    if (component.name() == name) return {component.id(), component.interval_steps()};
  }
  return {0, 0};
}

/// One client runs a small simulation (a box exchanged every 10 steps, 8 spheres) to its
/// end step; `pause` between exchanges (progress lines while the server waits for it).
void runSmallSimulation(std::uint16_t port, std::chrono::milliseconds pause = 0ms) {
  TestClient client(port);
  ASSERT_TRUE(client.hello().has_value());
  // The box expects all four components, so compilation needs no quiet period.
  declareAll(client, R"({"components": [
    {"name": "box", "communication_interval": 1e-4, "simulation_box": {"time_step": 1e-5, "end_time": 1e-3,
      "coupling": {"expected_count": 4}}},
    {"name": "glass", "material": {"density": 2500, "youngs_modulus": 5e6}},
    {"name": "floor", "plane": {"normal": {"z": 1}, "material": "glass"}},
    {"name": "spheres", "particle_lattice": {"material": "glass", "radius": 0.002, "spacing": 0.006,
      "origin": {"x": 0.01, "y": 0.01, "z": 0.003}, "counts": {"nx": 2, "ny": 2, "nz": 2}}}]})");
  const std::optional<v1::ServerMessage> compiled = client.receive();
  ASSERT_TRUE(compiled.has_value() && compiled->has_compiled()) << (compiled ? compiled->DebugString() : "none");
  const auto [box, interval] = componentOf(compiled->compiled(), "box");
  ASSERT_GT(interval, 0u);
  const std::uint64_t endStep = compiled->compiled().end_step();
  std::uint64_t step = 0;
  while (step < endStep) {
    if (pause.count() > 0) std::this_thread::sleep_for(pause);
    client.send(package(box, step));
    const std::optional<v1::ServerMessage> answer = client.receive();
    ASSERT_TRUE(answer.has_value() && answer->has_data()) << (answer ? answer->DebugString() : "none");
    EXPECT_EQ(answer->data().step(), step + interval) << "answered at the end of the interval";
    EXPECT_EQ(answer->data().simulation_box().particle_count(), 8u) << "no source or sink: the 2x2x2 lattice stays";
    step = answer->data().step();
  }
  const std::optional<v1::ServerMessage> finished = client.receive();
  ASSERT_TRUE(finished.has_value() && finished->has_finished()) << (finished ? finished->DebugString() : "none");
  EXPECT_EQ(finished->finished().step(), endStep);
  EXPECT_TRUE(client.waitForClose());
}

/// The whole path with the real host: Hello, Declare, Compiled, the box's exchanges up to
/// the end step, Finished, and --once ending the process with exit code 0.
TEST(DemlinkServerCli, OnceRunsOneSimulationOverTcpAndExits) {
  ServerProcess server({"--once", "--output", ::testing::TempDir() + "demlink_server_cli_once"});
  ASSERT_GT(server.port(), 0) << server.firstLine();
  runSmallSimulation(server.port());
  EXPECT_EQ(server.waitForExit(), 0) << "--once: the process ends after its simulation";
}

TEST(DemlinkServerCli, MaxSimulationsEndsTheServerAfterTheNth) {
  ServerProcess server({"--max-simulations", "2", "--output", ::testing::TempDir() + "demlink_server_cli_max"});
  ASSERT_GT(server.port(), 0) << server.firstLine();
  runSmallSimulation(server.port());
  {
    TestClient second(server.port());
    const std::optional<v1::ServerMessage> welcome = second.hello();
    ASSERT_TRUE(welcome.has_value() && welcome->has_welcome()) << "still serving after the first";
    EXPECT_EQ(welcome->welcome().simulation_number(), 2u);
  }  // leaves before declaring: the second simulation has not started
  runSmallSimulation(server.port());
  EXPECT_EQ(server.waitForExit(), 0) << "the process ends after its second simulation";
  const Result both = runServer({"--once", "--max-simulations", "3"});
  EXPECT_EQ(both.exit_code, 2) << both.output;
  EXPECT_NE(both.output.find("--once"), std::string::npos) << both.output;
}

TEST(DemlinkServerCli, ABadSceneFileStopsTheServerAtStartUp) {
  const std::filesystem::path scene = std::filesystem::path(::testing::TempDir()) / "demlink_server_bad_scene.json";
  std::ofstream(scene) << R"({"components": [{"name": "glass", "material": {"density": -2500}}]})";
  const Result result = runServer({"--port", "0", "--scene", scene.string()});
  EXPECT_EQ(result.exit_code, 2) << result.output;
  EXPECT_NE(result.output.find("density = -2500"), std::string::npos) << result.output;
  EXPECT_EQ(result.output.find("listening"), std::string::npos) << "refused before listening";

  // No simulation_box (a client declares it): the rest is still checked, a pit included.
  std::ofstream(scene) << R"({"components": [{"name": "gravel", "material": {}},
    {"name": "pit", "pit_generator": {"material": "gravel", "lower": {}, "upper": {"x": 1, "y": 1, "z": 1}}}]})";
  const Result pit = runServer({"--port", "0", "--scene", scene.string()});
  EXPECT_EQ(pit.exit_code, 2) << pit.output;
  EXPECT_NE(pit.output.find("pit_generator.sizes"), std::string::npos) << pit.output;
}

/// A running simulation prints progress lines naming whom it waits for.
TEST(DemlinkServerCli, ProgressLinesNameTheComponentWaitedFor) {
  ServerProcess server({"--once", "--progress", "0.2", "--output", ::testing::TempDir() + "demlink_server_cli_progress"});
  ASSERT_GT(server.port(), 0) << server.firstLine();
  runSmallSimulation(server.port(), 150ms);
  const std::string output = server.readOutput(10000ms);
  EXPECT_EQ(server.waitForExit(), 0);
  EXPECT_NE(output.find("steps/s"), std::string::npos) << output;
  EXPECT_NE(output.find("8 particles"), std::string::npos) << output;
  EXPECT_NE(output.find("exchanges/s, waiting for \"box\" of client \"test\""), std::string::npos) << output;
}

TEST(DemlinkServerCli, AnIncompleteAssemblyTimesOutAndTheServerGoesOn) {
  ServerProcess server({"--assembly-timeout", "0.5", "--output", ::testing::TempDir() + "demlink_server_cli_assembly"});
  ASSERT_GT(server.port(), 0) << server.firstLine();
  TestClient waiting(server.port());
  ASSERT_TRUE(waiting.hello().has_value());
  declareAll(waiting, R"({"components": [{"name": "box", "communication_interval": 1e-4,
    "simulation_box": {"time_step": 1e-5, "coupling": {"expected_count": 100}}}]})");
  const std::optional<v1::ServerMessage> error = waiting.receive(10000ms);
  ASSERT_TRUE(error.has_value() && error->has_error()) << (error ? error->DebugString() : "none");
  EXPECT_EQ(error->error().code(), v1::Error::TIMEOUT);
  EXPECT_EQ(error->error().field(), "box.simulation_box.coupling.expected_count");
  EXPECT_TRUE(waiting.waitForClose());
  TestClient next(server.port());
  const std::optional<v1::ServerMessage> welcome = next.hello();
  ASSERT_TRUE(welcome.has_value() && welcome->has_welcome());
  EXPECT_EQ(welcome->welcome().simulation_number(), 2u);
}

/// Peak resident memory of process `pid` [bytes] (VmHWM).
std::size_t peakResidentBytes(pid_t pid) {
  std::ifstream status("/proc/" + std::to_string(pid) + "/status");
  std::string line;
  while (std::getline(status, line)) {
    if (line.starts_with("VmHWM:")) return std::stoull(line.substr(6)) * 1024u;
  }
  return 0;
}

/// A client that sends its packages for 1500 exchanges of a 10 000-particle view (about
/// 176 kB each) without reading: the server holds its input back once 16 MiB wait for it,
/// the host waits for its next package and ends the simulation with TIMEOUT naming the view
/// (the driver, whose box is not exchanged, reads it); the server's peak memory stays far
/// below the 264 MB the unread answers would take.
TEST(DemlinkServerCli, AClientThatStopsReadingEndsWithTimeoutAndBoundedMemory) {
  ServerProcess server({"--timeout", "3", "--output", ::testing::TempDir() + "demlink_server_cli_backpressure"});
  ASSERT_GT(server.port(), 0) << server.firstLine();
  TestClient driver(server.port());
  TestClient stalled(server.port());
  ASSERT_TRUE(driver.hello("driver").has_value());
  ASSERT_TRUE(stalled.hello("stalled").has_value());
  declareAll(driver, R"({"components": [
    {"name": "box", "simulation_box": {"time_step": 1e-5, "end_time": 1,
      "coupling": {"expected_count": 4}}},
    {"name": "glass", "material": {"density": 2500, "youngs_modulus": 5e6}},
    {"name": "spheres", "particle_lattice": {"material": "glass", "radius": 0.002, "spacing": 0.006,
      "counts": {"nx": 25, "ny": 20, "nz": 20}}}]})");
  declareAll(stalled, R"({"components": [{"name": "view", "communication_interval": 1e-5,
    "particle_view": {"max_count": 10000}}]})");
  const std::optional<v1::ServerMessage> compiled = driver.receive(60000ms);
  ASSERT_TRUE(compiled.has_value() && compiled->has_compiled()) << (compiled ? compiled->DebugString() : "none");
  const std::size_t baseline = peakResidentBytes(server.pid());
  const auto [view, viewInterval] = componentOf(compiled->compiled(), "view");
  ASSERT_EQ(viewInterval, 1u);
  std::string burst;
  for (std::uint64_t step = 0; step < 1500; ++step) wire::appendFrame(package(view, step), burst);
  stalled.sendRaw(burst);
  const std::optional<v1::ServerMessage> answer = driver.receive(120000ms);
  ASSERT_TRUE(answer.has_value() && answer->has_error()) << (answer ? answer->DebugString() : "none");
  EXPECT_EQ(answer->error().code(), v1::Error::TIMEOUT) << answer->error().message();
  EXPECT_EQ(answer->error().component(), "view");
  EXPECT_NE(answer->error().message().find("\"stalled\""), std::string::npos) << answer->error().message();
  const std::size_t growth = peakResidentBytes(server.pid()) - baseline;
  EXPECT_LT(growth, 100u << 20) << "the server's peak RSS grew by " << growth << " bytes";
  EXPECT_TRUE(stalled.waitForClose(10000ms)) << "the stalled client is closed after the grace";
  TestClient next(server.port());
  const std::optional<v1::ServerMessage> welcome = next.hello();
  ASSERT_TRUE(welcome.has_value() && welcome->has_welcome()) << "the server keeps serving";
}

}  // namespace
}  // namespace demlink::server::test
