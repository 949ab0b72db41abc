/// The DEMLink FMU (client/fmu, docs/fmi.md): the configuration and its FMI variables, the
/// archive, and the packaged FMU stepped by a small FMI 2.0 master (fmu_master) against
/// the real demlink-server, with physical checks. The master runs as a child process:
/// the FMU loads libdemlink_c.so, which carries its own protobuf messages.
#include <gtest/gtest.h>
#include <unistd.h>

#include <chrono>
#include <cmath>
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
  EXPECT_EQ(config.components[4].strings, (std::vector<std::string>{"gravel"}));
  EXPECT_EQ(config.components[4].ints, (std::vector<long long>{1, 1}));  // box, PREDICTED
  // reference point, initial position, orientation, box size: layout reals[1..13]
  EXPECT_EQ(config.components[4].reals,
            (std::vector<double>{0, 0, 0, 0, 0, 0.11, 1, 0, 0, 0, 0.06, 0.06, 0.01}));
  EXPECT_EQ(config.components[3].ints, (std::vector<long long>{3}));  // the pit's seed
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

/// The message of a configuration's rejection ("accepted" when it parses).
std::string rejection(const std::string& text) {
  try {
    (void)parseConfig(text);
  } catch (const std::invalid_argument& e) {
    return e.what();
  }
  return "accepted";
}

TEST(FmuConfig, BadStatementsAreNamedWithLineFieldAndValue) {
  const std::string head = "model = M\ninterval = 0.01\n";
  EXPECT_NE(rejection("model = 1bad\n").find("model = '1bad'"), std::string::npos);
  EXPECT_NE(rejection(head + "[particle_view v]\n").find("line 3"), std::string::npos);
  EXPECT_NE(rejection(head + "[material a]\n[material a]\n").find("declared twice"), std::string::npos);
  EXPECT_NE(rejection("model = M\n[material a]\n").find("interval"), std::string::npos);
  EXPECT_NE(rejection(head + "port = 70000\n").find("port = '70000'"), std::string::npos);
  EXPECT_NE(rejection(head).find("no component"), std::string::npos);
  EXPECT_NE(rejection(head + "exchange_order = later\n").find("exchange_order = 'later'"), std::string::npos);
  EXPECT_NE(rejection(head + "speed = 3\n").find("line 3: speed = '3': unknown statement"), std::string::npos);
  // The positional form is refused with a pointer to the named one.
  EXPECT_NE(rejection(head + "component material gravel strings=gravel\n").find("positional form"), std::string::npos);
}

TEST(FmuConfig, MisplacedUnknownAndMalformedFieldsAreNamed) {
  const std::string head = "model = M\ninterval = 0.01\n[rigid_body plate]\nmaterial = gravel\ngeometry = box\n";
  // Unknown field: named with the kind's fields.
  const std::string unknown = rejection(head + "sise = 0.1 0.1 0.1\n");
  EXPECT_NE(unknown.find("line 6: plate.sise = '0.1 0.1 0.1': unknown field of rigid_body"), std::string::npos) << unknown;
  EXPECT_NE(unknown.find("reference_point"), std::string::npos) << unknown;
  // Malformed: a vector with a missing number, a word for a number, a choice out of its list.
  const std::string shortVector = rejection(head + "size = 0.1 0.1\n");
  EXPECT_NE(shortVector.find("plate.size = '0.1 0.1': needs 3 numbers separated by spaces [m], got 2"),
            std::string::npos) << shortVector;
  EXPECT_NE(rejection(head + "position = 0 0 x\n").find("plate.position = 'x': not a number"), std::string::npos);
  EXPECT_NE(rejection(head + "position = 0 0 inf\n").find("must be finite"), std::string::npos);
  EXPECT_NE(rejection(head + "motion = fast\n").find("plate.motion = 'fast': must be one of predicted, lagged"),
            std::string::npos);
  EXPECT_NE(rejection(head + "size = 1 1 1\nsize = 1 1 1\n").find("line 7: plate.size = '1 1 1': given twice"),
            std::string::npos);
  // Misplaced: a statement inside a section, a field of another shape, a field before any
  // section, a field of another kind.
  EXPECT_NE(rejection(head + "interval = 0.02\n").find("is a statement of the whole FMU"), std::string::npos);
  const std::string otherShape =
      rejection("model = M\ninterval = 0.01\n[region_sensor s]\ncentre = 0 0 0\nradius = 0.1\n");
  EXPECT_NE(otherShape.find("line 5: s.radius = '0.1': is a field of shape = sphere"), std::string::npos) << otherShape;
  EXPECT_NE(rejection("model = M\ninterval = 0.01\ngravity = 0 0 -9.81\n").find("unknown statement"), std::string::npos);
  EXPECT_NE(rejection(head + "target_height = 0.08\n").find("unknown field of rigid_body"), std::string::npos);
  // Missing required field, named with the section's line.
  EXPECT_NE(rejection("model = M\ninterval = 0.01\n[plane floor]\nmaterial = m\npoint = 0 0 0\n")
                .find("line 3: floor.normal = '': missing"),
            std::string::npos);
  // Bounds come in pairs.
  EXPECT_NE(rejection("model = M\ninterval = 0.01\n[simulation_box b]\nbounds_lower = 0 0 0\n")
                .find("b.bounds_upper"),
            std::string::npos);
}

TEST(FmuConfig, NamedFieldsFillTheGenericLayout) {
  const FmuConfig config = parseConfig(
      "model = M\ninterval = 0.01\n[simulation_box box]\ntime_step = 2e-5\ngravity = 0 0 -9.81\nthreads = 2\n"
      "[region_sensor probe]\nshape = sphere\ncentre = 1 2 3\nradius = 0.5\nattached_to = plate\n");
  ASSERT_EQ(config.components.size(), 2u);
  const ComponentSpec& box = config.components[0];
  ASSERT_EQ(box.reals.size(), 5u);  // time step, end time, gravity: reals[1..5]
  EXPECT_EQ(box.reals[0], 2e-5);
  EXPECT_EQ(box.reals[1], 0.0);     // no end time: the run ends with the FMU's Bye
  EXPECT_EQ(box.reals[4], -9.81);
  EXPECT_EQ(box.ints, (std::vector<long long>{2, 2}));  // expected count = the FMU's components, threads
  const ComponentSpec& probe = config.components[1];
  EXPECT_EQ(probe.ints, (std::vector<long long>{1}));
  EXPECT_EQ(probe.reals, (std::vector<double>{1, 2, 3, 0.5}));
  EXPECT_EQ(probe.strings, (std::vector<std::string>{"plate"}));
}

TEST(FmuConfig, ClumpTemplatesAndWhatPoursThemFillTheGenericLayout) {
  const FmuConfig config = parseConfig(
      "model = M\ninterval = 0.01\n[simulation_box box]\ntime_step = 2e-5\n"
      "[clump_template pebble]\nspheres = -0.002 0 0 0.003  0.002 0 0 0.0025\n"
      "[pit_generator bed]\nmaterial = gravel\nlower = 0 0 0\nupper = 1 1 1\nradius_min = 0.01\n"
      "radius_max = 0.02\ntarget_height = 0.5\nclump_template = pebble\n");
  ASSERT_EQ(config.components.size(), 3u);
  const ComponentSpec& pebble = config.components[1];
  EXPECT_EQ(pebble.kind, "clump_template");
  EXPECT_EQ(pebble.reals, (std::vector<double>{-0.002, 0, 0, 0.003, 0.002, 0, 0, 0.0025}));  // reals[1..8]
  const ComponentSpec& bed = config.components[2];
  EXPECT_EQ(bed.strings, (std::vector<std::string>{"gravel", "", "pebble"}));  // strings[2..4]
  // A sphere's four numbers, all of them.
  try {
    (void)parseConfig("model = M\ninterval = 0.01\n[clump_template pebble]\nspheres = 0 0 0\n");
    FAIL() << "accepted three numbers";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("pebble.spheres = '0 0 0': needs numbers in groups of 4"), std::string::npos)
        << e.what();
  }
}

TEST(FmuConfig, ParallelBondsAndClodsFillTheGenericLayout) {
  const FmuConfig config = parseConfig(
      "model = M\ninterval = 0.01\n[simulation_box box]\ntime_step = 2e-5\n"
      "[pit_generator bed]\nmaterial = gravel\nlower = 0 0 0\nupper = 1 1 1\nradius_min = 0.01\n"
      "radius_max = 0.02\ntarget_height = 0.5\nclod_fraction = 0.3\nclod_radius = 0.05\nclod_bonds = clay\n"
      "[parallel_bonds clay]\nnormal_stiffness_per_area = 1e9\nshear_stiffness_per_area = 2e9\n"
      "tensile_strength = 1e5\nshear_strength = 2e5\ngap_tolerance = 0.001\nmaterials = gravel sand\nseed = 4\n");
  ASSERT_EQ(config.components.size(), 3u);
  const ComponentSpec& bed = config.components[1];
  ASSERT_EQ(bed.reals.size(), 11u);  // reals[1..11]
  EXPECT_EQ(bed.reals[9], 0.3);
  EXPECT_EQ(bed.reals[10], 0.05);
  EXPECT_EQ(bed.strings, (std::vector<std::string>{"gravel", "clay"}));
  const ComponentSpec& clay = config.components[2];
  ASSERT_EQ(clay.reals.size(), 5u);  // kn, ks, strengths, gap: reals[1..5]; the rest defaults
  EXPECT_EQ(clay.reals, (std::vector<double>{1e9, 2e9, 1e5, 2e5, 0.001}));
  // The seed, and the region (none when unset): always written, so strings[2] is the
  // (empty) attached body and the materials follow.
  EXPECT_EQ(clay.ints, (std::vector<long long>{4, 0}));
  // A name list follows its field's own (empty) slot, as expected_names does; the layout
  // skips empty material names.
  EXPECT_EQ(clay.strings, (std::vector<std::string>{"", "", "gravel", "sand"}));
  EXPECT_FALSE(isExchanged("parallel_bonds"));
}

TEST(FmuConfig, ParallelBondsRegionsFillTheGenericLayout) {
  const std::string head = "model = M\ninterval = 0.01\n[parallel_bonds clay]\nnormal_stiffness_per_area = 1e9\n"
                           "shear_stiffness_per_area = 2e9\ntensile_strength = 1e5\nshear_strength = 2e5\n"
                           "gap_tolerance = 0.001\n";
  const FmuConfig sphere = parseConfig(head + "region = sphere\nregion_centre = 0.1 0.2 0.3\nregion_radius = 0.05\n"
                                              "region_attached_to = bucket\nmaterials = gravel\n");
  const ComponentSpec& lump = sphere.components[0];
  EXPECT_EQ(lump.ints, (std::vector<long long>{0, 2}));
  ASSERT_EQ(lump.reals.size(), 12u);  // reals[1..12]: the radius is the last
  EXPECT_EQ(lump.reals[8], 0.1);
  EXPECT_EQ(lump.reals[10], 0.3);
  EXPECT_EQ(lump.reals[11], 0.05);
  EXPECT_EQ(lump.strings, (std::vector<std::string>{"bucket", "", "gravel"}));
  const FmuConfig box =
      parseConfig(head + "region = box\nregion_centre = 0 0 1\nregion_size = 1 2 3\nregion_orientation = 0 0 0 1\n");
  const ComponentSpec& slab = box.components[0];
  EXPECT_EQ(slab.ints, (std::vector<long long>{0, 1}));
  ASSERT_EQ(slab.reals.size(), 18u);  // reals[1..18]
  EXPECT_EQ(slab.reals[11], 1.0);     // size
  EXPECT_EQ(slab.reals[13], 3.0);
  EXPECT_EQ(slab.reals[17], 1.0);  // orientation z
  // A box's size needs region = box; a sphere's radius region = sphere.
  const std::string noKind = rejection(head + "region_centre = 0 0 0\nregion_size = 1 1 1\n");
  EXPECT_NE(noKind.find("line 10: clay.region_size = '1 1 1': is a field of region = box"), std::string::npos) << noKind;
  const std::string otherKind = rejection(head + "region = box\nregion_centre = 0 0 0\nregion_radius = 1\n");
  EXPECT_NE(otherKind.find("clay.region_radius = '1': is a field of region = sphere"), std::string::npos) << otherKind;
  EXPECT_NE(rejection(head + "region = cylinder\n").find("must be one of none, box, sphere"), std::string::npos);
}

TEST(FmuConfig, MovingRegionsFillTheGenericLayout) {
  const FmuConfig config = parseConfig(
      "model = M\ninterval = 0.01\n[region_sensor scan]\nshape = sphere\ncentre = 0 0 1\nradius = 0.2\n"
      "velocity = 0.5 0 -0.25\n[particle_sink drop]\ncentre = 0 0 0\nsize = 1 1 1\n"
      "[flow_sensor lift]\nshape = disc\ncentre = 0 0 0\nnormal = 0 0 1\nradius = 0.3\nvelocity = 0 0 2\n");
  const ComponentSpec& scan = config.components[0];
  ASSERT_EQ(scan.reals.size(), 13u);  // reals[1..13]: the velocity is last, the orientation not given
  EXPECT_EQ(scan.reals[3], 0.2);
  for (std::size_t i = 4; i < 10; ++i) EXPECT_TRUE(std::isnan(scan.reals[i])) << i;
  EXPECT_EQ((std::vector<double>{scan.reals[10], scan.reals[11], scan.reals[12]}),
            (std::vector<double>{0.5, 0.0, -0.25}));
  EXPECT_EQ(config.components[1].reals.size(), 6u) << "no velocity: the layout ends with the size";
  const ComponentSpec& lift = config.components[2];
  ASSERT_EQ(lift.reals.size(), 14u);
  EXPECT_EQ(lift.reals[13], 2.0);
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
  // Every Real carries an SI unit and every variable says what it is; the wrench's units.
  for (const Variable& v : variablesOf(config)) {
    EXPECT_FALSE(v.description.empty()) << v.name;
    if (v.type == VariableType::kReal) {
      EXPECT_FALSE(v.unit.empty()) << v.name;
    }
  }
  EXPECT_NE(xml.find("name=\"plate.meanForce[3]\" valueReference="), std::string::npos);
  EXPECT_NE(xml.find("<Unit name=\"N.m\"><BaseUnit kg=\"1\" m=\"2\" s=\"-2\"/></Unit>"), std::string::npos);
  EXPECT_NE(xml.find("<Real unit=\"N.m\"/>"), std::string::npos);
  EXPECT_NE(xml.find("<Real unit=\"rad/s\" start=\"0\"/>"), std::string::npos);
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
  std::vector<std::string> expected = {"modelDescription.xml", "binaries/linux64/DEMLinkPlateInBed.so"};
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
/// once 15-35 mm deep; after each fmi2DoStep(t, h) the outputs are those at t + h (box.time,
/// and the body's position the pose sent at t moved over h); the run ends with
/// fmi2Terminate's Bye (the box has no end time) and the server exits.
TEST(FmuRealServer, PlateLoweredIntoBedFeelsUpwardForce) {
  const std::string summary = runMaster(DEMLINK_TEST_FMU, "plate", {});
  EXPECT_NE(summary.find(kPlateSummary), std::string::npos) << summary;
}

/// A box with its own end time: the steps up to it succeed, then fmi2DoStep answers
/// fmi2Discard and fmi2Terminated is set (not fmi2Error). Send first, the fifth step's
/// outputs already end at the end time (box.time == t + h after every step).
TEST(FmuRealServer, ServerEndOfRunIsDiscardWithTerminated) {
  const std::string summary = runMaster(DEMLINK_SHORT_FMU, "end", {"end"});
  EXPECT_NE(summary.find(kEndSummary), std::string::npos) << summary;
}

/// The receive-first option: after fmi2DoStep(t, h) box.time == t, the end of [t - h, t]
/// (one interval behind the step's end), so one more step succeeds before the end.
TEST(FmuRealServer, ReceiveFirstOrderLagsOneInterval) {
  const std::string summary = runMaster(DEMLINK_SHORT_RECEIVE_FIRST_FMU, "receive_first", {"end"});
  EXPECT_NE(summary.find(kReceiveFirstEndSummary), std::string::npos) << summary;
}

}  // namespace
}  // namespace demlink::fmu
