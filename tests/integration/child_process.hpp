#pragma once
/// A child process with its stdout on a pipe, for the end-to-end tests that run the real
/// server and a client program as separate processes (the C ABI's shared library carries its
/// own copy of the protobuf messages and cannot share a process with the server's). Every
/// wait is bounded; a child still running when the object goes away is killed.
#include <signal.h>
#include <sys/select.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cstdlib>
#include <functional>
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
    readUntil(timeout, 1, [&](const char* bytes, std::size_t) {
      if (bytes[0] == '\n') return false;
      line.push_back(bytes[0]);
      return true;
    });
    return line;
  }
  /// Everything the child writes to stdout until it closes it or the deadline passes.
  std::string readOutput(std::chrono::milliseconds timeout) {
    std::string text;
    readUntil(timeout, 4096, [&](const char* bytes, std::size_t n) {
      text.append(bytes, n);
      return true;
    });
    return text;
  }
  void signal(int number) const { kill(pid_, number); }
  [[nodiscard]] pid_t pid() const { return pid_; }
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
  /// Reads up to `chunk` bytes at a time from stdout and hands them to `take` until it returns
  /// false, the child closes stdout, or the deadline passes (polled every 50 ms).
  void readUntil(std::chrono::milliseconds timeout, std::size_t chunk,
                 const std::function<bool(const char*, std::size_t)>& take) {
    std::vector<char> buffer(chunk);
    const Clock::time_point deadline = Clock::now() + timeout;
    while (Clock::now() < deadline) {
      fd_set readable;
      FD_ZERO(&readable);
      FD_SET(out_, &readable);
      timeval wait{0, 50000};
      if (select(out_ + 1, &readable, nullptr, nullptr, &wait) <= 0) continue;
      const ssize_t n = read(out_, buffer.data(), chunk);
      if (n <= 0 || !take(buffer.data(), static_cast<std::size_t>(n))) return;
    }
  }

  pid_t pid_ = -1;
  int out_ = -1;
  bool exited_ = false;
};

/// The "host:port" a demlink-server child announced ("demlink-server listening on ...");
/// empty strings when the line does not match.
struct ServerAddress {
  std::string host;
  std::string port;
};
inline ServerAddress announcedAddress(const std::string& line) {
  const std::string prefix = "demlink-server listening on ";
  if (!line.starts_with(prefix)) return {};
  const std::string address = line.substr(prefix.size());
  const std::size_t colon = address.rfind(':');
  if (colon == std::string::npos) return {};
  return {address.substr(0, colon), address.substr(colon + 1)};
}

/// What runClientAgainstServer saw.
struct ClientRun {
  std::string announced;  ///< the server's first line
  std::string summary;    ///< the client's first line on stdout
  int client_exit = -1;   ///< -1: still running at the deadline (killed)
  int server_exit = -1;
};

/// Starts `demlink-server --port 0 --once --output out`, runs the client program whose
/// command line `command(host, port)` gives, and waits for both (the server exits once the
/// simulation ends). Bounded by `timeout` for the client and 20 s for the server after it.
inline ClientRun runClientAgainstServer(
    const std::string& serverExe, const std::string& out,
    const std::function<std::vector<std::string>(const std::string&, const std::string&)>& command,
    std::chrono::seconds timeout) {
  ClientRun run;
  Child server({serverExe, "--port", "0", "--once", "--output", out});
  run.announced = server.readLine(std::chrono::seconds(10));
  const ServerAddress address = announcedAddress(run.announced);
  if (std::atoi(address.port.c_str()) <= 0) return run;
  Child client(command(address.host, address.port));
  run.summary = client.readLine(timeout);
  run.client_exit = client.waitForExit(std::chrono::seconds(60));
  run.server_exit = server.waitForExit(std::chrono::seconds(20));
  return run;
}

/// demlink-server on an ephemeral loopback port with `arguments` after "--port 0": the
/// child and the port it announced (0 when it announced none within 10 s).
struct ServerChild {
  explicit ServerChild(const std::string& exe, std::vector<std::string> arguments)
      : child([&] {
          std::vector<std::string> line{exe, "--port", "0"};
          line.insert(line.end(), arguments.begin(), arguments.end());
          return line;
        }()) {
    announced = child.readLine(std::chrono::seconds(10));
    const ServerAddress address = announcedAddress(announced);
    host = address.host;
    port = std::atoi(address.port.c_str());
  }
  Child child;
  std::string announced;
  std::string host;
  int port = 0;
};

}  // namespace demlink::integration
