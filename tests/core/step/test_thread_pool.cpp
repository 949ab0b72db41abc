// The thread pool survives the operating system refusing a thread: the threads it had
// started are joined and a ThreadStartError says how many ran, instead of std::terminate
// ("terminate called without an active exception") from a destroyed joinable thread.
#include <gtest/gtest.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <atomic>
#include <fstream>
#include <string>

#include "demlink/core/step/thread_pool.hpp"

namespace demlink::core {
namespace {

/// This process's virtual memory size [bytes] (VmSize in /proc/self/status).
long virtualBytes() {
  std::ifstream status("/proc/self/status");
  std::string line;
  while (std::getline(status, line)) {
    if (line.rfind("VmSize:", 0) == 0) return std::stol(line.substr(7)) * 1024;
  }
  return -1;
}

TEST(ThreadPool, RunsEveryPartOnce) {
  ThreadPool pool(2);
  std::atomic<int> sum{0};
  pool.run(100, [&](std::uint32_t part) { sum += static_cast<int>(part); });
  EXPECT_EQ(sum.load(), 99 * 100 / 2);
}

TEST(ThreadPool, AThreadTheSystemRefusesIsAnErrorNotTerminate) {
  // In a child process: an address-space limit leaves room for about two 8 MiB thread
  // stacks, then 64 threads are asked for. Exit 0: ThreadStartError caught with some
  // threads started and joined; a signal (SIGABRT from std::terminate) fails the test.
  const pid_t child = fork();
  ASSERT_GE(child, 0);
  if (child == 0) {
    const long now = virtualBytes();
    rlimit limit{};
    limit.rlim_cur = limit.rlim_max = static_cast<rlim_t>(now + (20L << 20));
    if (now <= 0 || setrlimit(RLIMIT_AS, &limit) != 0) _exit(3);
    try {
      ThreadPool pool(64);
      _exit(4);  // every thread started: the limit did not bite
    } catch (const ThreadStartError& error) {
      const bool sensible = error.started() >= 1 && error.started() < 64 &&
                            std::string(error.what()).find("of 64 threads") != std::string::npos;
      _exit(sensible ? 0 : 5);
    }
  }
  int status = 0;
  ASSERT_EQ(waitpid(child, &status, 0), child);
  ASSERT_TRUE(WIFEXITED(status)) << "the child died of signal " << (WIFSIGNALED(status) ? WTERMSIG(status) : 0);
  EXPECT_EQ(WEXITSTATUS(status), 0);
}

}  // namespace
}  // namespace demlink::core
