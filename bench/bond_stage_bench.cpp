/// demlink-bench-bond-stage: the parallel-bond stage alone (BondSet::step), serial against
/// the thread pool, alternating, medians.
///
/// A cubic lattice of side N spheres (radius 10 mm, 0.1 mm gaps), bonded to its six
/// neighbours, each sphere moving and spinning a little (so the bonds load without
/// breaking); slots are shuffled, as clods' members are spread over a re-sorted bed.
/// Each round times `--steps` calls of BondSet::step on one thread (no pool) and on a
/// pool of `--threads`, in turn, and prints the wall time per step and per bond; the
/// close gives the medians and their ratio.
/// Usage: demlink-bench-bond-stage [--side N] [--threads T] [--rounds K] [--steps S]
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <numeric>
#include <optional>
#include <random>
#include <vector>

#include "demlink/cli/command_line.hpp"
#include "demlink/core/bonds/bond_set.hpp"
#include "demlink/core/parallel/thread_pool.hpp"
#include "demlink/core/walls/mesh_body.hpp"

namespace {

using namespace demlink::core;

constexpr double kRadius = 0.01;   // [m]
constexpr double kGap = 1.0e-4;    // [m]
constexpr double kDensity = 2600;  // [kg/m^3]
constexpr double kTimeStep = 1e-6; // [s]

/// The lattice, its slots in a shuffled order.
ParticleArrays lattice(int side, std::uint64_t seed) {
  std::vector<ParticleSpec> specs;
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> jiggle(-1.0, 1.0);
  const double spacing = 2.0 * kRadius + kGap;
  for (int i = 0; i < side; ++i) {
    for (int j = 0; j < side; ++j) {
      for (int k = 0; k < side; ++k) {
        ParticleSpec s;
        s.radius = kRadius;
        s.position = Vec3(i, j, k) * spacing;
        s.velocity = 1e-3 * Vec3(jiggle(rng), jiggle(rng), jiggle(rng));
        s.angular_velocity = 0.1 * Vec3(jiggle(rng), jiggle(rng), jiggle(rng));
        specs.push_back(s);
      }
    }
  }
  std::shuffle(specs.begin(), specs.end(), rng);
  ParticleArrays p;
  p.reserve(specs.size());
  for (std::size_t n = 0; n < specs.size(); ++n) p.append(specs[n], kDensity, n + 1);
  return p;
}

BondSet bondedSet(ParticleArrays& p) {
  BondSet set;
  BondRule rule;
  rule.name = "cement";
  rule.properties.normal_stiffness_per_area = 1e10;
  rule.properties.shear_stiffness_per_area = 1e10;
  rule.properties.tensile_strength = 1e30;
  rule.properties.shear_strength = 1e30;
  rule.properties.gap_tolerance = 2.0 * kGap;
  set.addRule(rule);
  set.step(nullptr, {}, 0.0, p, kTimeStep, 0);  // makes the bonds
  return set;
}

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v.size() % 2 == 1 ? v[v.size() / 2] : 0.5 * (v[v.size() / 2 - 1] + v[v.size() / 2]);
}

}  // namespace

int main(int argc, char** argv) {
  int side = 20;
  std::uint32_t threads = 2;
  int rounds = 7;
  int steps = 500;
  CLI::App app("The parallel-bond stage alone, serial against the thread pool (alternating, medians).",
               "demlink-bench-bond-stage");
  demlink::cli::addWholeNumber<int>(app, "--side", side, 2, 200, "spheres along the lattice's edge (default 20)");
  demlink::cli::addWholeNumber<std::uint32_t>(app, "--threads", threads, 2, 64, "pool threads (default 2)");
  demlink::cli::addWholeNumber<int>(app, "--rounds", rounds, 1, 1000, "alternating rounds (default 7)");
  demlink::cli::addWholeNumber<int>(app, "--steps", steps, 1, 1000000, "stage calls per round and side (default 500)");
  if (const std::optional<int> exitCode = demlink::cli::parse(app, argc, argv)) return *exitCode;

  ParticleArrays p = lattice(side, 1);
  BondSet set = bondedSet(p);
  const std::size_t bonds = set.bonds().size();
  ThreadPool pool(threads);
  std::printf("%zu spheres, %zu bonds, %d steps a round, pool of %u threads\n", p.size(), bonds, steps, threads);
  std::printf("| round | serial [us/step] | pool [us/step] | pool / serial |\n|---|---|---|---|\n");
  auto time = [&](ThreadPool* runner) {
    const auto start = std::chrono::steady_clock::now();
    for (int s = 0; s < steps; ++s) set.step(runner, {}, 0.0, p, kTimeStep, 1);
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count() / steps;
  };
  std::vector<double> serial;
  std::vector<double> threaded;
  for (int r = 0; r < rounds; ++r) {
    serial.push_back(time(nullptr));
    threaded.push_back(time(&pool));
    std::printf("| %d | %.1f | %.1f | %.3f |\n", r + 1, 1e6 * serial.back(), 1e6 * threaded.back(),
                threaded.back() / serial.back());
  }
  const double s = median(serial);
  const double t = median(threaded);
  std::printf("median: serial %.1f us/step (%.1f ns/bond), pool %.1f us/step (%.1f ns/bond), pool / serial %.3f\n",
              1e6 * s, 1e9 * s / static_cast<double>(bonds), 1e6 * t, 1e9 * t / static_cast<double>(bonds), t / s);
  std::printf("bonds intact after the rounds: %llu of %zu\n",
              static_cast<unsigned long long>(set.counts().intact), bonds);
  return 0;
}
