/// demlink-bench-unused: a scene pays nothing measurable for what it does not use.
///
/// Each pair runs the same bed (400 spheres settling in a box, `--steps` steps,
/// default 2000) as A and B, alternating A B A B ... `--repeats` times, and prints
/// the median CPU seconds of each, their ratio, and the median of the ratios of
/// neighbouring A, B runs (less sensitive to load that drifts during the runs):
///   watchdog        off (every_steps 0) vs every 100 steps (the default)
///   stage timing    off vs on (sampled: two clock reads per stage call on ~1 step in 64)
///   idle mesh       none vs a mesh body whose collision window never opens
///   idle deformable none vs a small mass-spring sheet far from the bed: the deformable
///                   stages run (motion, near lists, contacts, forces) but find nothing.
///                   A scene without deformable bodies runs none of these stages at all,
///                   so B / A bounds what the deformable code can cost it.
/// Usage: demlink-bench-unused [--repeats N] [--steps N]
#include <algorithm>
#include <ctime>
#include <cstdio>
#include <functional>
#include <memory>
#include <optional>
#include <random>
#include <vector>

#include "demlink/cli/command_line.hpp"
#include "demlink/core/deformable/mass_spring_body.hpp"
#include "demlink/core/world.hpp"

namespace {

using namespace demlink::core;

struct Variant {
  bool watchdog = true;
  bool timing = false;
  bool idle_mesh = false;
  bool idle_deformable = false;
};

/// CPU seconds of this thread: on a machine shared with other jobs, wall time mostly
/// measures their load; CPU time what the bed itself costs.
double threadCpuSeconds() {
  timespec t{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t);
  return static_cast<double>(t.tv_sec) + 1e-9 * static_cast<double>(t.tv_nsec);
}

double runBed(const Variant& v, int steps) {
  SimulationSettings s;
  s.time_step = 2e-6;
  s.allow_unsafe_time_step = true;  // the cost, not the accuracy, is measured here
  s.watchdog.every_steps = v.watchdog ? 100 : 0;
  World world(s);
  Material m;
  m.name = "grains";
  world.addMaterial(m);
  world.addPlane({"floor", Vec3::Zero(), Vec3::UnitZ(), 0});
  if (v.idle_mesh) {
    MeshBody mesh("idle", {Vec3(0, 0, 1), Vec3(1, 0, 1), Vec3(0, 1, 1)}, {{0, 1, 2}}, 0);
    mesh.setCollisionWindow(1e9, 1e9);
    world.addMesh(std::move(mesh));
  }
  if (v.idle_deformable) {
    MassSpringSpec sheet;
    sheet.name = "idle";
    sheet.total_mass = 0.01;
    sheet.stiffness = 1.0;
    sheet.box = MassSpringSpec::Box{Vec3(1.0, 1.0, 1.0), Vec3(1.02, 1.02, 1.001), 0.01};
    sheet.fixed_nodes = {0, 1, 2, 3, 4, 5, 6, 7, 8};
    world.addDeformableBody(std::make_unique<MassSpringBody>(sheet, "idle"), "idle");
  }
  std::mt19937_64 rng(1);
  std::uniform_real_distribution<double> jitter(-0.0005, 0.0005);
  for (int k = 0; k < 400; ++k) {
    ParticleSpec p;
    p.radius = 0.002;
    p.position = Vec3(0.0045 * (k % 10) + jitter(rng), 0.0045 * ((k / 10) % 10) + jitter(rng), 0.003 + 0.0045 * (k / 100));
    world.addParticle(p);
  }
  world.setStageTiming(v.timing);
  world.initialize();
  const double start = threadCpuSeconds();
  for (int n = 0; n < steps; ++n) world.step();
  return threadCpuSeconds() - start;
}

double median(std::vector<double> x) {
  std::sort(x.begin(), x.end());
  return x[x.size() / 2];
}

}  // namespace

int main(int argc, char** argv) {
  int repeats = 7;
  int steps = 2000;
  CLI::App app("A/B: a scene pays nothing for features it does not use.", "demlink-bench-unused");
  demlink::cli::addWholeNumber<int>(app, "--repeats", repeats, 1, 1000, "runs of each variant (default 7)");
  demlink::cli::addWholeNumber<int>(app, "--steps", steps, 1, 10'000'000, "steps per run (default 2000)");
  if (const std::optional<int> exitCode = demlink::cli::parse(app, argc, argv)) return *exitCode;
  const struct {
    const char* name;
    Variant a;
    Variant b;
  } pairs[] = {{"watchdog off / every 100 steps", {.watchdog = false}, {.watchdog = true}},
               {"stage timing off / on", {.timing = false}, {.timing = true}},
               {"no mesh / idle mesh", {.idle_mesh = false}, {.idle_mesh = true}},
               {"no deformable / idle sheet", {.idle_deformable = false}, {.idle_deformable = true}}};
  std::printf("| A / B | median A [CPU s] | median B [CPU s] | B / A | median of pair ratios |\n|---|---|---|---|---|\n");
  for (const auto& pair : pairs) {
    std::vector<double> a;
    std::vector<double> b;
    std::vector<double> ratios;
    for (int k = 0; k < repeats; ++k) {
      a.push_back(runBed(pair.a, steps));
      b.push_back(runBed(pair.b, steps));
      ratios.push_back(b.back() / a.back());
    }
    std::printf("| %s | %.4f | %.4f | %.3f | %.3f |\n", pair.name, median(a), median(b), median(b) / median(a),
                median(ratios));
  }
  return 0;
}
