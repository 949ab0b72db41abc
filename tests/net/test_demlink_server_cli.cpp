/// The demlink-server executable: bad options exit 2 naming the option and its value; a
/// started server prints its port and exits 0 on SIGINT.
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include "demlink/server/scene/scene_loader.hpp"
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
      {{"--port"}, "--port: 1 required N missing"},  // CLI11's wording
      {{"--bogus"}, "--bogus: unknown option"},
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
}

/// demlink-server as a child process on an ephemeral port; the port is read from its first
/// line with a bounded wait, so a server that never starts fails the test.
class ServerProcess {
 public:
  explicit ServerProcess(const std::vector<std::string>& arguments) {
    int fds[2];
    if (pipe(fds) != 0) return;
    std::vector<std::string> line = {DEMLINK_SERVER_EXE, "--port", "0"};
    line.insert(line.end(), arguments.begin(), arguments.end());
    std::vector<char*> argv;
    for (std::string& argument : line) argv.push_back(argument.data());
    argv.push_back(nullptr);
    pid_ = fork();
    if (pid_ == 0) {
      dup2(fds[1], STDOUT_FILENO);
      close(fds[0]);
      close(fds[1]);
      execv(DEMLINK_SERVER_EXE, argv.data());
      _exit(127);
    }
    close(fds[1]);
    out_ = fds[0];
    const TestClock::time_point deadline = TestClock::now() + kTimeout;
    while (first_line_.find('\n') == std::string::npos && TestClock::now() < deadline) {
      fd_set readable;
      FD_ZERO(&readable);
      FD_SET(out_, &readable);
      timeval wait{0, 100000};
      if (select(out_ + 1, &readable, nullptr, nullptr, &wait) <= 0) continue;
      char byte = 0;
      if (read(out_, &byte, 1) != 1) break;
      first_line_.push_back(byte);
    }
    const std::string prefix = "demlink-server listening on 127.0.0.1:";
    if (first_line_.starts_with(prefix)) port_ = static_cast<std::uint16_t>(std::atoi(first_line_.c_str() + prefix.size()));
  }
  ~ServerProcess() {
    if (pid_ > 0 && exit_status_ < 0) {
      kill(pid_, SIGKILL);
      waitpid(pid_, nullptr, 0);
    }
    if (out_ >= 0) close(out_);
  }
  ServerProcess(const ServerProcess&) = delete;
  ServerProcess& operator=(const ServerProcess&) = delete;

  /// 0 if the first line did not announce a port.
  [[nodiscard]] std::uint16_t port() const { return port_; }
  [[nodiscard]] const std::string& firstLine() const { return first_line_; }
  void signal(int number) const { kill(pid_, number); }
  /// The exit code, or -1 if the process did not exit within the timeout (it is killed).
  int waitForExit() {
    int status = 0;
    for (int k = 0; k < 300; ++k) {
      if (waitpid(pid_, &status, WNOHANG) == pid_) {
        exit_status_ = WIFEXITED(status) ? WEXITSTATUS(status) : 128;
        return exit_status_;
      }
      usleep(10000);
    }
    return -1;
  }

 private:
  pid_t pid_ = -1;
  int out_ = -1;
  std::string first_line_;
  std::uint16_t port_ = 0;
  int exit_status_ = -1;
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

/// The whole path with the real host: Hello, Declare, Compiled, the box's exchanges up to
/// the end step, Finished, and --once ending the process with exit code 0.
TEST(DemlinkServerCli, OnceRunsOneSimulationOverTcpAndExits) {
  ServerProcess server({"--once", "--output", ::testing::TempDir() + "demlink_server_cli_once"});
  ASSERT_GT(server.port(), 0) << server.firstLine();
  TestClient client(server.port());
  ASSERT_TRUE(client.hello().has_value());
  // The box expects all four components, so compilation needs no quiet period.
  const v1::Scene scene = parseSceneJson(R"({"components": [
    {"name": "box", "communication_interval": 1e-4, "simulation_box": {"time_step": 1e-5, "end_time": 1e-3,
      "coupling": {"expected_count": 4}}},
    {"name": "glass", "material": {"density": 2500, "youngs_modulus": 5e6}},
    {"name": "floor", "plane": {"normal": {"z": 1}, "material": "glass"}},
    {"name": "spheres", "particle_lattice": {"material": "glass", "radius": 0.002, "spacing": 0.006,
      "origin": {"x": 0.01, "y": 0.01, "z": 0.003}, "counts": {"nx": 2, "ny": 2, "nz": 2}}}]})",
                                         "cli test scene");
  for (const v1::ComponentDeclaration& component : scene.components()) {
    v1::ClientMessage declare;
    *declare.mutable_declare()->mutable_component() = component;
    client.send(declare);
  }
  const std::optional<v1::ServerMessage> compiled = client.receive();
  ASSERT_TRUE(compiled.has_value() && compiled->has_compiled()) << (compiled ? compiled->DebugString() : "none");
  std::uint32_t box = 0;
  std::uint64_t interval = 0;
  for (const v1::CompiledComponent& component : compiled->compiled().components()) {
    if (component.name() == "box") {
      box = component.id();
      interval = component.interval_steps();
    }
  }
  ASSERT_GT(interval, 0u);
  const std::uint64_t endStep = compiled->compiled().end_step();
  std::uint64_t step = 0;
  while (step < endStep) {
    v1::ClientMessage package;
    package.mutable_data()->set_component_id(box);
    package.mutable_data()->set_step(step);
    client.send(package);
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
  client.close();
  EXPECT_EQ(server.waitForExit(), 0) << "--once: the process ends after its simulation";
}

}  // namespace
}  // namespace demlink::server::test
