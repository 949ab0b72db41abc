/// demlink-bench-deposition: the "deposition-N" scene of bench/deposition/
/// (in.deposition, the LIGGGHTS input), run through the DEMLink core so it can be
/// compared side by side with LIGGGHTS (bench/run_deposition_compare.sh).
///
///   demlink-bench-deposition init_N.txt [--steps S] [--thermo K] [--threads T] [--dt DT]
///                            [--skin M] [--vmax V] [--rolling MU] [--window W] [--window-from S]
///   demlink-bench-deposition --generate N [--sizes mono|ratio10|cont5] [...]
///
/// --generate N builds the bed in memory instead (for the size-distribution and
/// large-N benchmarks): N spheres placed at random without overlap (biggest first)
/// in a square box, at a solid fraction of 0.25, with random velocities of up to
/// 0.5 m/s per component, so they collide while they settle. The box side is 0.1 m
/// up to 5,000 spheres and grows as N^(1/3) beyond. Radii (--sizes): mono, all 2 mm;
/// ratio10, one sphere in 20 of 5 mm, the others 0.5 mm (1:10); cont5, uniform in
/// [1, 5] mm (1:5). The skin is then the engine's default (half the smallest
/// radius) unless --skin is given, dt defaults to 2e-6 s, and the watchdog warns
/// instead of stopping (soft small spheres squeezed under large ones overlap deeply).
///
/// From step S (default 25000, the settled bed of deposition-5000) the stepping thread's
/// CPU time is taken per window of W steps (default 250); the summary gives its minimum
/// and median per step, the figures a loaded machine disturbs least (A/B comparisons).
///
/// The summary reports bytes per particle (particle columns, neighbour list and grid,
/// pair-loop plan) and how the thread pool ran (loops offered to the workers, loops
/// run on the caller alone because threading did not pay).
///
/// Scene (identical to in.deposition): spheres read from init_N.txt (id x y z r,
/// written by bench/deposition/make_particles.py), one material (rho 2500, E 5e6, nu 0.3, e 0.5,
/// mu 0.5, no rolling friction unless --rolling), Hertz-Mindlin, velocity Verlet, dt 1e-5 s,
/// gravity -9.81 z, skin 1 mm (LIGGGHTS `neighbor 0.001 bin`), planes z = 0,
/// x = 0, x = 0.1, y = 0, y = 0.1 of the same material.
///
/// Every K steps a thermo line like LIGGGHTS's `thermo_style custom step time
/// atoms c_ket c_ker c_zmx c_zav cpu` (plus a column counting particles outside
/// the box, a blow-up check); a summary at the end. Single-threaded unless
/// --threads T is given.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <exception>
#include <fstream>
#include <functional>
#include <numbers>
#include <random>
#include <unordered_map>
#include <limits>
#include <optional>
#include <sstream>
#include <string>
#include <string_view>
#include <vector>

#include "demlink/cli/command_line.hpp"
#include "demlink/core/particles/sphere.hpp"
#include "demlink/core/base/input_error.hpp"
#include "demlink/core/world.hpp"

namespace {

using demlink::core::Vec3;
using demlink::core::World;
namespace cli = demlink::cli;

constexpr double kBox = 0.1;  // [m] side of the square box (make_particles.py's box side)

struct Options {
  std::string init_file;
  std::size_t generate = 0;
  std::string sizes = "mono";
  bool skin_given = false;
  bool dt_given = false;
  std::uint64_t steps = 50000;
  std::uint64_t thermo = 5000;
  double time_step = 1.0e-5;
  double skin = 1.0e-3;
  double max_impact_velocity = 6.0;
  double rolling_friction = 0.0;  ///< --rolling: the pair loop's rolling-resistance pass (not in in.deposition)
  std::uint32_t threads = 1;
  std::uint64_t window = 250;
  std::uint64_t window_from = 25000;
  bool stage_times = false;
  bool portable_kernel = false;
  std::string save_final;
};

/// Parses the command line (demlink/cli/command_line.hpp); an exit code when the program
/// should stop now (--help, --version: 0; bad input: 2).
std::optional<int> parseOptions(int argc, char** argv, Options& o) {
  CLI::App app("The deposition benchmark scene on DEMLink's engine, side by side with LIGGGHTS.",
               "demlink-bench-deposition");
  auto* init = app.add_option("init_file", o.init_file,
                               "particles, 'id x y z r' per line (bench/deposition/make_particles.py); "
                               "'#' lines are comments")
                    ->type_name("init_N.txt");
  auto* generate = cli::addWholeNumber<std::size_t>(app, "--generate", o.generate, 1, 100000000,
                                                    "build a random bed of N spheres instead of reading a file");
  init->excludes(generate);
  app.add_option("--sizes", o.sizes, "radii of --generate: mono (2 mm), ratio10 (5 % of 5 mm, 0.5 mm), "
                                     "cont5 (uniform 1-5 mm)")
      ->check(CLI::IsMember({"mono", "ratio10", "cont5"}));
  cli::addWholeNumber<std::uint64_t>(app, "--steps", o.steps, 0, std::numeric_limits<std::uint64_t>::max(),
                                     "time steps to run (default 50000)");
  cli::addWholeNumber<std::uint64_t>(app, "--thermo", o.thermo, 0, std::numeric_limits<std::uint64_t>::max(),
                                     "thermo line every K steps (default 5000; 0 = only first and last)");
  cli::addWholeNumber<std::uint32_t>(app, "--threads", o.threads, 1, 1024,
                                     "engine threads (SimulationSettings::threads; default 1)");
  auto* dt = cli::addNumber(app, "--dt", o.time_step, {0.0, true},
                            "time step [s] (default 1e-5, as the LIGGGHTS input; 2e-6 with --generate)");
  auto* skin = cli::addNumber(app, "--skin", o.skin, {0.0}, "neighbour skin [m] (default 1e-3, as `neighbor 0.001`)");
  cli::addNumber(app, "--vmax", o.max_impact_velocity, {0.0, true},
                 "max_impact_velocity for the time-step check [m/s] (default 6)");
  cli::addNumber(app, "--rolling", o.rolling_friction, {0.0},
                 "rolling friction coefficient of the material (default 0, as in.deposition; the excavator "
                 "site's gravel has 0.25)");
  cli::addWholeNumber<std::uint64_t>(app, "--window", o.window, 1, std::numeric_limits<std::uint64_t>::max(),
                                     "steps per window of the windowed CPU time (default 250)");
  cli::addWholeNumber<std::uint64_t>(app, "--window-from", o.window_from, 0,
                                     std::numeric_limits<std::uint64_t>::max(),
                                     "first step of the windowed CPU time (default 25000: the settled bed)");
  app.add_flag("--stage-times", o.stage_times,
               "print each stage's sampled wall time per step (World::setStageTiming) at the end");
  app.add_flag("--portable-kernel", o.portable_kernel,
               "run the portable pair loop even where the AVX2/FMA one could run (SimulationSettings::portable_kernel)");
  app.add_option("--save-final", o.save_final,
                 "write the final particles to FILE as 'id x y z r' (an init file: e.g. a settled bed "
                 "to time the late steps alone)")
      ->type_name("FILE");
  if (const std::optional<int> exitCode = cli::parse(app, argc, argv)) return exitCode;
  if (o.init_file.empty() && o.generate == 0) {
    std::fprintf(stderr, "give init_N.txt or --generate N\n");
    return 2;
  }
  o.skin_given = skin->count() > 0;
  o.dt_given = dt->count() > 0;
  return std::nullopt;
}

struct InitParticle {
  Vec3 position;
  double radius;
  Vec3 velocity = Vec3::Zero();
};

/// Box side [m] of a generated bed of n spheres: 0.1 m up to 5,000, then growing as
/// n^(1/3) so the column keeps its aspect.
double generatedBoxSide(std::size_t n) { return kBox * std::max(1.0, std::cbrt(static_cast<double>(n) / 5000.0)); }

/// The --generate bed (see the file comment): random sequential placement without
/// overlap, biggest spheres first, found through a hash of cells of the largest diameter.
std::vector<InitParticle> generateBed(std::size_t n, const std::string& sizes, double box) {
  std::mt19937_64 rng(20261124);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  std::vector<double> radii(n);
  for (std::size_t k = 0; k < n; ++k) {
    if (sizes == "ratio10") {
      radii[k] = k % 20 == 0 ? 5.0e-3 : 0.5e-3;
    } else if (sizes == "cont5") {
      radii[k] = 1.0e-3 + 4.0e-3 * u(rng);
    } else {
      radii[k] = 2.0e-3;
    }
  }
  std::sort(radii.begin(), radii.end(), std::greater<>());
  double volume = 0.0;
  for (const double r : radii) volume += demlink::core::sphereVolume(r);
  const double height = volume / (0.25 * box * box);
  const double cell = 2.0 * radii.front();
  const auto keyOf = [&](const Vec3& x) {
    const auto c = [&](double v) { return static_cast<std::uint64_t>(std::max(0.0, std::floor(v / cell)) + 1.0); };
    return (c(x.z()) << 40) | (c(x.y()) << 20) | c(x.x());
  };
  std::unordered_map<std::uint64_t, std::vector<std::uint32_t>> cells;
  std::vector<InitParticle> out;
  out.reserve(n);
  for (const double r : radii) {
    for (;;) {
      const Vec3 x(r + (box - 2.0 * r) * u(rng), r + (box - 2.0 * r) * u(rng), r + (height - 2.0 * r) * u(rng));
      bool free = true;
      const std::uint64_t key = keyOf(x);
      for (std::uint64_t dz = 0; dz < 3 && free; ++dz) {
        for (std::uint64_t dy = 0; dy < 3 && free; ++dy) {
          for (std::uint64_t dx = 0; dx < 3 && free; ++dx) {
            const auto it = cells.find(key + (dz << 40) + (dy << 20) + dx - (1ull << 40) - (1ull << 20) - 1);
            if (it == cells.end()) continue;
            for (const std::uint32_t j : it->second) {
              const double reach = r + out[j].radius;
              if ((out[j].position - x).squaredNorm() < reach * reach) {
                free = false;
                break;
              }
            }
          }
        }
      }
      if (!free) continue;
      cells[key].push_back(static_cast<std::uint32_t>(out.size()));
      const Vec3 v = (Vec3(u(rng), u(rng), u(rng)) - Vec3::Constant(0.5)) * 1.0;
      out.push_back({x, r, v});
      break;
    }
  }
  return out;
}

std::vector<InitParticle> readInit(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw std::runtime_error("cannot open " + path);
  std::vector<InitParticle> out;
  std::string line;
  std::size_t lineNo = 0;
  while (std::getline(in, line)) {
    ++lineNo;
    const auto first = line.find_first_not_of(" \t\r");
    if (first == std::string::npos || line[first] == '#') continue;
    std::istringstream fields(line);
    long long id = 0;
    double x = 0.0, y = 0.0, z = 0.0, r = 0.0;
    if (!(fields >> id >> x >> y >> z >> r)) {
      throw std::runtime_error(path + ":" + std::to_string(lineNo) + ": expected 'id x y z r'");
    }
    out.push_back({Vec3(x, y, z), r});
  }
  if (out.empty()) throw std::runtime_error(path + ": no particles");
  return out;
}

struct Thermo {
  double ke_translational = 0.0;  ///< sum 1/2 m v^2 [J] (LIGGGHTS compute ke)
  double ke_rotational = 0.0;     ///< sum 1/2 I w^2 [J] (compute erotate/sphere)
  double max_z = 0.0;             ///< [m]
  double mean_z = 0.0;            ///< [m]
  std::size_t outside = 0;        ///< centres outside the box walls or below the floor
};

Thermo measure(const World& world, double box) {
  const auto& p = world.particles();
  Thermo t;
  t.max_z = p.size() > 0 ? p.position[0].z() : 0.0;
  double sumZ = 0.0;
  for (std::size_t i = 0; i < p.size(); ++i) {
    const Vec3& x = p.position[i];
    t.ke_translational += 0.5 * p.mass[i] * p.velocity[i].squaredNorm();
    t.ke_rotational += 0.5 / p.inv_inertia[i] * p.angular_velocity[i].squaredNorm();
    t.max_z = std::max(t.max_z, x.z());
    sumZ += x.z();
    if (x.x() < 0.0 || x.x() > box || x.y() < 0.0 || x.y() > box || x.z() < 0.0) ++t.outside;
  }
  t.mean_z = p.size() > 0 ? sumZ / static_cast<double>(p.size()) : 0.0;
  return t;
}

/// CPU time of the calling thread [s] (the stepping thread: load-robust for one thread).
double threadCpuSeconds() {
  timespec t{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t);
  return static_cast<double>(t.tv_sec) + 1e-9 * static_cast<double>(t.tv_nsec);
}

/// The k-th smallest of `values` (k < size).
double kthSmallest(std::vector<double> values, std::size_t k) {
  std::nth_element(values.begin(), values.begin() + static_cast<std::ptrdiff_t>(k), values.end());
  return values[k];
}

void printThermoHeader() {
  std::printf("%10s %12s %8s %14s %14s %12s %12s %10s %8s\n", "Step", "Time", "Atoms", "KinEng", "RotEng", "MaxZ",
              "MeanZ", "Wall", "Outside");
}

void printThermo(const World& world, double box, double wallSeconds) {
  const Thermo t = measure(world, box);
  std::printf("%10llu %12.6g %8zu %14.8g %14.8g %12.8g %12.8g %10.3f %8zu\n",
              static_cast<unsigned long long>(world.stepCount()), world.time(), world.particles().size(),
              t.ke_translational, t.ke_rotational, t.max_z, t.mean_z, wallSeconds, t.outside);
  std::fflush(stdout);
}

/// Writes the particles as an init file (readInit's format), full precision.
void saveParticles(const World& world, const std::string& path) {
  std::ofstream out(path);
  if (!out) throw std::runtime_error("cannot write " + path);
  const auto& p = world.particles();
  out << "# id x y z r [m], written by demlink-bench-deposition --save-final\n";
  out.precision(17);
  for (std::size_t i = 0; i < p.size(); ++i) {
    out << p.id[i] << ' ' << p.position[i].x() << ' ' << p.position[i].y() << ' ' << p.position[i].z() << ' '
        << p.radius[i] << '\n';
  }
  if (!out) throw std::runtime_error("cannot write " + path);
}

int run(const Options& o) {
  using Clock = std::chrono::steady_clock;
  const auto setupStart = Clock::now();
  const double box = o.generate > 0 ? generatedBoxSide(o.generate) : kBox;
  const std::vector<InitParticle> init = o.generate > 0 ? generateBed(o.generate, o.sizes, box) : readInit(o.init_file);

  demlink::core::SimulationSettings settings;
  settings.time_step = o.generate > 0 && !o.dt_given ? 2.0e-6 : o.time_step;
  settings.gravity = Vec3(0.0, 0.0, -9.81);
  settings.contact_model = demlink::core::ContactModel::HertzMindlin;
  settings.integrator = demlink::core::IntegratorKind::VelocityVerlet;
  settings.neighbour_skin = o.generate > 0 && !o.skin_given ? 0.0 : o.skin;
  settings.max_impact_velocity = o.max_impact_velocity;
  settings.allow_unsafe_time_step = false;
  // The LIGGGHTS input's 1e-5 s step is above the 1 % restitution limit (9.2e-6 s for this
  // glass); the comparison needs the same step, so it accepts a 10 % restitution error.
  settings.restitution_tolerance = 0.1;
  settings.threads = o.threads;
  settings.portable_kernel = o.portable_kernel;
  // Generated beds are for timing: soft spheres of 1:10 squeezed under large ones may
  // overlap beyond the watchdog's 0.5 of the smaller radius; warn instead of stopping.
  if (o.generate > 0) settings.watchdog.policy = demlink::core::GuardPolicy::Warn;
  World world(settings);

  demlink::core::Material material;
  material.name = "glass";
  material.density = 2500.0;
  material.youngs_modulus = 5.0e6;
  material.poisson_ratio = 0.3;
  material.restitution = 0.5;
  material.sliding_friction = 0.5;
  material.rolling_friction = o.rolling_friction;
  const std::uint32_t mat = world.addMaterial(material);

  for (std::size_t k = 0; k < init.size(); ++k) {
    demlink::core::ParticleSpec spec;
    spec.position = init[k].position;
    spec.radius = init[k].radius;
    spec.velocity = init[k].velocity;
    spec.material = mat;
    world.addParticle(spec, "particles[" + std::to_string(k) + "]");
  }
  struct PlaneDef {
    const char* name;
    Vec3 point;
    Vec3 normal;
  };
  const PlaneDef planes[] = {
      {"floor", Vec3(0.0, 0.0, 0.0), Vec3(0.0, 0.0, 1.0)},  {"x0", Vec3(0.0, 0.0, 0.0), Vec3(1.0, 0.0, 0.0)},
      {"x1", Vec3(box, 0.0, 0.0), Vec3(-1.0, 0.0, 0.0)},    {"y0", Vec3(0.0, 0.0, 0.0), Vec3(0.0, 1.0, 0.0)},
      {"y1", Vec3(0.0, box, 0.0), Vec3(0.0, -1.0, 0.0)},
  };
  for (const PlaneDef& def : planes) {
    demlink::core::PlaneSpec plane;
    plane.name = def.name;
    plane.point = def.point;
    plane.normal = def.normal;
    plane.material = mat;
    world.addPlane(plane, std::string("planes[") + def.name + "]");
  }
  world.initialize();
  world.setStageTiming(o.stage_times);
  const double setupSeconds = std::chrono::duration<double>(Clock::now() - setupStart).count();

  const auto& report = world.timeStepReport();
  const std::string source = o.generate > 0 ? "--generate --sizes " + o.sizes : o.init_file;
  std::printf("DEMLink deposition bench: %zu particles from %s, %llu steps, dt %g s, skin %g m, %u thread(s)\n",
              world.particles().size(), source.c_str(), static_cast<unsigned long long>(o.steps),
              world.settings().time_step, world.neighbourList().skin(), world.settings().threads);
  std::printf("time step limit %.4g s (%s; Rayleigh %.4g s, contact %.4g s at %g m/s); stages:",
              report.limit, report.limited_by.c_str(), report.rayleigh_time_step, report.contact_duration,
              world.settings().max_impact_velocity);
  for (const std::string& s : world.activeStages()) std::printf(" %s", s.c_str());
  std::printf("\npair kernel %s\n", std::string(demlink::core::pairKernelName(world.pairKernel())).c_str());
  std::printf("setup %.3f s, %zu neighbour pairs after initialize\n", setupSeconds,
              world.neighbourList().pairCount());
  printThermoHeader();

  const std::uint64_t buildsBefore = world.neighbourList().buildCount();
  const auto loopStart = Clock::now();
  printThermo(world, box, 0.0);
  // Thread CPU time per window of o.window steps from step o.window_from on: its minimum
  // and median per step are the figures least disturbed by other work on the machine.
  std::vector<double> windowSeconds;
  double windowStart = threadCpuSeconds();
  // World::advance between the steps something is measured or printed at.
  for (std::uint64_t s = 0; s < o.steps;) {
    std::uint64_t next = o.steps;
    const auto consider = [&](std::uint64_t event) {
      if (event > s && event < next) next = event;
    };
    if (o.thermo > 0) consider((s / o.thermo + 1) * o.thermo);
    consider(s < o.window_from ? o.window_from : o.window_from + ((s - o.window_from) / o.window + 1) * o.window);
    world.advance(next - s);
    s = next;
    if (s > o.window_from && (s - o.window_from) % o.window == 0) {
      const double now = threadCpuSeconds();
      windowSeconds.push_back(now - windowStart);
      windowStart = now;
    } else if (s == o.window_from) {
      windowStart = threadCpuSeconds();
    }
    if ((o.thermo > 0 && s % o.thermo == 0) || s == o.steps) {
      printThermo(world, box, std::chrono::duration<double>(Clock::now() - loopStart).count());
    }
  }
  const double wall = std::chrono::duration<double>(Clock::now() - loopStart).count();
  if (!o.save_final.empty()) saveParticles(world, o.save_final);

  const Thermo t = measure(world, box);
  const double n = static_cast<double>(world.particles().size());
  double maxFloorOverlap = 0.0;
  for (std::size_t i = 0; i < world.particles().size(); ++i) {
    maxFloorOverlap = std::max(maxFloorOverlap, world.particles().radius[i] - world.particles().position[i].z());
  }
  // Touching pairs at the end (particle-particle over the neighbour list; particle-plane).
  std::size_t contacts = 0;
  {
    const auto& p = world.particles();
    const auto offsets = world.neighbourList().offsets();
    const auto partners = world.neighbourList().partners();
    for (std::size_t i = 0; i + 1 < offsets.size(); ++i) {
      for (std::uint32_t k = offsets[i]; k < offsets[i + 1]; ++k) {
        const std::uint32_t j = partners[k];
        const double reach = p.radius[i] + p.radius[j];
        if ((p.position[j] - p.position[i]).squaredNorm() < reach * reach) ++contacts;
      }
    }
  }
  std::size_t wallContacts = 0;
  for (const auto& plane : world.planes()) {
    for (const std::uint32_t slot : plane.near_slots) {
      const auto& p = world.particles();
      if ((p.position[slot] - plane.spec.point).dot(plane.spec.normal) < p.radius[slot]) ++wallContacts;
    }
  }
  std::printf("Loop time of %.6f s for %llu steps with %zu atoms\n", wall, static_cast<unsigned long long>(o.steps),
              world.particles().size());
  std::printf("wall_seconds %.6f\n", wall);
  std::printf("particle_steps_per_second %.6e\n", wall > 0.0 ? n * static_cast<double>(o.steps) / wall : 0.0);
  std::printf("neighbour_builds %llu\n",
              static_cast<unsigned long long>(world.neighbourList().buildCount() - buildsBefore));
  std::printf("fused_kicks %llu\n", static_cast<unsigned long long>(world.fusedKicks()));
  std::printf("neighbour_pairs %zu\n", world.neighbourList().pairCount());
  std::printf("final_contacts %zu\n", contacts);
  std::printf("final_wall_contacts %zu\n", wallContacts);
  std::printf("final_mean_z %.8g\n", t.mean_z);
  std::printf("final_max_z %.8g\n", t.max_z);
  std::printf("final_ke_translational %.8g\n", t.ke_translational);
  std::printf("final_ke_rotational %.8g\n", t.ke_rotational);
  std::printf("final_ke %.8g\n", t.ke_translational + t.ke_rotational);
  std::printf("final_outside_box %zu\n", t.outside);
  std::printf("final_max_floor_overlap %.6g\n", maxFloorOverlap);
  // Memory the step keeps per particle (capacities): particle columns, neighbour list
  // with its grid, pair-loop chunk buffers.
  std::size_t columnBytes = 0;
  world.particles().forEachColumn(
      [&](const char*, const auto& column) { columnBytes += column.capacity() * sizeof(column[0]); });
  const std::size_t listBytes = world.neighbourList().bytes();
  const std::size_t pairLoopBytes = world.pairLoopPartition().bytes();
  std::printf("bytes_per_particle %.1f (columns %.1f, neighbour list and grid %.1f, pair-loop plan %.1f)\n",
              static_cast<double>(columnBytes + listBytes + pairLoopBytes) / n, static_cast<double>(columnBytes) / n,
              static_cast<double>(listBytes) / n, static_cast<double>(pairLoopBytes) / n);
  std::printf("pair_chunks %u\n", world.pairLoopPartition().chunks());
  std::printf("grid_levels %zu\n", world.neighbourList().grid().levelCount());
  std::printf("seconds_per_step %.6e\n", o.steps > 0 ? wall / static_cast<double>(o.steps) : 0.0);
  if (!windowSeconds.empty()) {
    const double perStep = 1e6 / static_cast<double>(o.window);
    std::printf("window_cpu_us_per_step min %.2f median %.2f (%zu windows of %llu steps from step %llu, this thread)\n",
                perStep * kthSmallest(windowSeconds, 0), perStep * kthSmallest(windowSeconds, windowSeconds.size() / 2),
                windowSeconds.size(), static_cast<unsigned long long>(o.window),
                static_cast<unsigned long long>(o.window_from));
  }
  if (o.stage_times && o.steps > 0) {
    // Sampled (stage_sampling.hpp), so a stage's figure is its mean per step.
    for (std::size_t k = 0; k < demlink::core::kStageCount; ++k) {
      const double seconds = world.stageSeconds()[k];
      if (seconds > 0.0) {
        std::printf("stage_us_per_step %s %.2f\n", std::string(demlink::core::stageTable()[k].name).c_str(),
                    1e6 * seconds / static_cast<double>(o.steps));
      }
    }
  }
  if (const demlink::core::ThreadPool* pool = world.threadPool()) {
    const demlink::core::ThreadPoolStats stats = pool->stats();
    std::printf("pool_parallel_loops %llu\npool_serial_loops %llu\npool_woken_loops %llu\n"
                "pool_chunks caller %llu workers %llu\n",
                static_cast<unsigned long long>(stats.parallel_runs),
                static_cast<unsigned long long>(stats.serial_runs), static_cast<unsigned long long>(stats.woken_runs),
                static_cast<unsigned long long>(stats.caller_chunks),
                static_cast<unsigned long long>(stats.worker_chunks));
    const demlink::core::SpinStats spins = demlink::core::SpinGate::instance().stats();
    std::printf("pool_spins ready %llu blocked %llu refused %llu\n",
                static_cast<unsigned long long>(spins.ready_spinning),
                static_cast<unsigned long long>(spins.blocked_after_spin),
                static_cast<unsigned long long>(spins.refused));
  }
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  Options options;
  if (const std::optional<int> exitCode = parseOptions(argc, argv, options)) return *exitCode;
  try {
    return run(options);
  } catch (const demlink::core::InputError& e) {
    std::fprintf(stderr, "input error: %s\n", e.what());
    return 1;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "error: %s\n", e.what());
    return 1;
  }
}
