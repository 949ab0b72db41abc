// The post-run viewer's reader on files written by the run's own VTK writer.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "demlink/core/base/input_error.hpp"
#include "demlink/core/output/vtk_writer.hpp"
#include "demlink/server/view/recorded_run.hpp"

namespace demlink::server {
namespace {

namespace fs = std::filesystem;

core::ParticleArrays particlesAt(double shift) {
  core::ParticleArrays particles;
  for (int k = 0; k < 5; ++k) {
    core::ParticleSpec spec;
    spec.position = core::Vec3(0.1 * k + shift, -0.2, 0.3);
    spec.velocity = core::Vec3(0.0, 3.0, 4.0);
    spec.radius = 0.01 + 0.001 * k;
    spec.material = static_cast<std::uint32_t>(k % 2);
    particles.append(spec, 2500.0, 100 + static_cast<std::uint64_t>(k));
  }
  return particles;
}

fs::path writeRun(const std::string& name, core::VtkEncoding encoding) {
  const fs::path dir = fs::temp_directory_path() / ("demlink_recorded_" + name);
  fs::remove_all(dir);
  fs::create_directories(dir);
  std::vector<core::PvdEntry> entries, meshEntries;
  for (int frame = 0; frame < 3; ++frame) {
    const std::string file = "particles_00000" + std::to_string(frame) + ".vtp";
    core::writeParticlesVtp((dir / file).string(), particlesAt(0.5 * frame), encoding);
    entries.push_back({0.25 * frame, file});
    const std::vector<core::Vec3> vertices{{0.0 + frame, 0, 0}, {1.0 + frame, 0, 0}, {0.0 + frame, 1, 0}};
    const std::vector<std::array<std::uint32_t, 3>> triangles{{0, 1, 2}};
    const std::string meshFile = "meshes_00000" + std::to_string(frame) + ".vtp";
    core::writeMeshVtp((dir / meshFile).string(), vertices, triangles, encoding);
    meshEntries.push_back({0.25 * frame, meshFile});
  }
  core::writePvd((dir / "particles.pvd").string(), entries);
  core::writePvd((dir / "meshes.pvd").string(), meshEntries);
  // A mass-spring square of two triangles and five springs whose first spring (nodes 0-1)
  // has torn by frame 2, taking the triangle along it.
  std::vector<core::PvdEntry> sheetEntries;
  const std::vector<core::Vec3> nodes{{0, 0, 0}, {0.1, 0, 0}, {0.1, 0.1, 0}, {0, 0.1, 0}};
  const std::vector<core::Vec3> zero(nodes.size(), core::Vec3::Zero());
  const std::vector<std::array<std::uint32_t, 2>> springs{{0, 1}, {1, 2}, {2, 3}, {3, 0}, {0, 2}};
  const std::vector<std::array<std::uint32_t, 3>> triangles{{0, 1, 2}, {0, 2, 3}};
  for (int frame = 0; frame < 3; ++frame) {
    const std::vector<char> intact{frame < 2 ? char{1} : char{0}, 1, 1, 1, 1};
    const std::vector<char> active{frame < 2 ? char{1} : char{0}, 1};
    const std::string file = "deformable_sheet_00000" + std::to_string(frame) + ".vtp";
    core::writeDeformableVtp((dir / file).string(), {nodes, zero, zero, springs, intact, triangles, active}, encoding);
    sheetEntries.push_back({0.25 * frame, file});
  }
  core::writePvd((dir / "deformable_sheet.pvd").string(), sheetEntries);
  return dir;
}

TEST(RecordedRun, ReadsTheRunsOwnFilesInBothEncodings) {
  for (const core::VtkEncoding encoding : {core::VtkEncoding::AppendedRaw, core::VtkEncoding::Ascii}) {
    const fs::path dir = writeRun(encoding == core::VtkEncoding::Ascii ? "ascii" : "raw", encoding);
    RecordedRun run(dir, "OUTPUT_DIR");
    ASSERT_EQ(run.frameCount(), 3u);
    EXPECT_EQ(run.frameTime(2), 0.5);
    EXPECT_NE(run.sceneJson().find(R"("name":"meshes","triangles":[0,1,2],"springs":[]})"), std::string::npos)
        << run.sceneJson();
    EXPECT_NE(run.sceneJson().find(R"("name":"sheet","triangles":[0,1,2,0,2,3],"springs":[0,1,1,2,2,3,3,0,0,2]})"),
              std::string::npos)
        << run.sceneJson();
    std::uint64_t version = 0;
    const ViewSnapshot* frame = run.snapshot(2, version);
    EXPECT_EQ(version, 3u);
    ASSERT_EQ(frame->particleCount(), 5u);
    EXPECT_FLOAT_EQ(frame->position[3 * 4], static_cast<float>(0.4 + 1.0));
    EXPECT_FLOAT_EQ(frame->radius[4], 0.014f);
    EXPECT_FLOAT_EQ(frame->speed[0], 5.0f);
    EXPECT_EQ(frame->id[3], 103u);
    EXPECT_EQ(frame->material[3], 1u);
    EXPECT_EQ(frame->status.time, 0.5);
    ASSERT_EQ(frame->surfaces.size(), 2u);  // the meshes, then the sheet
    EXPECT_FLOAT_EQ(frame->surfaces[0].positions[3], 3.0f);  // the mesh's second vertex at frame 2
    EXPECT_EQ(frame->surfaces[0].spring_intact, std::vector<std::uint8_t>{}) << "a rigid mesh has no springs";
    EXPECT_EQ(frame->surfaces[1].spring_intact, (std::vector<std::uint8_t>{0, 1, 1, 1, 1})) << "torn by frame 2";
    EXPECT_EQ(frame->surfaces[1].triangle_active, (std::vector<std::uint8_t>{0, 1}));
    frame = run.snapshot(1, version);
    EXPECT_EQ(frame->surfaces[1].spring_intact, (std::vector<std::uint8_t>{1, 1, 1, 1, 1})) << "intact at frame 1";
    EXPECT_EQ(frame->surfaces[1].triangle_active, (std::vector<std::uint8_t>{1, 1}));
    run.snapshot(99, version);  // clamped to the last frame
    EXPECT_EQ(version, 3u);
  }
}

TEST(RecordedRun, RefusesWhatIsNotARun) {
  const fs::path empty = fs::temp_directory_path() / "demlink_recorded_empty";
  fs::remove_all(empty);
  fs::create_directories(empty);
  try {
    RecordedRun run(empty, "OUTPUT_DIR");
    FAIL() << "an empty folder was accepted";
  } catch (const core::InputError& error) {
    EXPECT_NE(std::string(error.what()).find("OUTPUT_DIR"), std::string::npos);
    EXPECT_NE(std::string(error.what()).find("no particles.pvd"), std::string::npos);
  }
  // A frame cut short: its error names the file.
  const fs::path dir = writeRun("truncated", core::VtkEncoding::AppendedRaw);
  const fs::path frame = dir / "particles_000001.vtp";
  fs::resize_file(frame, fs::file_size(frame) / 2);
  RecordedRun run(dir, "OUTPUT_DIR");
  std::uint64_t version = 0;
  try {
    run.snapshot(1, version);
    FAIL() << "a truncated frame was accepted";
  } catch (const core::InputError& error) {
    EXPECT_NE(std::string(error.what()).find("particles_000001.vtp"), std::string::npos) << error.what();
  }
}

}  // namespace
}  // namespace demlink::server
