/// demlink-bench-fem: cost of the linear FEM body's two integrators against its size.
///
/// A cantilever of quadratic tetrahedra (boxTetMesh, clamped at x = 0) at about 1e3, 1e4 and
/// 1e5 DOF. For each size it reports
///   build:  read the .msh + assemble K and M [s], and the whole FemBody construction, which
///           adds the sparse LDL^T factorisation of A1 (three-level) or the Lanczos estimate
///           of omega_max (central differences);
///   step:   wall time per step of each scheme (beginStep + endStep, a tip load each step),
///   limit:  the central-difference critical step, and the wall time per simulated second of
///           each scheme when the three-level scheme runs at 10x that step.
/// Usage: demlink-bench-fem [--max-dof N] [--steps S]   (defaults 120000 DOF, 200 steps)
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <optional>
#include <string>

#include "demlink/cli/command_line.hpp"

#include "demlink/core/deformable/fem_assembly.hpp"
#include "demlink/core/deformable/fem_body.hpp"
#include "demlink/core/deformable/gmsh_reader.hpp"
#include "demlink/core/deformable/tet_mesh.hpp"

namespace {

using namespace demlink::core;
using Clock = std::chrono::steady_clock;

double seconds(Clock::time_point since) {
  return std::chrono::duration<double>(Clock::now() - since).count();
}

struct Size {
  int nx, ny, nz;
};

double stepCost(FemBody& body, double dt, int steps) {
  const auto start = Clock::now();
  for (int i = 0; i < steps; ++i) {
    body.beginStep(dt, Vec3(0, 0, -9.81));
    body.surface().clearForces();
    body.surface().addContactForce(0, body.surface().positions()[body.surface().triangles()[0][0]],
                                   Vec3(0, 0, -1));
    body.endStep(dt, Vec3(0, 0, -9.81));
  }
  return seconds(start) / steps;
}

}  // namespace

int main(int argc, char** argv) {
  long maxDof = 120000;
  int steps = 200;
  CLI::App app("Cost of the linear FEM body's two integrators against its size.", "demlink-bench-fem");
  demlink::cli::addWholeNumber<long>(app, "--max-dof", maxDof, 1, 100000000,
                                     "largest cantilever to build, in degrees of freedom (default 120000)");
  demlink::cli::addWholeNumber<int>(app, "--steps", steps, 1, 1000000, "steps timed per scheme (default 200)");
  if (const std::optional<int> exitCode = demlink::cli::parse(app, argc, argv)) return *exitCode;
  const std::string path =
      (std::filesystem::temp_directory_path() / ("demlink_fem_bench_" + std::to_string(::getpid()) + ".msh"))
          .string();
  std::printf(
      "| DOF | elements | read+assemble [s] | build 3-level [s] | build CD [s] | step 3-level [ms] | step CD "
      "[ms] "
      "| CD dt_crit [s] | 3-level at 10 dt_crit / CD [wall per sim. s] |\n");
  std::printf("|---|---|---|---|---|---|---|---|---|\n");
  for (const Size s : {Size{8, 2, 2}, Size{20, 4, 4}, Size{40, 10, 10}}) {
    const double length = 1.0;
    const double side = length * s.ny / s.nx;
    const TetMesh mesh =
        boxTetMesh(Vec3::Zero(), Vec3(length, side, length * s.nz / s.nx), s.nx, s.ny, s.nz, 2);
    const long dof = 3 * static_cast<long>(mesh.nodes.size());
    if (dof > maxDof) break;
    writeGmsh(path, mesh, "4.1");
    FemSpec spec;
    spec.name = "bench";
    spec.msh_path = path;
    spec.youngs_modulus = 1e8;
    spec.poisson_ratio = 0.3;
    spec.density = 1000.0;
    spec.rayleigh_alpha = 1e-4;
    spec.fixed_regions.push_back({Vec3(-1e-9, -1.0, -1.0), Vec3(1e-9, 1.0, 1.0)});

    auto start = Clock::now();
    const TetMesh read = readGmsh(path);
    const FemMatrices matrices = assembleTetMesh(read, {1e8, 0.3, 1000.0}, true);
    const double assemble = seconds(start);

    spec.integrator = FemIntegrator::kCentralDifference;
    start = Clock::now();
    FemBody explicitBody(spec, 1e-7, "bench");
    const double buildCd = seconds(start);
    const double critical = explicitBody.criticalTimeStep();
    FemBody cd(spec, 0.9 * critical, "bench");
    const double stepCd = stepCost(cd, 0.9 * critical, steps);

    spec.integrator = FemIntegrator::kThreeLevel;
    start = Clock::now();
    FemBody implicitBody(spec, 10.0 * critical, "bench");
    const double buildThree = seconds(start);
    const double stepThree = stepCost(implicitBody, 10.0 * critical, steps);

    std::printf("| %ld | %zu | %.3f | %.3f | %.3f | %.3f | %.3f | %.3g | %.3g / %.3g |\n", dof,
                mesh.tetCount(), assemble, buildThree, buildCd, 1e3 * stepThree, 1e3 * stepCd, critical,
                stepThree / (10.0 * critical), stepCd / (0.9 * critical));
    std::fflush(stdout);
    (void)matrices;
  }
  std::filesystem::remove(path);
  return 0;
}
