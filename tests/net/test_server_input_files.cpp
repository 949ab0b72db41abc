/// Files demlink-server reads must be regular files of bounded size: a FIFO would block
/// it forever and a device would be read until memory runs out. Each is refused at once
/// with exit 2 naming the option and the file; a corrupt session record is exit 2 too.
#include <gtest/gtest.h>
#include <sys/stat.h>
#include <sys/wait.h>

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

namespace demlink::server::test {
namespace {

struct Result {
  int exit_code = -1;
  std::string output;
  double seconds = 0.0;
};

/// demlink-server with `arguments`, bounded by `timeout` (a process that blocks is killed).
Result runServer(const std::vector<std::string>& arguments) {
  std::string command = "timeout -s KILL 20 \"" + std::string(DEMLINK_SERVER_EXE) + "\"";
  for (const std::string& argument : arguments) command.append(" \"").append(argument).append("\"");
  command.append(" 2>&1");
  Result result;
  const auto start = std::chrono::steady_clock::now();
  FILE* pipe = popen(command.c_str(), "r");
  if (pipe == nullptr) return result;
  char buffer[512];
  while (std::fgets(buffer, sizeof buffer, pipe) != nullptr) result.output += buffer;
  const int status = pclose(pipe);
  result.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  if (status != -1 && WIFEXITED(status)) result.exit_code = WEXITSTATUS(status);
  return result;
}

class ServerInputFiles : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = std::filesystem::path(::testing::TempDir()) / "demlink_server_input_files";
    std::filesystem::remove_all(dir_);
    std::filesystem::create_directories(dir_);
    fifo_ = (dir_ / "fifo").string();
    ASSERT_EQ(mkfifo(fifo_.c_str(), 0600), 0);
  }
  std::filesystem::path dir_;
  std::string fifo_;
};

TEST_F(ServerInputFiles, AFifoOrADeviceIsRefusedWithExitTwoNamingIt) {
  const std::vector<std::pair<std::vector<std::string>, std::string>> cases = {
      {{"--replay", fifo_}, "a FIFO"},
      {{"--restore", fifo_}, "a FIFO"},
      {{"--scene", fifo_}, "a FIFO"},
      {{"--replay", "/dev/zero"}, "a device"},
      {{"--restore", "/dev/zero"}, "a device"},
      {{"--scene", "/dev/zero"}, "a device"},
      {{"--replay", dir_.string()}, "a folder"},
  };
  for (const auto& [arguments, what] : cases) {
    const Result result = runServer(arguments);
    std::printf("%s %s: exit %d after %.3f s\n", arguments[0].c_str(), arguments[1].c_str(), result.exit_code,
                result.seconds);
    EXPECT_EQ(result.exit_code, 2) << arguments[0] << " " << arguments[1] << "\n" << result.output;
    EXPECT_NE(result.output.find(arguments[1]), std::string::npos) << result.output;
    EXPECT_NE(result.output.find("is not a regular file (" + what + ")"), std::string::npos) << result.output;
    EXPECT_LT(result.seconds, 10.0) << "refused before it is opened";
  }
}

TEST_F(ServerInputFiles, ACorruptSessionRecordIsExitTwo) {
  const std::filesystem::path record = dir_ / "corrupt.rec";
  std::ofstream(record, std::ios::binary) << std::string("\x05hello\xff\xff\xff", 9);
  const Result result = runServer({"--replay", record.string(), "--output", (dir_ / "out").string()});
  EXPECT_EQ(result.exit_code, 2) << result.output;
  EXPECT_NE(result.output.find("session record"), std::string::npos) << result.output;
}

}  // namespace
}  // namespace demlink::server::test
