/// demlink-bench-choices: what each speed/accuracy choice costs and gains.
///
/// For every contact law x integrator, and time steps at fractions of the
/// critical limit, it reports
///   cost:     wall seconds per simulated second, and particle-steps per second,
///             for the same simulated time of a bed forming (2,025 spheres in a box),
///   accuracy: the rebound ratio error of a head-on sphere impact (requested e = 0.5)
///             and the kinetic-energy error of an elastic (e = 1) impact, both
///             against their exact values.
/// Usage: demlink-bench-choices [--time T] [--threads T]   (T: simulated seconds, default 0.2)
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdint>
#include <optional>
#include <random>
#include <string>

#include "demlink/cli/command_line.hpp"
#include "demlink/core/world.hpp"

namespace {

using namespace demlink::core;

Material grains(double restitution) {
  Material m;
  m.name = "grains";
  m.density = 2500.0;
  m.youngs_modulus = 5e6;
  m.poisson_ratio = 0.3;
  m.restitution = restitution;
  m.sliding_friction = 0.5;
  return m;
}

SimulationSettings settingsFor(ContactModel law, IntegratorKind integrator, double dt, double speed) {
  SimulationSettings s;
  s.contact_model = law;
  s.integrator = integrator;
  s.time_step = dt;
  s.max_impact_velocity = speed;
  s.allow_unsafe_time_step = true;  // we probe the limit on purpose
  return s;
}

/// Critical time-step limit for 2-3 mm grains at 2 m/s under `law`.
double limitFor(ContactModel law) {
  World world(settingsFor(law, IntegratorKind::VelocityVerlet, 1e-9, 2.0));
  world.addMaterial(grains(0.5));
  ParticleSpec p;
  p.radius = 0.002;
  world.addParticle(p);
  world.initialize();
  return world.timeStepReport().limit;
}

/// Rebound ratio of two 2 mm spheres meeting head-on at 1 m/s, divided by e.
double impactRatio(ContactModel law, IntegratorKind integrator, double dt, double e) {
  SimulationSettings s = settingsFor(law, integrator, dt, 2.0);
  s.gravity = Vec3::Zero();
  World world(s);
  world.addMaterial(grains(e));
  ParticleSpec a;
  a.radius = 0.002;
  a.position = Vec3(-0.00201, 0.0, 0.0);
  a.velocity = Vec3(0.5, 0.0, 0.0);
  ParticleSpec b = a;
  b.position = -a.position;
  b.velocity = -a.velocity;
  world.addParticle(a);
  world.addParticle(b);
  world.initialize();
  const auto& p = world.particles();
  for (int n = 0; n < 10'000'000; ++n) {
    world.step();
    if ((p.position[1] - p.position[0]).norm() > 0.00403) break;
  }
  return std::abs(p.velocity[1].x() - p.velocity[0].x()) / e;
}

struct Cost {
  double wall_per_simulated;  ///< [s/s]
  double particle_steps_per_second;
};

/// Cost of simulating `duration` seconds of a bed forming.
Cost bedCost(ContactModel law, IntegratorKind integrator, double dt, double duration, std::uint32_t threads) {
  SimulationSettings s = settingsFor(law, integrator, dt, 2.0);
  s.threads = threads;
  World world(s);
  const auto mat = world.addMaterial(grains(0.5));
  const double box = 0.1;
  world.addPlane({"floor", Vec3::Zero(), Vec3::UnitZ(), mat});
  world.addPlane({"x0", Vec3::Zero(), Vec3::UnitX(), mat});
  world.addPlane({"x1", Vec3::Constant(box), -Vec3::UnitX(), mat});
  world.addPlane({"y0", Vec3::Zero(), Vec3::UnitY(), mat});
  world.addPlane({"y1", Vec3::Constant(box), -Vec3::UnitY(), mat});
  std::mt19937_64 rng(12345);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  for (int i = 0; i < 2025; ++i) {
    ParticleSpec p;
    p.radius = 0.002 + 0.001 * u(rng);
    p.position = Vec3(0.0045 + 0.0065 * (i % 15), 0.0045 + 0.0065 * ((i / 15) % 15), 0.0035 + 0.0065 * (i / 225));
    world.addParticle(p);
  }
  world.initialize();
  const auto steps = static_cast<long>(std::ceil(duration / dt));
  const auto t0 = std::chrono::steady_clock::now();
  for (long n = 0; n < steps; ++n) world.step();
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return {seconds / duration, 2025.0 * static_cast<double>(steps) / seconds};
}

}  // namespace

int main(int argc, char** argv) {
  double duration = 0.2;
  std::uint32_t threads = 1;
  CLI::App app("Speed and accuracy of each contact law x integrator x time step on a bed of 2025 spheres.",
               "demlink-bench-choices");
  demlink::cli::addNumber(app, "--time", duration, {0.0, true}, "simulated time of each bed run [s] (default 0.2)")
      ->type_name("T");
  demlink::cli::addWholeNumber<std::uint32_t>(app, "--threads", threads, 1, 1024, "engine threads (default 1)");
  if (const std::optional<int> exitCode = demlink::cli::parse(app, argc, argv)) return *exitCode;
  std::printf("bed: 2025 spheres, %.3g s simulated, %u thread(s)\n\n", duration, threads);
  std::printf("| contact law | integrator | dt / limit | dt [s] | wall s per simulated s | M particle-steps/s | e error (e=0.5) | energy error (e=1) |\n");
  std::printf("|---|---|---|---|---|---|---|---|\n");
  for (ContactModel law : {ContactModel::HertzMindlin, ContactModel::LinearSpringDashpot}) {
    const double limit = limitFor(law);
    for (IntegratorKind integrator : {IntegratorKind::VelocityVerlet, IntegratorKind::ExplicitEuler}) {
      for (double fraction : {1.0, 0.5, 0.2}) {
        const double dt = fraction * limit;
        const Cost cost = bedCost(law, integrator, dt, duration, threads);
        const double eError = impactRatio(law, integrator, dt, 0.5) - 1.0;
        const double energyError = std::pow(impactRatio(law, integrator, dt, 1.0), 2) - 1.0;
        std::printf("| %s | %s | %.1f | %.3g | %.1f | %.2f | %+.2e | %+.2e |\n", std::string(toString(law)).c_str(),
                    std::string(toString(integrator)).c_str(), fraction, dt, cost.wall_per_simulated,
                    cost.particle_steps_per_second / 1e6, eError, energyError);
        std::fflush(stdout);
      }
    }
  }
  return 0;
}
