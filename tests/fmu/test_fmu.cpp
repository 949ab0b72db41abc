/// The DEMLink FMU (client/fmu, docs/fmi.md): the configuration and its FMI variables, the
/// archive, and the packaged FMU stepped by a small FMI 2.0 master (fmu_master) against
/// the real demlink-server, with physical checks. The master runs as a child process:
/// the FMU loads libdemlink_c.so, which carries its own protobuf messages.
#include <gtest/gtest.h>
#include <unistd.h>

#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <stdexcept>
#include <string>
#include <vector>

#include "child_process.hpp"
#include "fmu_config.hpp"
#include "fmu_master_summaries.hpp"
#include "zip_writer.hpp"

namespace demlink::fmu {
namespace {

TEST(FmuConfig, PlateConfigurationGivesTheBodyAndBoxVariables) {
  const FmuConfig config = readConfigFile(DEMLINK_FMU_TEST_CONFIG);
  EXPECT_EQ(config.model_identifier, "DEMLinkPlateInBed");
  EXPECT_DOUBLE_EQ(config.interval_s, 0.002);
  ASSERT_EQ(config.components.size(), 5u);
  EXPECT_EQ(config.components[4].strings, (std::vector<std::string>{"gravel", ""}));
  const std::vector<Variable> variables = variablesOf(config);
  // 4 parameters; box: 3 inputs + 1 + 4 outputs; rigid body: 13 inputs + 19 outputs.
  ASSERT_EQ(variables.size(), 4u + 8u + 32u);
  int inputs = 0;
  int outputs = 0;
  for (const Variable& v : variables) {
    inputs += v.causality == Causality::kInput ? 1 : 0;
    outputs += v.causality == Causality::kOutput ? 1 : 0;
  }
  EXPECT_EQ(inputs, 16);
  EXPECT_EQ(outputs, 24);
  // Start values of the body's inputs are its declared pose; the box's gravity its declared one.
  for (const Variable& v : variables) {
    if (v.name == "plate.position[3]") {
      EXPECT_DOUBLE_EQ(v.start, 0.11);
    } else if (v.name == "plate.orientation[1]") {
      EXPECT_DOUBLE_EQ(v.start, 1.0);
    } else if (v.name == "box.gravity[3]") {
      EXPECT_DOUBLE_EQ(v.start, -9.81);
    }
  }
}

TEST(FmuConfig, ValueReferencesAreUniqueWithinEachType) {
  const std::vector<Variable> variables = variablesOf(readConfigFile(DEMLINK_FMU_TEST_CONFIG));
  std::uint32_t next[3] = {0, 0, 0};
  for (const Variable& v : variables) {
    EXPECT_EQ(v.value_reference, next[static_cast<int>(v.type)]++) << v.name;
  }
}

TEST(FmuConfig, BadInputIsNamedWithLineFieldAndValue) {
  const auto message = [](const std::string& text) {
    try {
      (void)parseConfig(text);
    } catch (const std::invalid_argument& e) {
      return std::string(e.what());
    }
    return std::string("accepted");
  };
  const std::string head = "model M\ninterval 0.01\n";
  EXPECT_NE(message("model 1bad\n").find("model = '1bad'"), std::string::npos);
  EXPECT_NE(message(head + "component particle_view v\n").find("line 3"), std::string::npos);
  EXPECT_NE(message(head + "component rigid_body b reals=1,x\n").find("b.reals = 'x'"), std::string::npos);
  EXPECT_NE(message(head + "component material a\ncomponent material a\n").find("declared twice"), std::string::npos);
  EXPECT_NE(message("model M\ncomponent material a\n").find("interval"), std::string::npos);
  EXPECT_NE(message(head + "port 70000\n").find("port = '70000'"), std::string::npos);
  EXPECT_NE(message(head).find("no component"), std::string::npos);
}

TEST(FmuConfig, GuidChangesWithTheText) {
  EXPECT_EQ(guidOf("model A"), guidOf("model A"));
  EXPECT_NE(guidOf("model A"), guidOf("model B"));
  EXPECT_EQ(guidOf("x").size(), 38u);
}

TEST(FmuConfig, ModelDescriptionListsEveryOutputOnce) {
  const FmuConfig config = readConfigFile(DEMLINK_FMU_TEST_CONFIG);
  const std::string xml = modelDescriptionXml(config, "{g}");
  EXPECT_NE(xml.find("fmiVersion=\"2.0\""), std::string::npos);
  EXPECT_NE(xml.find("modelIdentifier=\"DEMLinkPlateInBed\""), std::string::npos);
  EXPECT_NE(xml.find("stepSize=\"0.002\""), std::string::npos);
  std::size_t unknowns = 0;
  for (std::size_t at = xml.find("<Unknown "); at != std::string::npos; at = xml.find("<Unknown ", at + 1)) ++unknowns;
  EXPECT_EQ(unknowns, 2u * 24u);  // Outputs and InitialUnknowns
}

TEST(FmuZip, RoundTripAndCrc) {
  EXPECT_EQ(crc32("123456789"), 0xCBF43926u);  // the CRC-32 check value
  const std::vector<ZipEntry> entries = {{"a.txt", "hello"}, {"dir/b.so", std::string(1000, '\0')}};
  const std::vector<ZipEntry> back = readStoredZip(zipArchive(entries));
  ASSERT_EQ(back.size(), 2u);
  EXPECT_EQ(back[1].name, "dir/b.so");
  EXPECT_EQ(back[1].data, entries[1].data);
  std::string corrupt = zipArchive(entries);
  corrupt[30 + 5] = 'X';  // first byte of "hello"
  EXPECT_THROW(readStoredZip(corrupt), std::invalid_argument);
}

TEST(FmuArchive, PackagedFmuHasTheStandardLayout) {
  const std::vector<ZipEntry> entries = readStoredZip(readFile(DEMLINK_TEST_FMU));
  std::vector<std::string> names;
  for (const ZipEntry& e : entries) names.push_back(e.name);
  std::vector<std::string> expected = {"modelDescription.xml", "binaries/linux64/DEMLinkPlateInBed.so",
                                       "binaries/linux64/libdemlink_c.so"};
#if defined(DEMLINK_WIN64)
  expected.push_back("binaries/win64/DEMLinkPlateInBed.dll");  // the cross-built library (cmake/Win64.cmake)
#endif
  expected.push_back("resources/demlink_fmu.cfg");
  EXPECT_EQ(names, expected);
  EXPECT_EQ(entries.back().data, readFile(DEMLINK_FMU_TEST_CONFIG));
  EXPECT_NE(entries[0].data.find(guidOf(entries.back().data)), std::string::npos);
}

/// Runs fmu_master on `fmu` (with `extra` arguments) against a fresh demlink-server and
/// checks that both exit 0 (the server once the FMU said Bye); returns the master's summary.
std::string runMaster(const std::string& fmu, const std::string& tag, const std::vector<std::string>& extra) {
  const std::filesystem::path out =
      std::filesystem::temp_directory_path() / ("demlink_fmu_" + tag + "_" + std::to_string(::getpid()));
  std::filesystem::remove_all(out);
  const integration::ClientRun run = integration::runClientAgainstServer(
      DEMLINK_SERVER_EXE, (out / "server").string(),
      [&](const std::string& host, const std::string& port) {
        std::vector<std::string> line = {DEMLINK_FMU_MASTER_EXE, fmu, host, port, (out / "unpacked").string()};
        line.insert(line.end(), extra.begin(), extra.end());
        return line;
      },
      std::chrono::seconds(300));
  EXPECT_EQ(run.client_exit, 0) << run.announced << "\n" << run.summary;
  EXPECT_EQ(run.server_exit, 0) << "the run ends and the server exits";
  if (!::testing::Test::HasFailure()) std::filesystem::remove_all(out);
  return run.summary;
}

/// The FMU stepped by fmu_master against demlink-server: a plate lowered into a gravel bed
/// feels no force while clear of it and an upward force above the displaced column's weight
/// once 15-35 mm deep; its reported position lags the inputs by exactly one interval; the run
/// ends with fmi2Terminate's Bye (the box has no end time) and the server exits.
TEST(FmuRealServer, PlateLoweredIntoBedFeelsUpwardForce) {
  const std::string summary = runMaster(DEMLINK_TEST_FMU, "plate", {});
  EXPECT_NE(summary.find(kPlateSummary), std::string::npos) << summary;
}

/// A box with its own end time: the steps up to it succeed, then fmi2DoStep answers
/// fmi2Discard and fmi2Terminated is set (not fmi2Error).
TEST(FmuRealServer, ServerEndOfRunIsDiscardWithTerminated) {
  const std::string summary = runMaster(DEMLINK_SHORT_FMU, "end", {"end"});
  EXPECT_NE(summary.find(kEndSummary), std::string::npos) << summary;
}

}  // namespace
}  // namespace demlink::fmu
