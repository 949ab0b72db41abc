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
      {{"--port"}, "--port = (missing)"},
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

/// Starts the server on an ephemeral port, reads the port from its first line, sends SIGINT.
TEST(DemlinkServerCli, ListensOnAnEphemeralPortAndExitsZeroOnSigint) {
  int fds[2];
  ASSERT_EQ(pipe(fds), 0);
  const std::string output = ::testing::TempDir() + "demlink_server_cli_out";
  const pid_t child = fork();
  ASSERT_NE(child, -1);
  if (child == 0) {
    dup2(fds[1], STDOUT_FILENO);
    close(fds[0]);
    close(fds[1]);
    execl(DEMLINK_SERVER_EXE, DEMLINK_SERVER_EXE, "--port", "0", "--output", output.c_str(),
          static_cast<char*>(nullptr));
    _exit(127);
  }
  close(fds[1]);
  // The first line, read with a bounded wait so a server that never starts fails the test.
  std::string firstLine;
  const TestClock::time_point deadline = TestClock::now() + kTimeout;
  while (firstLine.find('\n') == std::string::npos && TestClock::now() < deadline) {
    fd_set readable;
    FD_ZERO(&readable);
    FD_SET(fds[0], &readable);
    timeval wait{0, 100000};
    if (select(fds[0] + 1, &readable, nullptr, nullptr, &wait) <= 0) continue;
    char byte = 0;
    if (read(fds[0], &byte, 1) != 1) break;
    firstLine.push_back(byte);
  }
  const std::string prefix = "demlink-server listening on 127.0.0.1:";
  const bool started = firstLine.starts_with(prefix);
  EXPECT_TRUE(started) << firstLine;
  if (started) {
    const int port = std::atoi(firstLine.c_str() + prefix.size());
    EXPECT_GT(port, 0);
    TestClient client(static_cast<std::uint16_t>(port));
    EXPECT_TRUE(client.hello().has_value()) << "the server answers Hello";
  }
  kill(child, SIGINT);
  int status = -1;
  for (int k = 0; k < 300 && waitpid(child, &status, WNOHANG) == 0; ++k) usleep(10000);
  if (waitpid(child, &status, WNOHANG) == 0) {
    kill(child, SIGKILL);
    waitpid(child, &status, 0);
    ADD_FAILURE() << "demlink-server did not exit within 3 s of SIGINT";
  }
  close(fds[0]);
  EXPECT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 0) << "status " << status;
}

}  // namespace
}  // namespace demlink::server::test
