/// Contact output files of a run (simulation_box.output.contact_interval, mesh_loads):
/// contacts_NNNNNN.vtp / .csv on their steps with contacts.pvd, whose wall forces
/// carry the resting spheres' weight to 0.5 %, starting with a frame at step 0 like the
/// particles'; mesh frames with per-triangle loads whose forces read back from the file
/// add up to the mesh wrench, loads already in the step-0 frame, and integrals that a
/// checkpoint carries (a restored run's frame equals the unbroken run's, byte for byte);
/// bad output fields are refused naming the field.
#include <gtest/gtest.h>

#include <algorithm>
#include <span>
#include <sstream>
#include <string>

#include "demlink/core/base/input_error.hpp"
#include "demlink/core/output/vtk_writer.hpp"
#include "demlink/server/run/frame_series.hpp"
#include "demlink/server/run/headless_runner.hpp"
#include "demlink/server/run/contact_output_plan.hpp"
#include "demlink/server/scene/scene_loader.hpp"
#include "test_support.hpp"

namespace demlink::server {
namespace {

constexpr double kRadius = 0.002;  // [m]

/// Four spheres touching the floor (centres at `height`), apart from each other.
std::string restingSceneJson(const std::string& output, double height = kRadius) {
  return R"({"components": [
    {"name": "box", "simulation_box": {"time_step": 1e-5, "restitution_tolerance": 0.2, "end_time": 0.3,
      "output": {"progress_interval_s": 60, )" + output + R"(}}},
    {"name": "glass", "material": {"density": 2500, "youngs_modulus": 5e6, "restitution": 0.3}},
    {"name": "floor", "plane": {"normal": {"z": 1}, "material": "glass"}},
    {"name": "spheres", "particle_lattice": {"material": "glass", "radius": 0.002, "spacing": 0.006,
      "origin": {"x": 0.01, "y": 0.01, "z": )" + std::to_string(height) + R"(}, "counts": {"nx": 2, "ny": 2, "nz": 1}}}
  ]})";
}

/// The same spheres, sliding at 0.05 m/s over a static box whose top is z = 0, with
/// `box` fields (end time, intervals, restore file).
std::string slidingOnMeshJson(const std::string& box, double height) {
  return R"({"components": [
    {"name": "box", "simulation_box": {"time_step": 1e-5, "restitution_tolerance": 0.2, )" + box + R"(}},
    {"name": "glass", "material": {"density": 2500, "youngs_modulus": 5e6, "restitution": 0.3}},
    {"name": "floor", "rigid_body": {"material": "glass", "box": {"size": {"x": 0.06, "y": 0.06, "z": 0.01}},
      "position": {"x": 0.02, "y": 0.02, "z": -0.005}}},
    {"name": "spheres", "particle_lattice": {"material": "glass", "radius": 0.002, "spacing": 0.006,
      "origin": {"x": 0.01, "y": 0.01, "z": )" + std::to_string(height) + R"(}, "counts": {"nx": 2, "ny": 2, "nz": 1},
      "velocity": {"x": 0.05}}}
  ]})";
}

std::vector<std::vector<std::string>> csvRows(const std::string& text) {
  std::vector<std::vector<std::string>> rows;
  std::istringstream in(text);
  for (std::string line; std::getline(in, line);) {
    std::vector<std::string> fields;
    std::istringstream fieldsIn(line);
    for (std::string field; std::getline(fieldsIn, field, ',');) fields.push_back(field);
    rows.push_back(fields);
  }
  return rows;
}

TEST(ContactOutputs, ContactFilesOnTheirStepsCarryTheWeight) {
  const test::ScratchDir scratch;
  TranslatedScene scene =
      translateScene(parseSceneJson(restingSceneJson(R"("contact_interval": 0.1)"), "resting"), {});
  scene.run.output_directory = (scratch.path() / "out").string();
  (void)runHeadless(scene);
  const std::filesystem::path out = scratch.path() / "out";
  const std::string pvd = test::readText(out / "contacts.pvd");
  EXPECT_EQ(test::countOccurrences(pvd, "<DataSet "), 4u) << "steps 0, 10000, 20000, 30000";
  const std::string vtp = test::readText(out / "contacts_000002.vtp");
  EXPECT_NE(vtp.find("NumberOfLines=\"4\""), std::string::npos);
  for (const char* name : {"normal_force", "tangential_force", "overlap", "contact_point", "kind"}) {
    EXPECT_NE(vtp.find("Name=\"" + std::string(name) + "\""), std::string::npos) << name;
  }
  const auto rows = csvRows(test::readText(out / "contacts_000002.csv"));
  ASSERT_EQ(rows.size(), 5u);
  ASSERT_EQ(rows[0], core::contactsCsvColumns());
  const auto column = std::find(rows[0].begin(), rows[0].end(), "normal_force_N") - rows[0].begin();
  double wallNormal = 0.0;
  for (std::size_t r = 1; r < rows.size(); ++r) {
    EXPECT_EQ(rows[r][0], "1") << "plane contacts only";
    wallNormal += std::stod(rows[r][static_cast<std::size_t>(column)]);
  }
  EXPECT_NEAR(wallNormal / (scene.world.totalMass() * 9.81), 1.0, 0.005);
}

TEST(ContactOutputs, ContactSeriesStartsAtStepZero) {
  // Spheres 0.1 mm into the floor at the start: the step-0 frame holds their contacts.
  const test::ScratchDir scratch;
  TranslatedScene scene = translateScene(
      parseSceneJson(restingSceneJson(R"("contact_interval": 0.1)", kRadius - 1e-4), "pressed"), {});
  scene.run.output_directory = (scratch.path() / "out").string();
  scene.run.end_time = 0.1;
  (void)runHeadless(scene);
  const std::filesystem::path out = scratch.path() / "out";
  const std::string pvd = test::readText(out / "contacts.pvd");
  ASSERT_EQ(test::countOccurrences(pvd, "<DataSet "), 2u) << pvd;
  EXPECT_NE(pvd.find(R"(timestep="0" group="" part="0" file="contacts_000000.vtp")"), std::string::npos) << pvd;
  const auto rows = csvRows(test::readText(out / "contacts_000000.csv"));
  ASSERT_EQ(rows.size(), 5u) << "a header and four plane contacts";
  const auto column = std::find(rows[0].begin(), rows[0].end(), "overlap_m") - rows[0].begin();
  for (std::size_t r = 1; r < rows.size(); ++r) {
    EXPECT_NEAR(std::stod(rows[r][static_cast<std::size_t>(column)]), 1e-4, 1e-9) << "the initial overlap";
  }
}

/// Sum of a mesh's per-triangle values of `field` [unit of the field].
template <class Field>
double sumOver(std::span<const core::TriangleLoad> loads, Field field) {
  double sum = 0.0;
  for (const core::TriangleLoad& load : loads) sum += field(load);
  return sum;
}

TEST(ContactOutputs, MeshLoadsStartAtStepZeroAndSurviveACheckpoint) {
  const test::ScratchDir scratch;
  auto run = [&](const std::string& name, const std::string& restore) {
    TranslatedScene scene = translateScene(
        parseSceneJson(slidingOnMeshJson(R"("end_time": 0.02, "output": {"progress_interval_s": 60,
                                             "vtk_interval": 0.01, "checkpoint_interval": 0.01, "mesh_loads": true})",
                                         kRadius - 1e-5),
                       name),
        {});
    scene.run.output_directory = (scratch.path() / name).string();
    scene.run.restore_file = restore;
    (void)runHeadless(scene);
    return scene;
  };
  const TranslatedScene unbroken = run("unbroken", "");
  const TranslatedScene restored = run("restored", (scratch.path() / "unbroken" / "checkpoint_000001.bin").string());

  // Step 0: the initialising evaluation's loads, not zeros, in the first mesh frame.
  {
    TranslatedScene fresh = translateScene(
        parseSceneJson(slidingOnMeshJson(R"("end_time": 0.02, "output": {"mesh_loads": true})", kRadius - 1e-5),
                       "fresh"),
        {});
    fresh.world.setContactOutput(contactOutputOf(fresh.run, planRun(fresh.run, 1e-5, true)));
    fresh.world.initialize();
    const std::span<const core::TriangleLoad> loads = fresh.world.meshLoads(0);
    const double pressing = sumOver(loads, [](const core::TriangleLoad& l) { return l.normal_force; });
    EXPECT_NEAR(pressing, -fresh.world.meshes()[0].force().z(), 1e-12 * pressing);
    EXPECT_GT(pressing, 0.0);
    FrameSeries frames(scratch.path() / "fresh", "out");
    frames.writeFrame(fresh.world, 0.0);
    EXPECT_EQ(test::readText(scratch.path() / "fresh" / "meshes_000000.vtp"),
              test::readText(scratch.path() / "unbroken" / "meshes_000000.vtp"));
  }

  // The restored run's last frame is the unbroken run's, integrals included.
  EXPECT_EQ(test::readText(scratch.path() / "restored" / "meshes_000001.vtp"),
            test::readText(scratch.path() / "unbroken" / "meshes_000002.vtp"));
  const std::span<const core::TriangleLoad> a = unbroken.world.meshLoads(0);
  const std::span<const core::TriangleLoad> b = restored.world.meshLoads(0);
  ASSERT_EQ(a.size(), b.size());
  for (std::size_t t = 0; t < a.size(); ++t) {
    EXPECT_EQ(a[t].normal_impulse, b[t].normal_impulse) << t;
    EXPECT_EQ(a[t].friction_work, b[t].friction_work) << t;
    EXPECT_EQ(a[t].archard_work, b[t].archard_work) << t;
  }
  // The impulse over 0.02 s carries the spheres' weight (within the first contact's
  // settling), and the sliding spheres did frictional work.
  const double impulse = sumOver(a, [](const core::TriangleLoad& l) { return l.normal_impulse; });
  EXPECT_NEAR(impulse / (unbroken.world.totalMass() * 9.81 * 0.02), 1.0, 0.05);
  EXPECT_GT(sumOver(a, [](const core::TriangleLoad& l) { return l.friction_work; }), 0.0);
}

TEST(ContactOutputs, MeshFramesCarryTriangleLoadsThatAddUpToTheWrench) {
  core::SimulationSettings settings;
  settings.time_step = 1.0e-5;
  settings.restitution_tolerance = 0.2;
  core::World world(settings);
  core::Material glass;
  glass.name = "glass";
  glass.restitution = 0.3;
  const auto material = world.addMaterial(glass);
  const core::TriangleMesh floor = core::rectangleMesh(core::Vec3::Zero(), 0.01, 0.01, 3, 3);
  world.addMesh(core::MeshBody("floor", floor.vertices, floor.triangles, material));
  for (const double x : {-0.004, 0.0033}) {
    core::ParticleSpec s;
    s.radius = kRadius;
    s.position = core::Vec3(x, 0.001, kRadius);
    world.addParticle(s);
  }
  world.setContactOutput({0, true});
  world.initialize();
  for (int n = 0; n < 3'000; ++n) world.step();

  const test::ScratchDir scratch;
  FrameSeries frames(scratch.path(), "out");
  frames.writeFrame(world, 0.0);
  const std::string binary = test::readText(scratch.path() / "meshes_000000.vtp");
  for (const char* name : {"load_force", "pressure", "normal_impulse", "archard_work", "friction_work"}) {
    EXPECT_NE(binary.find("Name=\"" + std::string(name) + "\""), std::string::npos) << name;
  }
  const std::filesystem::path ascii = scratch.path() / "loads.vtp";
  core::writeMeshLoadsVtp(ascii.string(), world.meshes()[0].worldVertices(), world.meshes()[0].triangles(),
                          world.meshLoads(0), core::VtkEncoding::Ascii);
  const std::string file = test::readText(ascii);
  const std::vector<double> force = test::asciiValues(file, "load_force");
  ASSERT_EQ(force.size(), 3 * floor.triangles.size());
  core::Vec3 sum = core::Vec3::Zero();
  for (std::size_t t = 0; t < floor.triangles.size(); ++t) sum += core::Vec3(force[3 * t], force[3 * t + 1], force[3 * t + 2]);
  const core::Vec3 wrench = world.meshes()[0].force();
  EXPECT_LT((sum - wrench).norm(), 1.0e-12 * wrench.norm());
  EXPECT_NEAR(-sum.z() / (world.totalMass() * 9.81), 1.0, 0.005);
}

TEST(ContactOutputs, BadOutputFieldsAreRefusedNamingTheField) {
  const std::pair<std::string, std::string> cases[] = {
      {R"("contact_interval": -0.1)", "output.contact_interval"},
      {R"("mesh_loads": true)", "output.mesh_loads"},
  };
  for (const auto& [output, field] : cases) {
    try {
      (void)translateScene(parseSceneJson(restingSceneJson(output), "resting"), {});
      ADD_FAILURE() << output << " accepted";
    } catch (const core::InputError& error) {
      EXPECT_NE(error.field().find(field), std::string::npos) << error.what();
    }
  }
}

}  // namespace
}  // namespace demlink::server
