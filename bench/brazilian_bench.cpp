/// demlink-bench-brazilian: the Brazilian (indirect tensile) test of a bonded disc.
///
/// A disc of diameter D, one sphere layer thick (t = 2 r: a 2D-ish slab in the x-y plane),
/// is built from spheres of radius 0.90 .. 0.97 r on a hexagonal lattice of pitch 2 r jittered by
/// +-0.02 r (no sphere overlaps another), cemented
/// with parallel bonds (Potyondy and Cundall, "A bonded-particle model for rock", Int. J.
/// Rock Mech. Min. Sci. 41 (2004) 1329-1364, doi:10.1016/j.ijrmms.2004.09.011) and
/// squeezed across a diameter between two flat platens closing at a constant speed. The
/// peak platen force F gives the indirect tensile strength sigma_t = 2 F / (pi D t); the
/// bench prints it against the bond tensile strength for several seeds (the jitter and
/// the radii), with their mean and standard deviation.
///
/// Usage: demlink-bench-brazilian [--seeds N] [--diameter-radii K] [--speed V]
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numbers>
#include <optional>
#include <vector>

#include "demlink/cli/command_line.hpp"
#include "demlink/core/base/random.hpp"
#include "demlink/core/world.hpp"

namespace {

using namespace demlink::core;

constexpr double kRadius = 1.0e-3;            // mean sphere radius r [m]
constexpr double kNormalStiffness = 1.0e13;   // kn [Pa/m]: E = kn 2r = 20 GPa
constexpr double kShearStiffness = 4.0e12;    // ks [Pa/m]
constexpr double kTensileStrength = 5.0e6;    // [Pa]
constexpr double kShearStrength = 1.0e7;      // [Pa]
constexpr double kTimeStep = 5.0e-8;          // [s]

Material rock() {
  Material m;
  m.name = "rock";
  m.density = 2650.0;
  m.youngs_modulus = 2.0e10;
  m.poisson_ratio = 0.25;
  m.restitution = 0.3;
  m.sliding_friction = 0.5;
  return m;
}

/// A flat platen: a square in its local x-z plane, normal along y.
MeshBody platen(const std::string& name, double halfWidth, std::uint32_t material) {
  const double h = halfWidth;
  std::vector<Vec3> vertices{Vec3(-h, 0.0, -h), Vec3(h, 0.0, -h), Vec3(h, 0.0, h), Vec3(-h, 0.0, h)};
  return MeshBody(name, std::move(vertices), {{0, 1, 2}, {0, 2, 3}}, material);
}

struct Result {
  double peak_force = 0.0;   ///< [N]
  double strength = 0.0;     ///< sigma_t = 2 F / (pi D t) [Pa]
  std::uint64_t bonds = 0;
  std::uint64_t broken = 0;
  std::size_t spheres = 0;
};

Result squeeze(std::uint64_t seed, double diameterRadii, double speed) {
  SimulationSettings settings;
  settings.time_step = kTimeStep;
  settings.gravity = Vec3::Zero();
  settings.max_impact_velocity = 10.0 * speed;
  settings.watchdog.every_steps = 0;
  World world(settings);
  const std::uint32_t material = world.addMaterial(rock());
  const double diameter = diameterRadii * kRadius;
  // Hexagonal lattice of pitch 2r jittered by +-0.02 r, radii 0.90 .. 0.97 r: centres at least
  // 1.943 r apart, so no two spheres overlap (an overlap would push the pair apart and break
  // its bond at once); gaps up to 0.26 r.
  Random random(seed);
  const double pitch = 2.0 * kRadius;
  const int rows = static_cast<int>(std::ceil(diameter / (std::sqrt(3.0) * kRadius))) + 1;
  double top = 0.0;
  for (int j = -rows; j <= rows; ++j) {
    for (int i = -rows; i <= rows; ++i) {
      Vec3 x((i + 0.5 * (j & 1)) * pitch, j * std::sqrt(3.0) * kRadius, 0.0);
      x += Vec3(random.uniform(-0.02, 0.02), random.uniform(-0.02, 0.02), 0.0) * kRadius;
      if (x.norm() + kRadius > 0.5 * diameter) continue;
      ParticleSpec s;
      s.material = material;
      s.position = x;
      s.radius = kRadius * random.uniform(0.90, 0.97);
      world.addParticle(s);
      top = std::max(top, std::abs(x.y()) + s.radius);
    }
  }
  BondRule rule;
  rule.name = "cement";
  rule.properties.radius_multiplier = 1.0;
  rule.properties.normal_stiffness_per_area = kNormalStiffness;
  rule.properties.shear_stiffness_per_area = kShearStiffness;
  rule.properties.tensile_strength = kTensileStrength;
  rule.properties.shear_strength = kShearStrength;
  rule.properties.gap_tolerance = 0.3 * kRadius;  // every lattice neighbour
  world.addBondRule(rule, "cement");
  MeshBody upper = platen("upper", diameter, material);
  upper.setPose(Vec3(0.0, top, 0.0), Quat::Identity());
  upper.setVelocity(Vec3(0.0, -0.5 * speed, 0.0), Vec3::Zero());
  MeshBody lower = platen("lower", diameter, material);
  lower.setPose(Vec3(0.0, -top, 0.0), Quat::Identity());
  lower.setVelocity(Vec3(0.0, 0.5 * speed, 0.0), Vec3::Zero());
  world.addMesh(std::move(upper), "upper");
  world.addMesh(std::move(lower), "lower");
  world.step();  // the bonds are made at the end of the first step
  Result result;
  result.spheres = world.particles().size();
  result.bonds = world.bonds().counts().intact;
  const double thickness = 2.0 * kRadius;
  // Until the force has fallen to a third of its peak after bonds broke, or the platens
  // have closed by a tenth of the diameter.
  const auto steps = static_cast<std::uint64_t>(0.1 * diameter / speed / kTimeStep);
  for (std::uint64_t n = 0; n < steps; ++n) {
    world.step();
    const double force = 0.5 * (world.meshes()[0].force().y() - world.meshes()[1].force().y());
    result.peak_force = std::max(result.peak_force, force);
    if (world.bonds().counts().broken > 0 && force < result.peak_force / 3.0) break;
  }
  result.broken = world.bonds().counts().broken;
  result.strength = 2.0 * result.peak_force / (std::numbers::pi * diameter * thickness);
  return result;
}

}  // namespace

int main(int argc, char** argv) {
  int seeds = 5;
  double diameterRadii = 30.0;
  double speed = 0.02;
  CLI::App app("Brazilian test of a bonded disc: indirect tensile strength 2F/(pi D t) against the bond tensile "
               "strength, over several seeds.",
               "demlink-bench-brazilian");
  demlink::cli::addWholeNumber<int>(app, "--seeds", seeds, 1, 100, "number of packings (default 5)");
  demlink::cli::addNumber(app, "--diameter-radii", diameterRadii, {8.0, false, 200.0},
                          "disc diameter in sphere radii (default 30)");
  demlink::cli::addNumber(app, "--speed", speed, {0.0, true, 1.0}, "platens' closing speed [m/s] (default 0.02)");
  if (const std::optional<int> exitCode = demlink::cli::parse(app, argc, argv)) return *exitCode;
  std::printf("bond tensile strength %.4g Pa, D = %.4g m, t = %.4g m, closing at %.4g m/s\n", kTensileStrength,
              diameterRadii * kRadius, 2.0 * kRadius, speed);
  std::printf("seed,spheres,bonds,broken,peak_force_N,sigma_t_Pa,sigma_t_over_bond_strength\n");
  std::vector<double> ratios;
  for (int s = 1; s <= seeds; ++s) {
    const Result r = squeeze(static_cast<std::uint64_t>(s), diameterRadii, speed);
    const double ratio = r.strength / kTensileStrength;
    ratios.push_back(ratio);
    std::printf("%d,%zu,%llu,%llu,%.6g,%.6g,%.4f\n", s, r.spheres, static_cast<unsigned long long>(r.bonds),
                static_cast<unsigned long long>(r.broken), r.peak_force, r.strength, ratio);
  }
  double mean = 0.0;
  for (const double x : ratios) mean += x;
  mean /= static_cast<double>(ratios.size());
  double variance = 0.0;
  for (const double x : ratios) variance += (x - mean) * (x - mean);
  const double deviation = ratios.size() > 1 ? std::sqrt(variance / static_cast<double>(ratios.size() - 1)) : 0.0;
  std::printf("sigma_t / bond tensile strength: mean %.4f, standard deviation %.4f over %zu seeds\n", mean, deviation,
              ratios.size());
  return 0;
}
