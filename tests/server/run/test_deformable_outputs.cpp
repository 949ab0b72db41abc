/// What a headless run writes for its deformable bodies: a .vtp per frame in the body's .pvd
/// (springs as lines with an "intact" flag), broken_springs.csv with one row per broken
/// spring, the run log rows, and a checkpointed run that continues bit-identically (same
/// final checkpoint, broken_springs.csv listing only the springs broken after the restore).
#include <gtest/gtest.h>

#include <sstream>

#include "demlink/core/deformable/mass_spring_body.hpp"
#include "demlink/server/run/headless_runner.hpp"
#include "demlink/server/scene/scene_loader.hpp"
#include "test_support.hpp"

namespace demlink::server {
namespace {

/// A 0.4 x 0.4 m sheet (5 x 5 nodes, 10 kg, shear springs) hung by its four corners; springs
/// break above `breakForce` [N]. A few spheres land on it.
std::string sheetScene(double endTime, double breakForce, double checkpointInterval) {
  std::ostringstream json;
  json << R"({"components": [
    {"name": "box", "simulation_box": {"time_step": 1e-4, "end_time": )" << endTime << R"(,
      "output": {"vtk_interval": 0.05, "progress_interval_s": 60, "checkpoint_interval": )" << checkpointInterval << R"(}}},
    {"name": "glass", "material": {"density": 2500, "youngs_modulus": 1e7}},
    {"name": "sheet", "mass_spring_body": {
      "box": {"lo": {"x": 0, "y": 0, "z": -0.01}, "hi": {"x": 0.4, "y": 0.4, "z": 0.01}, "node_spacing": 0.1},
      "material": "glass", "total_mass": 10, "stiffness": 1e4, "damping": 20, "shear_factor": 1,
      "break_force": )" << breakForce << R"(,
      "fixed": {"nodes": [0, 4, 20, 24]}}},
    {"name": "drops", "particle_lattice": {"material": "glass", "radius": 0.03, "spacing": 0.1,
      "origin": {"x": 0.15, "y": 0.15, "z": 0.1}, "counts": {"nx": 2, "ny": 2, "nz": 1}}},
    {"name": "centre", "tracker": {"nodes": ["sheet:12"], "sample_interval": 0.01}}
  ]})";
  return json.str();
}

RunSummary run(const std::string& json, const std::filesystem::path& out, const std::string& restore = {}) {
  TranslatedScene scene = translateScene(parseSceneJson(json, "sheet"), {});
  scene.run.output_directory = out.string();
  scene.run.restore_file = restore;
  return runHeadless(scene);
}

std::vector<std::string> lines(const std::string& text) {
  std::vector<std::string> out;
  std::istringstream in(text);
  for (std::string line; std::getline(in, line);) out.push_back(line);
  return out;
}

TEST(DeformableOutputs, FramesBrokenSpringsAndRunLog) {
  const test::ScratchDir scratch;
  const std::filesystem::path out = scratch.path() / "out";
  // 25 N: below the corner springs' tension under the sheet's own weight, so they tear.
  const RunSummary summary = run(sheetScene(0.2, 25.0, 0.0), out);
  EXPECT_EQ(summary.frames, 5u);

  const std::string pvd = test::readText(out / "deformable_sheet.pvd");
  EXPECT_EQ(test::countOccurrences(pvd, "<DataSet "), 5u);
  for (int k = 0; k < 5; ++k) {
    EXPECT_TRUE(std::filesystem::exists(out / ("deformable_sheet_00000" + std::to_string(k) + ".vtp"))) << k;
  }
  const std::string frame = test::readText(out / "deformable_sheet_000004.vtp");
  EXPECT_NE(frame.find("NumberOfPoints=\"25\""), std::string::npos);
  // 2 x 5 x 4 structural + 2 x 4 x 4 shear springs as lines, 2 x 4 x 4 triangles.
  EXPECT_NE(frame.find("NumberOfLines=\"72\""), std::string::npos) << frame.substr(0, 400);
  EXPECT_NE(frame.find("NumberOfPolys=\"32\""), std::string::npos);
  EXPECT_NE(frame.find("Name=\"intact\""), std::string::npos);

  const std::vector<std::string> broken = lines(test::readText(out / "broken_springs.csv"));
  ASSERT_GE(broken.size(), 2u) << "the corner springs tear";
  EXPECT_EQ(broken[0], "time_s,body,spring,x_m,y_m,z_m,force_N,strain");
  EXPECT_NE(broken[1].find(",sheet,"), std::string::npos) << broken[1];
  const std::string log = test::readText(out / "run_log.csv");
  EXPECT_NE(log.find("deformable,sheet.nodes,25,"), std::string::npos) << log;
  EXPECT_NE(log.find("deformable,sheet.critical_time_step,"), std::string::npos) << log;
  EXPECT_NE(log.find("deformable,sheet.broken_springs," + std::to_string(broken.size() - 1) + ","), std::string::npos)
      << log;
  const std::vector<std::string> tracked = lines(test::readText(out / "node_tracker_centre.csv"));
  EXPECT_EQ(tracked.size(), 1u + 21u) << "header + samples at 0, 0.01, ..., 0.2 s";
}

TEST(DeformableOutputs, FemBodyFramesAreUnstructuredGridsWithStress) {
  // The FEM tests' cantilever (110 nodes, 254 linear tetrahedra), clamped at x = 0, sagging.
  const std::filesystem::path mesh =
      std::filesystem::path(DEMLINK_TESTS_DIR) / "core/deformable/data/bar_order1.msh";
  const test::ScratchDir scratch;
  const std::filesystem::path out = scratch.path() / "out";
  run(R"({"components": [
    {"name": "box", "simulation_box": {"time_step": 1e-4, "end_time": 0.02,
      "output": {"vtk_interval": 0.01, "progress_interval_s": 60}}},
    {"name": "steel", "material": {}},
    {"name": "bar", "fem_body": {"material": "steel", "mesh": {"msh_file": ")" + mesh.string() + R"(",
      "youngs_modulus": 1e7, "poisson_ratio": 0.3, "density": 1000},
      "fixed": {"regions": [{"lo": {"x": -1, "y": -1, "z": -1}, "hi": {"x": 0.001, "y": 1, "z": 1}}]}}}
  ]})",
      out);
  EXPECT_EQ(test::countOccurrences(test::readText(out / "deformable_bar.pvd"), "<DataSet "), 3u);
  const std::string frame = test::readText(out / "deformable_bar_000002.vtu");
  EXPECT_NE(frame.find("<VTKFile type=\"UnstructuredGrid\""), std::string::npos);
  EXPECT_NE(frame.find("NumberOfPoints=\"110\" NumberOfCells=\"254\""), std::string::npos) << frame.substr(0, 300);
  EXPECT_NE(frame.find("Name=\"von_mises_stress\""), std::string::npos);
  EXPECT_FALSE(std::filesystem::exists(out / "broken_springs.csv")) << "no mass-spring body, no tears to list";
  const std::string log = test::readText(out / "run_log.csv");
  EXPECT_NE(log.find("deformable,bar.kind,fem,"), std::string::npos);
  // The three-level integrator has no step limit and the scene no particles: limits that
  // do not exist are empty values, and frames without particles have no heights.
  EXPECT_NE(log.find("deformable,bar.critical_time_step,,s\n"), std::string::npos) << log;
  EXPECT_EQ(log.find("inf"), std::string::npos) << log;
  EXPECT_EQ(log.find("nan"), std::string::npos) << log;
  const std::vector<std::string> summary = lines(test::readText(out / "summary.csv"));
  ASSERT_EQ(summary.size(), 4u);
  EXPECT_EQ(summary[3].rfind("0.02,0,0,,,", 0), 0u) << summary[3];
}

TEST(DeformableOutputs, RestoredRunContinuesBitIdentically) {
  const test::ScratchDir scratch;
  const std::filesystem::path& dir = scratch.path();
  const std::string json = sheetScene(0.2, 25.0, 0.1);
  run(json, dir / "full");
  run(json, dir / "cont", (dir / "full" / "checkpoint_000001.bin").string());
  EXPECT_TRUE(test::readText(dir / "cont" / "checkpoint_final.bin") ==
              test::readText(dir / "full" / "checkpoint_final.bin"));
  EXPECT_EQ(test::readText(dir / "cont" / "deformable_sheet_000002.vtp"),
            test::readText(dir / "full" / "deformable_sheet_000004.vtp"))
      << "the continued run's third frame (t = 0.2 s) is the full run's fifth";
  // The continued run lists exactly the full run's springs that broke after t = 0.1 s.
  std::vector<std::string> after;
  for (const std::string& row : lines(test::readText(dir / "full" / "broken_springs.csv"))) {
    if (row.rfind("time_s", 0) != 0 && std::stod(row) > 0.1) after.push_back(row);
  }
  std::vector<std::string> continued = lines(test::readText(dir / "cont" / "broken_springs.csv"));
  continued.erase(continued.begin());
  EXPECT_EQ(continued, after);
}

}  // namespace
}  // namespace demlink::server
