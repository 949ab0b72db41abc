#pragma once
/// A child process (a server or a client program) with its stdout on a pipe, for the
/// end-to-end tests that run the C ABI's programs against the real demlink-server: the C
/// ABI's shared library carries its own copy of the protobuf messages and cannot share a
/// process with the server's. Every wait is bounded; a child still running when the object
/// goes is killed.
#include <signal.h>
#include <sys/select.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <string>
#include <vector>

namespace demlink::integration {

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

/// The "host:port" a demlink-server child announces on its first line ("demlink-server
/// listening on HOST:PORT"); empty strings when the line is not that.
inline std::pair<std::string, std::string> announcedAddress(const std::string& line) {
  const std::string prefix = "demlink-server listening on ";
  if (!line.starts_with(prefix)) return {};
  const std::string address = line.substr(prefix.size());
  const std::size_t colon = address.rfind(':');
  if (colon == std::string::npos) return {};
  return {address.substr(0, colon), address.substr(colon + 1)};
}

}  // namespace demlink::integration
