/// The win64 FMU under wine (tests/windows/CMakeLists.txt): the win64 build of the FMU test
/// master (tests/fmu/fmu_master.cpp, the same checks as on Linux) unpacks the packaged test
/// FMU, loads its binaries/win64 library and steps it against the Linux demlink-server over
/// loopback. The wine prefix is booted by the fixture windows_wine_prefix.
#include <gtest/gtest.h>
#include <unistd.h>

#include <chrono>
#include <filesystem>
#include <string>
#include <vector>

#include "child_process.hpp"
#include "fmu_master_summaries.hpp"

namespace {

/// Runs the win64 fmu_master under wine on `fmu` (with `extra` arguments) against a fresh
/// demlink-server and checks that both exit 0; returns the master's summary line.
std::string runMasterUnderWine(const std::string& fmu, const std::string& tag, const std::vector<std::string>& extra) {
  const std::filesystem::path out =
      std::filesystem::temp_directory_path() / ("demlink_wine_fmu_" + tag + "_" + std::to_string(::getpid()));
  std::filesystem::remove_all(out);
  const demlink::integration::ClientRun run = demlink::integration::runClientAgainstServer(
      DEMLINK_SERVER_EXE, (out / "server").string(),
      [&](const std::string& host, const std::string& port) {
        std::vector<std::string> line = {"/usr/bin/env", "WINEPREFIX=" DEMLINK_WINE_PREFIX, "WINEDEBUG=-all",
                                         DEMLINK_WINE, DEMLINK_WIN64_FMU_MASTER, fmu, host, port,
                                         (out / "unpacked").string()};
        line.insert(line.end(), extra.begin(), extra.end());
        return line;
      },
      std::chrono::seconds(400));
  EXPECT_EQ(run.client_exit, 0) << run.announced << "\n" << run.summary;
  EXPECT_EQ(run.server_exit, 0) << "the run ends and the server exits";
  if (!::testing::Test::HasFailure()) std::filesystem::remove_all(out);
  return run.summary;
}

/// The plate lowered into the gravel bed (tests/fmu/plate_in_bed.cfg): the master's
/// physical checks hold (its exit code) over all the steps of the Linux test.
TEST(FmuUnderWine, PlateLoweredIntoBedFeelsUpwardForce) {
  const std::string summary = runMasterUnderWine(DEMLINK_TEST_FMU, "plate", {});
  EXPECT_NE(summary.find(demlink::fmu::kPlateSummary), std::string::npos) << summary;
}

/// The server's end of the run is fmi2Discard with fmi2Terminated on Windows too.
TEST(FmuUnderWine, ServerEndOfRunIsDiscardWithTerminated) {
  const std::string summary = runMasterUnderWine(DEMLINK_SHORT_FMU, "end", {"end"});
  EXPECT_NE(summary.find(demlink::fmu::kEndSummary), std::string::npos) << summary;
}

/// The receive-first option's timing (box.time == t after fmi2DoStep(t, h)).
TEST(FmuUnderWine, ReceiveFirstOrderLagsOneInterval) {
  const std::string summary = runMasterUnderWine(DEMLINK_SHORT_RECEIVE_FIRST_FMU, "receive_first", {"end"});
  EXPECT_NE(summary.find(demlink::fmu::kReceiveFirstEndSummary), std::string::npos) << summary;
}

}  // namespace
