/// Saved state through the server: the ParticleSystem component (CSV and
/// checkpoint sources, errors with line and column), the particle CSV round trip,
/// determinism of a translated example scene, and demlink-run's checkpoints,
/// --restore and run_log.csv.
#include <gtest/gtest.h>
#include <sys/wait.h>

#include <cstdlib>
#include <cstring>
#include <fstream>
#include <sstream>

#include "demlink/core/checkpoint_file.hpp"
#include "demlink/core/base/input_error.hpp"
#include "demlink/core/components/particle_source.hpp"
#include "demlink/server/scene/particle_csv.hpp"
#include "demlink/server/scene/scene_loader.hpp"
#include "demlink/server/scene/scene_translator.hpp"
#include "test_support.hpp"
#include "scene_test_support.hpp"

namespace demlink::server {
namespace {

const std::filesystem::path kScenes = std::filesystem::path(DEMLINK_EXAMPLES_DIR) / "scenes";

constexpr const char* kBox = R"({"name": "box", "simulation_box": {"end_time": 0.01, "time_step": 1e-5}})";
constexpr const char* kGlass = R"({"name": "glass", "material": {"youngs_modulus": 5e6}})";
constexpr const char* kSteel = R"({"name": "steel", "material": {"density": 7800, "youngs_modulus": 2e7}})";
constexpr const char* kFloor = R"({"name": "floor", "plane": {"normal": {"z": 1}, "material": "glass"}})";

using test::sceneOf;

std::string systemFrom(const std::string& key, const std::filesystem::path& file) {
  return R"({"name": "bed", "particle_system": {")" + key + R"(": ")" + file.string() + R"("}})";
}

core::InputError translationError(const v1::Scene& scene, const std::filesystem::path& dir = {}) {
  try {
    (void)translateScene(scene, dir);
  } catch (const core::InputError& error) {
    return error;
  }
  ADD_FAILURE() << "expected an InputError";
  return core::InputError("(none)", "", "");
}

/// FNV-1a over the bytes of every particle column, in slot order.
std::uint64_t columnsHash(const core::ParticleArrays& p) {
  std::uint64_t h = 1469598103934665603ull;
  p.forEachColumn([&](const char*, const auto& column) {
    const auto* bytes = reinterpret_cast<const unsigned char*>(column.data());
    for (std::size_t k = 0; k < column.size() * sizeof(column[0]); ++k) h = (h ^ bytes[k]) * 1099511628211ull;
  });
  return h;
}

TEST(ParticleSystem, CsvRoundTripReproducesEveryValue) {
  const test::ScratchDir scratch;
  // A moving pile of two materials, written after some steps (non-round numbers).
  TranslatedScene a = translateScene(loadSceneFile((kScenes / "particle_system.json").string()), kScenes);
  a.world.initialize();
  for (int n = 0; n < 300; ++n) a.world.step();
  const std::filesystem::path csv = scratch.path() / "set.csv";
  writeParticleCsv(a.world, csv);

  // Load it into a scene that declares the materials in the other order.
  TranslatedScene b = translateScene(sceneOf({kBox, kSteel, kGlass, systemFrom("csv_file", csv)}), {});
  const core::ParticleArrays& pa = a.world.particles();
  const core::ParticleArrays& pb = b.world.particles();
  ASSERT_EQ(pb.size(), pa.size());
  std::vector<std::size_t> slotOfId(pa.size() + 1);
  for (std::size_t i = 0; i < pa.size(); ++i) slotOfId[pa.id[i]] = i;
  for (std::size_t k = 0; k < pb.size(); ++k) {
    // The world assigns ids 1..N in file order, and the file is in id order.
    const std::size_t i = slotOfId[pb.id[k]];
    EXPECT_TRUE(pb.position[k] == pa.position[i]) << k;
    EXPECT_TRUE(pb.velocity[k] == pa.velocity[i]) << k;
    EXPECT_EQ(pb.radius[k], pa.radius[i]);
    EXPECT_EQ(b.world.materials()[pb.material[k]].name, a.world.materials()[pa.material[i]].name);
    EXPECT_EQ(pb.mass[k], pa.mass[i]) << "same density through the material name";
  }
}

TEST(ParticleSystem, CheckpointSourceTakesParticlesAndMapsMaterialsByName) {
  const test::ScratchDir scratch;
  TranslatedScene a = translateScene(loadSceneFile((kScenes / "particle_system.json").string()), kScenes);
  a.world.initialize();
  for (int n = 0; n < 300; ++n) a.world.step();
  const std::filesystem::path file = scratch.path() / "a.bin";
  core::writeCheckpointFile(a.world, file);

  TranslatedScene b = translateScene(sceneOf({kBox, kSteel, kGlass, kFloor, systemFrom("checkpoint_file", file)}), {});
  const core::ParticleArrays& pa = a.world.particles();
  const core::ParticleArrays& pb = b.world.particles();
  ASSERT_EQ(pb.size(), pa.size());
  for (std::size_t i = 0; i < pa.size(); ++i) {
    EXPECT_TRUE(pb.position[i] == pa.position[i]);
    EXPECT_TRUE(pb.velocity[i] == pa.velocity[i]);
    EXPECT_TRUE(pb.angular_velocity[i] == pa.angular_velocity[i]);
    EXPECT_EQ(pb.radius[i], pa.radius[i]);
    EXPECT_EQ(b.world.materials()[pb.material[i]].name, a.world.materials()[pa.material[i]].name);
  }
  // A scene without "steel" cannot take the set.
  const core::InputError e = translationError(sceneOf({kBox, kGlass, systemFrom("checkpoint_file", file)}));
  EXPECT_EQ(e.field(), "components[2].particle_system.checkpoint_file material") << e.what();
  EXPECT_EQ(e.value(), "\"steel\"");
  // Garbage is refused naming the file.
  test::writeText(scratch.path() / "junk.bin", "not a checkpoint at all");
  const core::InputError junk =
      translationError(sceneOf({kBox, kGlass, systemFrom("checkpoint_file", scratch.path() / "junk.bin")}));
  EXPECT_NE(junk.field().find("junk.bin"), std::string::npos) << junk.what();
}

TEST(ParticleSystem, BadCsvNamesLineAndColumn) {
  const std::string header = "id,x,y,z,vx,vy,vz,radius,material\n";
  struct Case {
    std::string text;
    std::string field;   ///< expected suffix of the error's field
    std::string reason;  ///< expected part of the message
  };
  const std::vector<Case> cases = {
      {"id,x,y,z,r\n1,0,0,0,1\n", "set.csv:line 1", "expected the header"},
      {header + "1,0,0,0.1,0,0,0,0.002\n", "set.csv:line 2", "expected 9 columns"},
      {header + "\n1,0,0,0.1,0,0,0,0.002,glass\n2,0,0.01,abc,0,0,0,0.002,glass\n", "set.csv:line 4",
       "column 4 (z): is not a number"},
      {header + "1,0,0,0.1,0,0,nan,0.002,glass\n", "set.csv:line 2", "column 7 (vz): must be finite"},
      {header + "1,0,0,0.1,0,0,0,-0.002,glass\n", "set.csv:line 2", "column 8 (radius): must be > 0"},
      {header + "-1,0,0,0.1,0,0,0,0.002,glass\n", "set.csv:line 2", "column 1 (id)"},
      {header + "1,0,0,0.1,0,0,0,0.002,glass\n1,0,0.01,0.1,0,0,0,0.002,glass\n", "set.csv:line 3",
       "id already used on line 2"},
      {header + "1,0,0,0.1,0,0,0,0.002,\n", "set.csv:line 2", "column 9 (material): is empty"},
      {header, "set.csv", "contains no particles"},
      {"", "set.csv", "expected the header"},
      {header + "1,0,0,0.1,0,0,0,0.002,sand\n", "set.csv:line 2 column 9 (material)", "not declared"},
  };
  const test::ScratchDir scratch;
  for (const Case& c : cases) {
    SCOPED_TRACE(c.text);
    test::writeText(scratch.path() / "set.csv", c.text);
    const core::InputError e = translationError(sceneOf({kBox, kGlass, systemFrom("csv_file", "set.csv")}),
                                                scratch.path());
    EXPECT_TRUE(e.field().ends_with(c.field)) << e.what();
    EXPECT_NE(std::string(e.what()).find(c.reason), std::string::npos) << e.what();
  }
  const core::InputError missing = translationError(sceneOf({kBox, kGlass, systemFrom("csv_file", "none.csv")}),
                                                    scratch.path());
  EXPECT_EQ(missing.field(), "components[2].particle_system.csv_file");
  const core::InputError noSource = translationError(sceneOf({kBox, kGlass, R"({"name": "s", "particle_system": {}})"}));
  EXPECT_EQ(noSource.field(), "components[2].particle_system");
}

TEST(Determinism, ExampleSceneRunTwiceIsBitIdentical) {
  // The whole path: scene file -> translator -> world; every column hashed.
  std::vector<std::uint64_t> hashes;
  for (int run = 0; run < 2; ++run) {
    TranslatedScene t = translateScene(loadSceneFile((kScenes / "particle_system.json").string()), kScenes);
    t.world.initialize();
    for (int n = 0; n < 3000; ++n) t.world.step();
    hashes.push_back(columnsHash(t.world.particles()));
  }
  EXPECT_EQ(hashes[0], hashes[1]);
  // The hash sees a change: one more step changes it.
  TranslatedScene t = translateScene(loadSceneFile((kScenes / "particle_system.json").string()), kScenes);
  t.world.initialize();
  for (int n = 0; n < 3001; ++n) t.world.step();
  EXPECT_NE(columnsHash(t.world.particles()), hashes[0]);
}

/// Runs the example with a seeded particle source (source_linear_paper.json, its seed
/// replaced by `seed`) for `steps` steps; returns the column hash and the inserted count.
std::pair<std::uint64_t, std::uint64_t> runSourceExample(const std::string& seed, int steps) {
  std::string json = test::readText(kScenes / "source_linear_paper.json");
  const std::string key = R"("seed": "2024")";
  const std::size_t at = json.find(key);
  EXPECT_NE(at, std::string::npos) << "the example's seed changed; update this test";
  if (at != std::string::npos) json.replace(at, key.size(), R"("seed": ")" + seed + "\"");
  TranslatedScene t = translateScene(parseSceneJson(json, "source_linear_paper.json"), kScenes);
  t.world.initialize();
  for (int n = 0; n < steps; ++n) t.world.step();
  std::uint64_t inserted = 0;
  for (const auto& component : t.world.components()) {
    if (const auto* source = dynamic_cast<const core::ParticleSource*>(component.get())) {
      inserted += source->report().inserted_count;
    }
  }
  return {columnsHash(t.world.particles()), inserted};
}

TEST(Determinism, SceneWithSeededSourceRunTwiceIsBitIdentical) {
  // 1.6 s at 5e-4 s: about 400 spheres inserted while the first ones already pile up.
  constexpr int kSteps = 3200;
  const auto first = runSourceExample("2024", kSteps);
  const auto second = runSourceExample("2024", kSteps);
  ASSERT_GT(first.second, 300u) << "the source inserted too little for the test to mean much";
  EXPECT_EQ(first.second, second.second);
  EXPECT_EQ(first.first, second.first);
  // The hash sees the seed: another seed places the spheres elsewhere.
  EXPECT_NE(runSourceExample("2025", kSteps).first, first.first);
}

int runTool(const std::vector<std::string>& arguments, const std::filesystem::path& log) {
  std::string command;
  command.append("\"").append(DEMLINK_RUN_EXE).append("\"");
  for (const std::string& argument : arguments) command.append(" \"").append(argument).append("\"");
  command.append(" > \"").append(log.string()).append("\" 2>&1");
  const int status = std::system(command.c_str());
  return status != -1 && WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

std::string withCheckpoints(double endTime) {
  std::string json = test::tinySceneJson(endTime, 0.0025);
  const std::string key = R"("vtk_interval": )";
  json.insert(json.find(key), R"("checkpoint_interval": 0.004, )");
  return json;
}

TEST(DemlinkRunState, RestoredRunEndsWhereTheUninterruptedRunEnds) {
  const test::ScratchDir scratch;
  const std::filesystem::path& dir = scratch.path();
  test::writeText(dir / "tiny.json", withCheckpoints(0.012));
  ASSERT_EQ(runTool({(dir / "tiny.json").string(), "--quiet", "--output", (dir / "full").string()}, dir / "a.log"), 0)
      << test::readText(dir / "a.log");
  for (const char* name : {"checkpoint_000001.bin", "checkpoint_000002.bin", "checkpoint_000003.bin",
                           "checkpoint_final.bin", "particles_final.csv", "run_log.csv"}) {
    EXPECT_TRUE(std::filesystem::exists(dir / "full" / name)) << name;
  }
  ASSERT_EQ(runTool({(dir / "tiny.json").string(), "--quiet", "--output", (dir / "cont").string(), "--restore",
                     (dir / "full" / "checkpoint_000001.bin").string()},
                    dir / "b.log"),
            0)
      << test::readText(dir / "b.log");
  const std::string full = test::readText(dir / "full" / "particles_final.csv");
  EXPECT_EQ(test::readText(dir / "cont" / "particles_final.csv"), full);
  EXPECT_EQ(test::countOccurrences(full, "\n"), 9u) << "header + 8 spheres";
  // Same final state, so the same final checkpoint, byte for byte.
  EXPECT_TRUE(test::readText(dir / "cont" / "checkpoint_final.bin") ==
              test::readText(dir / "full" / "checkpoint_final.bin"));
  const std::string log = test::readText(dir / "cont" / "run_log.csv");
  EXPECT_NE(log.find("config,start_time,0.004,s"), std::string::npos) << log;
  EXPECT_NE(log.find("timing,steps,800,"), std::string::npos) << log;
  EXPECT_NE(log.find("timing,status,completed"), std::string::npos) << log;
}

TEST(DemlinkRunState, RunLogHoldsConfigurationAndTiming) {
  const test::ScratchDir scratch;
  const std::filesystem::path& dir = scratch.path();
  test::writeText(dir / "tiny.json", test::tinySceneJson(0.005, 0.0025));
  ASSERT_EQ(runTool({(dir / "tiny.json").string(), "--quiet", "--output", (dir / "out").string()}, dir / "a.log"), 0);
  const std::string log = test::readText(dir / "out" / "run_log.csv");
  EXPECT_EQ(log.rfind("section,key,value,unit\n", 0), 0u);
  for (const char* row : {"config,time_step,1e-05,s", "config,contact_model,hertz_mindlin,",
                          "config,integrator,velocity_verlet,", "config,threads,1,", "config,particles,8,",
                          "config,critical_time_step,", "config,neighbour_skin,", "config,active_stages,",
                          "timing,steps,500,", "timing,steps_per_second,", "timing,particle_steps_per_second,",
                          "timing,neighbour_builds,", "timing,total_wall,", "timing,status,completed"}) {
    EXPECT_NE(log.find(row), std::string::npos) << row << "\n" << log;
  }
  // Every row has four fields (values with commas are quoted).
  std::istringstream rows(log);
  for (std::string line; std::getline(rows, line);) {
    std::size_t commas = 0;
    bool quoted = false;
    for (char c : line) {
      if (c == '"') quoted = !quoted;
      if (c == ',' && !quoted) ++commas;
    }
    EXPECT_EQ(commas, 3u) << line;
  }
}

TEST(DemlinkRunState, AbortedRunLeavesAValidRunLog) {
  const test::ScratchDir scratch;
  const std::filesystem::path& dir = scratch.path();
  // A material name with a comma cannot be written to particles_final.csv: the run fails at
  // its very end (a fresh output folder, so the failure is not the folder policy's).
  std::string scene = test::tinySceneJson(0.002, 0.001);
  for (std::size_t at = scene.find("\"glass\""); at != std::string::npos; at = scene.find("\"glass\"", at)) {
    scene.replace(at, 7, "\"gl,ass\"");
  }
  test::writeText(dir / "tiny.json", scene);
  EXPECT_EQ(runTool({(dir / "tiny.json").string(), "--quiet", "--output", (dir / "out").string()}, dir / "a.log"), 1);
  const std::string log = test::readText(dir / "out" / "run_log.csv");
  EXPECT_NE(log.find("config,time_step,1e-05,s"), std::string::npos) << log;
  EXPECT_NE(log.find("timing,status,"), std::string::npos) << log;
  EXPECT_NE(log.find("aborted: "), std::string::npos) << log;
  EXPECT_EQ(log.find("completed"), std::string::npos);
}

TEST(DemlinkRunState, BadRestoreFileExitsTwoNamingTheFile) {
  const test::ScratchDir scratch;
  const std::filesystem::path& dir = scratch.path();
  test::writeText(dir / "tiny.json", test::tinySceneJson(0.002, 0.001));
  test::writeText(dir / "junk.bin", "DEMLCKPT and then nothing sensible");
  EXPECT_EQ(runTool({(dir / "tiny.json").string(), "--output", (dir / "out").string(), "--restore",
                     (dir / "junk.bin").string()},
                    dir / "a.log"),
            2);
  const std::string output = test::readText(dir / "a.log");
  EXPECT_NE(output.find("junk.bin"), std::string::npos) << output;
  // A checkpoint of another scene (other material stiffness) is refused too.
  test::writeText(dir / "other.json", test::tinySceneJson(0.002, 0.001));
  ASSERT_EQ(runTool({(dir / "other.json").string(), "--quiet", "--output", (dir / "o").string()}, dir / "b.log"), 0);
  std::string changed = test::readText(dir / "tiny.json");
  changed.replace(changed.find("5e6"), 3, "6e6");
  test::writeText(dir / "changed.json", changed);
  EXPECT_EQ(runTool({(dir / "changed.json").string(), "--output", (dir / "c").string(), "--restore",
                     (dir / "o" / "checkpoint_final.bin").string()},
                    dir / "c.log"),
            2);
  EXPECT_NE(test::readText(dir / "c.log").find("materials"), std::string::npos) << test::readText(dir / "c.log");
  // A checkpoint at the end time leaves nothing to run.
  EXPECT_EQ(runTool({(dir / "other.json").string(), "--output", (dir / "d").string(), "--restore",
                     (dir / "o" / "checkpoint_final.bin").string()},
                    dir / "d.log"),
            2);
  EXPECT_NE(test::readText(dir / "d.log").find("end_time"), std::string::npos) << test::readText(dir / "d.log");
}

}  // namespace
}  // namespace demlink::server
