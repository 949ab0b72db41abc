/// demlink-bench-step-limit: does the accepted time step keep restitution within
/// the tolerance at every contact-onset phase?
///
/// For every contact law x integrator and requested e it prints the step
/// fraction f = dt / t_c the calibration accepts, the worst error of the
/// dimensionless model over 1024 onset phases at f, and the worst error the
/// engine itself delivers at 0.99 of the world's accepted limit over random
/// onset phases, sphere on a plane and sphere on sphere (radius 10 mm, E 10 MPa,
/// impact 1 m/s, no gravity). Error: |e_delivered - e| / max(e, 0.1).
/// Usage: demlink-bench-step-limit [--phases N] [--seed S]
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdint>
#include <optional>
#include <random>

#include "demlink/cli/command_line.hpp"
#include "demlink/core/contact/contact_law_registry.hpp"
#include "demlink/core/contact/time_step_calibration.hpp"
#include "demlink/core/world.hpp"

namespace {

using namespace demlink::core;

constexpr double kRadius = 0.01;  // [m]
constexpr double kSpeed = 1.0;    // [m/s]

Material material(double e) {
  Material m;
  m.name = "grains";
  m.density = 2500.0;
  m.youngs_modulus = 1e7;
  m.poisson_ratio = 0.3;
  m.restitution = e;
  m.sliding_friction = 0.0;
  return m;
}

SimulationSettings settingsFor(ContactModel law, IntegratorKind integrator, double dt) {
  SimulationSettings s;
  s.contact_model = law;
  s.integrator = integrator;
  s.time_step = dt;
  s.gravity = Vec3::Zero();
  s.max_impact_velocity = kSpeed;
  return s;
}

/// The world's accepted limit for the impact scenes below.
double acceptedLimit(ContactModel law, IntegratorKind integrator, double e, bool onPlane) {
  World world(settingsFor(law, integrator, 1e-12));
  world.addMaterial(material(e));
  if (onPlane) world.addPlane({"floor", Vec3::Zero(), Vec3::UnitZ(), 0});
  ParticleSpec p;
  p.radius = kRadius;
  world.addParticle(p);
  world.initialize();
  return world.timeStepReport().limit;
}

/// Rebound ratio of a sphere hitting a plane (or an equal sphere head-on) whose
/// contact starts `phase` of a step after the last step without overlap.
std::optional<double> rebound(ContactModel law, IntegratorKind integrator, double e, double dt, double phase,
                              bool onPlane) {
  World world(settingsFor(law, integrator, dt));
  world.addMaterial(material(e));
  const double gap = (3.0 + phase) * kSpeed * dt;  // overlap -phase v dt after three steps
  ParticleSpec a;
  a.radius = kRadius;
  if (onPlane) {
    world.addPlane({"floor", Vec3::Zero(), Vec3::UnitZ(), 0});
    a.position = Vec3(0.0, 0.0, kRadius + gap);
    a.velocity = Vec3(0.0, 0.0, -kSpeed);
    world.addParticle(a);
  } else {
    a.position = Vec3(-kRadius - 0.5 * gap, 0.0, 0.0);
    a.velocity = Vec3(0.5 * kSpeed, 0.0, 0.0);
    ParticleSpec b = a;
    b.position = -a.position;
    b.velocity = -a.velocity;
    world.addParticle(a);
    world.addParticle(b);
  }
  world.initialize();
  const ParticleArrays& p = world.particles();
  for (int n = 0; n < 10'000'000; ++n) {
    world.step();
    if (onPlane && p.position[0].z() > kRadius + gap) return p.velocity[0].z() / kSpeed;
    if (!onPlane && (p.position[1] - p.position[0]).norm() > 2.0 * kRadius + gap) {
      return (p.velocity[1].x() - p.velocity[0].x()) / kSpeed;
    }
  }
  return std::nullopt;
}

}  // namespace

int main(int argc, char** argv) {
  int phases = 16;
  std::uint64_t seed = 1;
  CLI::App app("Worst restitution error over contact-onset phases at the accepted time-step limit.",
               "demlink-bench-step-limit");
  demlink::cli::addWholeNumber<int>(app, "--phases", phases, 1, 100000,
                                    "random onset phases per engine impact (default 16)");
  demlink::cli::addWholeNumber<std::uint64_t>(app, "--seed", seed, 0, UINT64_MAX, "random seed (default 1)");
  if (const std::optional<int> exitCode = demlink::cli::parse(app, argc, argv)) return *exitCode;
  std::printf("tolerance %.3g; engine: radius %.3g m, E 1e7 Pa, %.3g m/s, %d random onset phases, dt = 0.99 x limit\n\n",
              SimulationSettings{}.restitution_tolerance, kRadius, kSpeed, phases);
  std::printf("| law | integrator | e | f = dt/t_c | model worst (1024 phases) | engine worst, plane | engine worst, sphere pair |\n");
  std::printf("|---|---|---|---|---|---|---|\n");
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> uniform(0.0, 1.0);
  const double tolerance = SimulationSettings{}.restitution_tolerance;
  for (const ContactLawEntry& law : contactLaws()) {
    for (IntegratorKind integrator : {IntegratorKind::VelocityVerlet, IntegratorKind::ExplicitEuler}) {
      for (double e : {0.01, 0.05, 0.1, 0.2, 0.5, 0.9, 1.0}) {
        const double c = law.damping_for_restitution(e);
        const double f = accurateStepFraction(law.model, integrator, e, c, tolerance);
        const double model = worstRestitutionError(law.model, integrator, e, c, f, 1024);
        double worst[2] = {0.0, 0.0};
        for (int k = 0; k < 2; ++k) {
          const bool onPlane = k == 0;
          const double dt = 0.99 * acceptedLimit(law.model, integrator, e, onPlane);
          for (int i = 0; i < phases; ++i) {
            const std::optional<double> got = rebound(law.model, integrator, e, dt, uniform(rng), onPlane);
            worst[k] = std::max(worst[k], got ? restitutionError(*got, e) : 1.0);
          }
        }
        std::printf("| %s | %s | %.2f | %.4g | %.4f | %.4f | %.4f |\n", std::string(law.name).c_str(),
                    std::string(toString(integrator)).c_str(), e, f, model, worst[0], worst[1]);
      }
    }
  }
  return 0;
}
