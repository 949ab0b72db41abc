/// The Modelica package's exact call sequence (tests/client/modelica_sequence.c, through
/// the C ABI) against the real demlink-server. Both run as child processes: the C ABI's
/// shared library carries its own copy of the protobuf messages and cannot share a process
/// with the server's (duplicate registration aborts), and this is how they run in practice.
/// Every wait is bounded; a child still running at its deadline is killed and the test fails.
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/select.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <string>
#include <vector>

namespace demlink::integration {
namespace {

using Clock = std::chrono::steady_clock;

/// A child process with its stdout on a pipe.
class Child {
 public:
  explicit Child(std::vector<std::string> line) {
    int fds[2];
    if (pipe(fds) != 0) return;
    std::vector<char*> argv;
    for (std::string& argument : line) argv.push_back(argument.data());
    argv.push_back(nullptr);
    pid_ = fork();
    if (pid_ == 0) {
      dup2(fds[1], STDOUT_FILENO);
      close(fds[0]);
      close(fds[1]);
      execv(argv[0], argv.data());
      _exit(127);
    }
    close(fds[1]);
    out_ = fds[0];
  }
  ~Child() {
    if (pid_ > 0 && !exited_) {
      kill(pid_, SIGKILL);
      waitpid(pid_, nullptr, 0);
    }
    if (out_ >= 0) close(out_);
  }
  Child(const Child&) = delete;
  Child& operator=(const Child&) = delete;

  /// Reads stdout until a newline or the deadline; returns the line so far.
  std::string readLine(std::chrono::milliseconds timeout) {
    std::string line;
    const Clock::time_point deadline = Clock::now() + timeout;
    while (Clock::now() < deadline) {
      fd_set readable;
      FD_ZERO(&readable);
      FD_SET(out_, &readable);
      timeval wait{0, 50000};
      if (select(out_ + 1, &readable, nullptr, nullptr, &wait) <= 0) continue;
      char byte = 0;
      if (read(out_, &byte, 1) != 1) break;
      if (byte == '\n') break;
      line.push_back(byte);
    }
    return line;
  }
  /// The exit code; -1 if it did not exit within `timeout` (it is then killed by the destructor).
  int waitForExit(std::chrono::milliseconds timeout) {
    const Clock::time_point deadline = Clock::now() + timeout;
    while (Clock::now() < deadline) {
      int status = 0;
      if (waitpid(pid_, &status, WNOHANG) == pid_) {
        exited_ = true;
        return WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
      }
      usleep(10000);
    }
    return -1;
  }

 private:
  pid_t pid_ = -1;
  int out_ = -1;
  bool exited_ = false;
};

TEST(ModelicaSequenceRealServer, CAbiCallSequenceRunsAgainstDemlinkServer) {
  const std::filesystem::path out =
      std::filesystem::temp_directory_path() / ("demlink_e2e_modelica_" + std::to_string(::getpid()));
  std::filesystem::remove_all(out);
  Child server({DEMLINK_SERVER_EXE, "--port", "0", "--once", "--output", out.string()});
  const std::string announced = server.readLine(std::chrono::seconds(10));
  const std::string prefix = "demlink-server listening on ";
  ASSERT_TRUE(announced.starts_with(prefix)) << announced;
  const std::string address = announced.substr(prefix.size());
  const std::size_t colon = address.rfind(':');
  ASSERT_NE(colon, std::string::npos) << announced;
  const std::string host = address.substr(0, colon);
  const std::string port = address.substr(colon + 1);
  ASSERT_GT(std::atoi(port.c_str()), 0) << announced;

  Child program({DEMLINK_MODELICA_SEQUENCE_EXE, host, port, "20"});
  const std::string summary = program.readLine(std::chrono::seconds(60));
  EXPECT_EQ(program.waitForExit(std::chrono::seconds(60)), 0) << summary;
  EXPECT_NE(summary.find("20 samples"), std::string::npos) << summary;
  EXPECT_EQ(server.waitForExit(std::chrono::seconds(10)), 0) << "--once: the server exits after the simulation";
  const std::filesystem::path sim = out / "sim_001";
  EXPECT_TRUE(std::filesystem::exists(sim / "checkpoint_final.bin")) << sim;
  EXPECT_TRUE(std::filesystem::exists(sim / "run_log.csv")) << sim;
  if (!::testing::Test::HasFailure()) std::filesystem::remove_all(out);
}

}  // namespace
}  // namespace demlink::integration
