/// demlink-bench-deposition: the "deposition-N" scene of bench/deposition/
/// (in.deposition, the LIGGGHTS input), run through the DEMLink core so it can be
/// compared side by side with LIGGGHTS (bench/run_deposition_compare.sh).
///
///   demlink-bench-deposition init_N.txt [--steps S] [--thermo K] [--threads T] [--dt DT]
///                            [--skin M] [--vmax V]
///
/// Scene (identical to in.deposition): spheres read from init_N.txt (id x y z r,
/// written by bench/deposition/make_particles.py), one material (rho 2500, E 5e6, nu 0.3, e 0.5,
/// mu 0.5, no rolling friction), Hertz-Mindlin, velocity Verlet, dt 1e-5 s,
/// gravity -9.81 z, skin 1 mm (LIGGGHTS `neighbor 0.001 bin`), planes z = 0,
/// x = 0, x = 0.1, y = 0, y = 0.1 of the same material.
///
/// Every K steps a thermo line like LIGGGHTS's `thermo_style custom step time
/// atoms c_ket c_ker c_zmx c_zav cpu` (plus a column counting particles outside
/// the box, a blow-up check); a summary at the end. Single-threaded unless
/// --threads T is given.
#include <algorithm>
#include <chrono>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <fstream>
#include <limits>
#include <optional>
#include <sstream>
#include <string>
#include <string_view>
#include <vector>

#include "demlink/cli/command_line.hpp"
#include "demlink/core/input_error.hpp"
#include "demlink/core/world.hpp"

namespace {

using demlink::core::Vec3;
using demlink::core::World;
namespace cli = demlink::cli;

constexpr double kBox = 0.1;  // [m] side of the square box (make_particles.py's box side)

struct Options {
  std::string init_file;
  std::uint64_t steps = 50000;
  std::uint64_t thermo = 5000;
  double time_step = 1.0e-5;
  double skin = 1.0e-3;
  double max_impact_velocity = 6.0;
  std::uint32_t threads = 1;
};

/// Parses the command line (demlink/cli/command_line.hpp); an exit code when the program
/// should stop now (--help, --version: 0; bad input: 2).
std::optional<int> parseOptions(int argc, char** argv, Options& o) {
  CLI::App app("The deposition benchmark scene on DEMLink's engine, side by side with LIGGGHTS.",
               "demlink-bench-deposition");
  app.add_option("init_file", o.init_file, "particles, 'id x y z r' per line (bench/deposition/make_particles.py); "
                                           "'#' lines are comments")
      ->required()
      ->type_name("init_N.txt");
  cli::addWholeNumber<std::uint64_t>(app, "--steps", o.steps, 0, std::numeric_limits<std::uint64_t>::max(),
                                     "time steps to run (default 50000)");
  cli::addWholeNumber<std::uint64_t>(app, "--thermo", o.thermo, 0, std::numeric_limits<std::uint64_t>::max(),
                                     "thermo line every K steps (default 5000; 0 = only first and last)");
  cli::addWholeNumber<std::uint32_t>(app, "--threads", o.threads, 1, 1024,
                                     "engine threads (SimulationSettings::threads; default 1)");
  cli::addNumber(app, "--dt", o.time_step, {0.0, true}, "time step [s] (default 1e-5, as the LIGGGHTS input)");
  cli::addNumber(app, "--skin", o.skin, {0.0}, "neighbour skin [m] (default 1e-3, as `neighbor 0.001`)");
  cli::addNumber(app, "--vmax", o.max_impact_velocity, {0.0, true},
                 "max_impact_velocity for the time-step check [m/s] (default 6)");
  return cli::parse(app, argc, argv);
}

struct InitParticle {
  Vec3 position;
  double radius;
};

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

Thermo measure(const World& world) {
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
    if (x.x() < 0.0 || x.x() > kBox || x.y() < 0.0 || x.y() > kBox || x.z() < 0.0) ++t.outside;
  }
  t.mean_z = p.size() > 0 ? sumZ / static_cast<double>(p.size()) : 0.0;
  return t;
}

void printThermoHeader() {
  std::printf("%10s %12s %8s %14s %14s %12s %12s %10s %8s\n", "Step", "Time", "Atoms", "KinEng", "RotEng", "MaxZ",
              "MeanZ", "Wall", "Outside");
}

void printThermo(const World& world, double wallSeconds) {
  const Thermo t = measure(world);
  std::printf("%10llu %12.6g %8zu %14.8g %14.8g %12.8g %12.8g %10.3f %8zu\n",
              static_cast<unsigned long long>(world.stepCount()), world.time(), world.particles().size(),
              t.ke_translational, t.ke_rotational, t.max_z, t.mean_z, wallSeconds, t.outside);
  std::fflush(stdout);
}

int run(const Options& o) {
  using Clock = std::chrono::steady_clock;
  const auto setupStart = Clock::now();
  const std::vector<InitParticle> init = readInit(o.init_file);

  demlink::core::SimulationSettings settings;
  settings.time_step = o.time_step;
  settings.gravity = Vec3(0.0, 0.0, -9.81);
  settings.contact_model = demlink::core::ContactModel::HertzMindlin;
  settings.integrator = demlink::core::IntegratorKind::VelocityVerlet;
  settings.neighbour_skin = o.skin;
  settings.max_impact_velocity = o.max_impact_velocity;
  settings.allow_unsafe_time_step = false;
  settings.threads = o.threads;
  World world(settings);

  demlink::core::Material material;
  material.name = "glass";
  material.density = 2500.0;
  material.youngs_modulus = 5.0e6;
  material.poisson_ratio = 0.3;
  material.restitution = 0.5;
  material.sliding_friction = 0.5;
  material.rolling_friction = 0.0;
  const std::uint32_t mat = world.addMaterial(material);

  for (std::size_t k = 0; k < init.size(); ++k) {
    demlink::core::ParticleSpec spec;
    spec.position = init[k].position;
    spec.radius = init[k].radius;
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
      {"x1", Vec3(kBox, 0.0, 0.0), Vec3(-1.0, 0.0, 0.0)},   {"y0", Vec3(0.0, 0.0, 0.0), Vec3(0.0, 1.0, 0.0)},
      {"y1", Vec3(0.0, kBox, 0.0), Vec3(0.0, -1.0, 0.0)},
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
  const double setupSeconds = std::chrono::duration<double>(Clock::now() - setupStart).count();

  const auto& report = world.timeStepReport();
  std::printf("DEMLink deposition bench: %zu particles from %s, %llu steps, dt %g s, skin %g m, %u thread(s)\n",
              world.particles().size(), o.init_file.c_str(), static_cast<unsigned long long>(o.steps),
              world.settings().time_step, world.neighbourList().skin(), world.settings().threads);
  std::printf("time step limit %.4g s (%s; Rayleigh %.4g s, contact %.4g s at %g m/s); stages:",
              report.limit, report.limited_by.c_str(), report.rayleigh_time_step, report.contact_duration,
              world.settings().max_impact_velocity);
  for (const std::string& s : world.activeStages()) std::printf(" %s", s.c_str());
  std::printf("\nsetup %.3f s, %zu neighbour pairs after initialize\n", setupSeconds,
              world.neighbourList().pairCount());
  printThermoHeader();

  const std::uint64_t buildsBefore = world.neighbourList().buildCount();
  const auto loopStart = Clock::now();
  printThermo(world, 0.0);
  for (std::uint64_t s = 1; s <= o.steps; ++s) {
    world.step();
    if ((o.thermo > 0 && s % o.thermo == 0) || s == o.steps) {
      printThermo(world, std::chrono::duration<double>(Clock::now() - loopStart).count());
    }
  }
  const double wall = std::chrono::duration<double>(Clock::now() - loopStart).count();

  const Thermo t = measure(world);
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
