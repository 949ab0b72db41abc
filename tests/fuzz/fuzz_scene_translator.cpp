/// libFuzzer target: scene JSON through the loader, the translators and the world's first
/// steps, as demlink-run reads a scene file. Checked: every refusal is a core::InputError
/// (anything else thrown aborts), no crash or sanitizer report, and a scene that is
/// accepted steps to finite positions and velocities.
///
/// Seeds: the small valid scene and variants with extreme finite values (1e308, -1e308,
/// 5e-324, DBL_MAX in gravity, the room's motion, lattice velocity and spacing,
/// orientations, time step, client timeout), long names and names with control bytes,
/// file paths outside the scene's folder, and deep nesting.
#include <spdlog/spdlog.h>
#include <unistd.h>

#include <algorithm>
#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

#include "demlink/core/base/input_error.hpp"
#include "demlink/server/scene/scene_loader.hpp"
#include "demlink/server/scene/scene_translator.hpp"
#include "fuzz_seeds.hpp"

namespace {

void check(bool condition) {
  if (!condition) std::abort();
}

/// The scene's folder: empty, so every file a scene names is refused or missing.
const std::filesystem::path& sceneFolder() {
  static const std::filesystem::path folder = [] {
    const std::filesystem::path p =
        std::filesystem::temp_directory_path() / ("demlink_fuzz_scene_" + std::to_string(getpid()));
    std::filesystem::create_directories(p);
    return p;
  }();
  return folder;
}

/// Bounds the work one input asks for (sphere counts, steps), so the fuzzer spends its
/// time on validation rather than on legitimately large scenes: lattices above 1000
/// spheres are skipped (the memory limit itself is tested in tests/server).
bool smallEnough(const demlink::v1::Scene& scene) {
  for (const demlink::v1::ComponentDeclaration& c : scene.components()) {
    if (!c.has_particle_lattice()) continue;
    const demlink::v1::LatticeCounts& n = c.particle_lattice().counts();
    if (static_cast<double>(n.nx()) * n.ny() * n.nz() > 1000.0) return false;
  }
  return true;
}

std::string sceneWith(const std::string& box, const std::string& material, const std::string& extra) {
  return R"({"components": [{"name": "box", "simulation_box": {"time_step": 1e-5, "end_time": 1e-3)" +
         (box.empty() ? "" : ", " + box) + R"(}}, {"name": "glass", "material": {"density": 2500)" +
         (material.empty() ? "" : ", " + material) + R"(}}, {"name": "spheres", "particle_lattice": {"material":
         "glass", "radius": 0.002, "spacing": 0.006, "origin": {"z": 0.003}, "counts": {"nx": 2, "ny": 2, "nz": 2})" +
         (extra.empty() ? "" : ", " + extra) + "}}]}";
}

}  // namespace

extern "C" int LLVMFuzzerInitialize(int* /*argc*/, char*** /*argv*/) {
  demlink::fuzz::silenceProtobufLog();
  spdlog::set_level(spdlog::level::off);
  std::vector<std::string> seeds = {demlink::fuzz::kSeedSceneJson};
  for (const char* value : {"1e308", "-1e308", "5e-324", "1.7976931348623157e308", "-0"}) {
    const std::string v = value;
    seeds.push_back(sceneWith(R"("gravity": {"z": )" + v + "}", "", ""));
    seeds.push_back(sceneWith(R"("frame": {"angular_velocity": {"z": )" + v + R"(}, "origin": {"x": )" + v + "}}", "",
                              ""));
    seeds.push_back(sceneWith(R"("time_step": )" + v + R"(, "allow_unsafe_time_step": true)", "", ""));
    seeds.push_back(sceneWith(R"("coupling": {"client_timeout": )" + v + "}", "", ""));
    seeds.push_back(sceneWith("", R"("youngs_modulus": )" + v, ""));
    seeds.push_back(sceneWith("", "", R"("velocity": {"z": )" + v + "}"));
    seeds.push_back(sceneWith("", "", R"("spacing": )" + v));
    seeds.push_back(sceneWith("", "", R"("orientation": {"w": )" + v + R"(, "x": )" + v + "}"));
  }
  seeds.push_back(sceneWith(R"("threads": 4294967295)", "", ""));
  seeds.push_back(sceneWith("", R"("name": ")" + std::string(5000, 'n') + "\"", ""));
  seeds.push_back(sceneWith("", R"("name": "a\n[00:00:00] error: forged\u001b[31m")", ""));
  seeds.push_back(sceneWith(R"("coupling": {"expected_names": [")" + std::string(300, 'e') + R"("]})", "", ""));
  seeds.push_back(R"({"components": [{"name": "box", "simulation_box": {"end_time": 1}}, {"name": "g", "material": {}},
      {"name": "m", "mesh_body": {"material": "g", "stl_file": "../../../etc/passwd"}},
      {"name": "p", "particle_file": {"material": "g", "path": "/dev/zero"}}]})");
  seeds.push_back(std::string(100, '[') + std::string(100, ']'));
  seeds.push_back(R"({"components": )" + std::string(70, '[') + std::string(70, ']') + "}");
  demlink::fuzz::writeSeedsIfAsked(seeds);
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string json(reinterpret_cast<const char*>(data), size);
  try {
    const demlink::v1::Scene scene = demlink::server::parseSceneJson(json, "fuzz.json");
    if (!smallEnough(scene)) return 0;
    demlink::server::TranslatedScene translated = demlink::server::translateScene(scene, sceneFolder());
    demlink::core::World& world = translated.world;
    world.initialize();
    for (int step = 0; step < 5; ++step) world.step();
    const demlink::core::ParticleArrays& p = world.particles();
    for (std::size_t i = 0; i < p.size(); ++i) check(p.position[i].allFinite() && p.velocity[i].allFinite());
  } catch (const demlink::core::InputError& error) {
    // Outside text in a value is escaped (log_text.hpp): one line, no terminal escapes.
    check(error.value().find('\n') == std::string::npos && error.value().find('\x1b') == std::string::npos);
  }
  return 0;
}
