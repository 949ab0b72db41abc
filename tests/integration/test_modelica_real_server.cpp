/// The Modelica package's exact call sequence (tests/client/modelica_sequence.c, through
/// the C ABI) against the real demlink-server. Both run as child processes: the C ABI's
/// shared library carries its own copy of the protobuf messages and cannot share a process
/// with the server's (duplicate registration aborts), and this is how they run in practice.
/// Every wait is bounded; a child still running at its deadline is killed and the test fails.
#include <gtest/gtest.h>
#include <unistd.h>

#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <string>

#include "child_process.hpp"

namespace demlink::integration {
namespace {

TEST(ModelicaSequenceRealServer, CAbiCallSequenceRunsAgainstDemlinkServer) {
  const std::filesystem::path out =
      std::filesystem::temp_directory_path() / ("demlink_e2e_modelica_" + std::to_string(::getpid()));
  std::filesystem::remove_all(out);
  Child server({DEMLINK_SERVER_EXE, "--port", "0", "--once", "--output", out.string()});
  const std::string announced = server.readLine(std::chrono::seconds(10));
  const auto [host, port] = announcedAddress(announced);
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
