/// Whole scenes end in the same bits on one thread and on two: the final checkpoint
/// (particles, meshes, deformable nodes, bonds, sensors' and sources' state) of each
/// example scene that exercises one kind of wall or component is byte-for-byte the same,
/// but for the one field that records the thread count the run used.
/// The engine's determinism tests cover the particle bed; these cover what the step does
/// around it (mesh contacts, deformable bodies, bonds, sinks and sensors, insertion).
#include <gtest/gtest.h>

#include <cstring>
#include <filesystem>
#include <stdexcept>
#include <string>

#include "demlink/core/checkpoint_file.hpp"
#include "demlink/core/simulation_settings.hpp"
#include "demlink/server/run/headless_runner.hpp"
#include "demlink/server/scene/scene_loader.hpp"
#include "demlink/server/scene/scene_translator.hpp"
#include "test_support.hpp"

namespace demlink::server {
namespace {

/// The thread count the settings section (SETT) records: its last four bytes (world_checkpoint.cpp
/// writes it last; a restore reads and ignores it). Zeroed in `checkpoint`, returned.
std::uint32_t takeThreadCount(std::string& checkpoint) {
  const std::size_t tag = checkpoint.find("SETT");
  if (tag == std::string::npos) throw std::runtime_error("the checkpoint has no SETT section");
  std::uint64_t length = 0;
  std::memcpy(&length, checkpoint.data() + tag + 4, sizeof length);
  const std::size_t at = tag + 4 + sizeof length + length - sizeof(std::uint32_t);
  std::uint32_t threads = 0;
  std::memcpy(&threads, checkpoint.data() + at, sizeof threads);
  std::memset(checkpoint.data() + at, 0, sizeof threads);
  return threads;
}

/// The scene `file` run for `steps` steps on `threads` threads into `out`; returns the
/// bytes of its final checkpoint.
std::string finalCheckpoint(const std::filesystem::path& file, std::uint32_t threads, std::uint64_t steps,
                            const std::filesystem::path& out) {
  v1::Scene scene = loadSceneFile(file.string());
  for (v1::ComponentDeclaration& component : *scene.mutable_components()) {
    if (!component.has_simulation_box()) continue;
    v1::SimulationBox& box = *component.mutable_simulation_box();
    box.set_threads(threads);
    box.set_end_time(static_cast<double>(steps) * box.time_step());
  }
  TranslatedScene translated = translateScene(scene, file.parent_path());
  translated.run.output_directory = out.string();
  translated.run.final_checkpoint = true;
  runHeadless(translated);
  return test::readText(out / core::kFinalCheckpointFileName);
}

struct SceneCase {
  const char* file;     ///< under examples/
  std::uint64_t steps;  ///< long enough for the scene's contacts to form
};

class SceneBitIdentity : public ::testing::TestWithParam<SceneCase> {};

TEST_P(SceneBitIdentity, OneAndTwoThreadsWriteTheSameFinalCheckpoint) {
  ASSERT_GE(core::maxThreads(), 2u);
  const test::ScratchDir scratch;
  const std::filesystem::path file = std::filesystem::path(DEMLINK_EXAMPLES_DIR) / GetParam().file;
  std::string one = finalCheckpoint(file, 1, GetParam().steps, scratch.path() / "one");
  std::string two = finalCheckpoint(file, 2, GetParam().steps, scratch.path() / "two");
  ASSERT_GT(one.size(), 0u);
  ASSERT_EQ(one.size(), two.size());
  EXPECT_EQ(takeThreadCount(one), 1u);  // the runs did use the threads asked for
  EXPECT_EQ(takeThreadCount(two), 2u);
  EXPECT_TRUE(one == two) << GetParam().file << ": the final checkpoints differ";
}

INSTANTIATE_TEST_SUITE_P(Examples, SceneBitIdentity,
                         ::testing::Values(SceneCase{"scenes/chute_and_paddle.json", 3000},   // moving meshes
                                           SceneCase{"scenes/sensors_and_sink.json", 3000},   // sink, sensors
                                           SceneCase{"scenes/bonded_bed.json", 2000},         // parallel bonds
                                           SceneCase{"scenes/facet_bodies.json", 2000},       // facet bodies
                                           SceneCase{"scenes/clump_source.json", 2000},       // clumps inserted
                                           SceneCase{"deformable/sheet_impact.json", 300}),   // mass-spring sheet
                         [](const ::testing::TestParamInfo<SceneCase>& param) {
                           std::string name = std::filesystem::path(param.param.file).stem().string();
                           for (char& c : name) {
                             if (c == '-') c = '_';
                           }
                           return name;
                         });

}  // namespace
}  // namespace demlink::server
