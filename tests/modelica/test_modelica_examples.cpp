/// The Modelica examples' exact call sequences (bucket_digging_sequence.c,
/// truck_loading_sequence.c) against the real demlink-server, and the staged package's
/// Resources. Server and programs run as child processes (the C ABI's library carries its
/// own protobuf messages); every wait is bounded.
#include <gtest/gtest.h>
#include <unistd.h>

#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "child_process.hpp"

namespace demlink::modelica {
namespace {

std::string readFile(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

/// Runs `program HOST PORT [ARG]` against a fresh server; returns the program's summary line.
/// The server's quiet period is far longer than the clients' timeout (120 s), and the
/// models count no components: only every component's DeclarationsDone at the end of its
/// initial algorithm can start the compile.
std::string runAgainstServer(const std::string& program, const std::string& arg, const std::string& tag) {
  const std::filesystem::path out =
      std::filesystem::temp_directory_path() / ("demlink_modelica_" + tag + "_" + std::to_string(::getpid()));
  std::filesystem::remove_all(out);
  integration::ServerChild server(DEMLINK_SERVER_EXE, {"--once", "--output", out.string(), "--quiet-period", "1000"});
  if (server.port <= 0) {
    ADD_FAILURE() << "no port announced: " << server.announced;
    return {};
  }
  std::vector<std::string> command{program, server.host, std::to_string(server.port)};
  if (!arg.empty()) command.push_back(arg);
  integration::Child client(command);
  const std::string summary = client.readLine(std::chrono::seconds(600));
  EXPECT_EQ(client.waitForExit(std::chrono::seconds(60)), 0) << server.announced << "\n" << summary;
  // End time 0: the DEM run ends with the model's, when every component said Bye.
  EXPECT_EQ(server.child.waitForExit(std::chrono::seconds(20)), 0) << "the server ends when all components said Bye";
  if (!::testing::Test::HasFailure()) std::filesystem::remove_all(out);
  return summary;
}

TEST(ModelicaResources, StagedPackageHasHeaderAndLibrary) {
  const std::filesystem::path staged = DEMLINK_MODELICA_STAGED;
  const std::filesystem::path source = DEMLINK_MODELICA_SOURCE;
  EXPECT_EQ(readFile(staged / "Resources/Include/demlink/demlink_c.h"),
            readFile(source / "../../include/demlink/demlink_c.h"));
  EXPECT_EQ(readFile(staged / "Resources/Include/demlink_modelica.h"),
            readFile(source / "Resources/Include/demlink_modelica.h"));
  EXPECT_EQ(readFile(staged / "Resources/Library/linux64/libdemlink_c.so"), readFile(DEMLINK_C_LIBRARY));
  // The SONAME the linked simulation loads, next to the name the tool links.
  EXPECT_EQ(readFile(staged / "Resources/Library/linux64/libdemlink_c.so.1"), readFile(DEMLINK_C_LIBRARY));
  EXPECT_EQ(readFile(staged / "package.mo"), readFile(source / "package.mo"));
}

/// The bucket feels no force while clear of the bed, a drag against its motion above the
/// passive earth pressure bound in the gravel, lifts gravel out, and the bed's mass is
/// conserved (bucket_digging_sequence.c states the bounds).
TEST(ModelicaExamples, BucketDiggingFeelsTheGravel) {
  const std::string summary = runAgainstServer(DEMLINK_BUCKET_SEQUENCE_EXE,
                                               std::string(DEMLINK_MODELICA_SOURCE) + "/Resources/Data/bucket.stl", "bucket");
  EXPECT_NE(summary.find("301 samples"), std::string::npos) << summary;
}

/// The truck's load equals the source's delivered mass, the bed carries its weight and the
/// suspension settles by weight / stiffness (truck_loading_sequence.c states the bounds).
TEST(ModelicaExamples, TruckLoadEqualsDeliveredMass) {
  const std::string summary = runAgainstServer(
      DEMLINK_TRUCK_SEQUENCE_EXE, std::string(DEMLINK_MODELICA_SOURCE) + "/Resources/Data/truck_bed.stl", "truck");
  EXPECT_NE(summary.find("401 samples"), std::string::npos) << summary;
}

/// Run-time inputs from the model side: the delivered mass stops growing once the source is
/// switched off, a sink switched off keeps the pile lying in it and removes it once switched
/// on, a sensor moved and resized by its inputs weighs the pile (switched_source_sequence.c
/// states the bounds).
TEST(ModelicaExamples, SwitchedSourceSinkAndMovedSensor) {
  const std::string summary = runAgainstServer(DEMLINK_SWITCHED_SEQUENCE_EXE, "", "switched");
  EXPECT_NE(summary.find("401 samples"), std::string::npos) << summary;
}

}  // namespace
}  // namespace demlink::modelica
