// Linear FEM body, dynamics: first bending frequency, Rayleigh damping, the three-level scheme
// beyond the explicit limit (energy), central differences at its limit, imported Matrix Market
// matrices, checkpoint continuation.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <vector>

#include "deformable/fem_test_support.hpp"
#include "demlink/core/deformable/fem_input_files.hpp"
#include "demlink/core/base/input_error.hpp"
#include "demlink/core/state/state_stream.hpp"

namespace demlink::core {
namespace {

using fem_test::Beam;
using fem_test::TempDir;

/// Deflects the beam statically under a tip load, removes the load and records the mean tip
/// z displacement after each of `steps` steps.
std::vector<double> freeVibration(FemBody& body, const Beam& beam, double dt, int steps) {
  body.surface().clearForces();
  fem_test::loadTip(body, beam.length, Vec3(0, 0, -1.0));
  body.solveStatic(Vec3::Zero());
  body.surface().clearForces();
  std::vector<double> tip;
  for (int i = 0; i < steps; ++i) {
    body.beginStep(dt, Vec3::Zero());
    body.endStep(dt, Vec3::Zero());
    tip.push_back(fem_test::tipZ(body, beam.length));
  }
  return tip;
}

/// Times [s] of the upward zero crossings of `x` sampled at i * dt (linear interpolation).
std::vector<double> upCrossings(const std::vector<double>& x, double dt) {
  std::vector<double> t;
  for (std::size_t i = 1; i < x.size(); ++i) {
    if (x[i - 1] < 0.0 && x[i] >= 0.0) t.push_back(dt * (static_cast<double>(i) - x[i] / (x[i] - x[i - 1])));
  }
  return t;
}

double period(const std::vector<double>& crossings) {
  return (crossings.back() - crossings.front()) / static_cast<double>(crossings.size() - 1);
}

// Quadratic tetrahedra, 20 x 2 x 2 cells, free vibration from the static tip deflection,
// three-level scheme at T/200: the first bending frequency within 2% of Euler-Bernoulli's
// 1.875^2 sqrt(EI / (rho A L^4)) / (2 pi).
TEST(FemDynamics, FirstBendingFrequencyMatchesEulerBernoulli) {
  TempDir dir("frequency");
  const Beam beam;
  writeGmsh(dir.file("beam.msh"), beam.mesh(), "4.1");
  const double f = beam.firstFrequency();
  const double dt = 1.0 / (200.0 * f);
  FemBody body(beam.spec(dir.file("beam.msh")), dt, "fem");
  const std::vector<double> crossings = upCrossings(freeVibration(body, beam, dt, 2000), dt);
  ASSERT_GE(crossings.size(), 8u);
  const double measured = 1.0 / period(crossings);
  std::printf("first bending frequency: FEM %.4f Hz, Euler-Bernoulli %.4f Hz\n", measured, f);
  EXPECT_NEAR(measured / f, 1.0, 0.02);
}

// Rayleigh damping C = alpha K + beta M: the first mode decays with
// zeta = alpha omega / 2 + beta / (2 omega), here 1% from each term; the decay rate is fitted to
// the logarithm of successive peaks and must give zeta within 2%.
TEST(FemDynamics, RayleighDampingDecayRate) {
  TempDir dir("damping");
  const Beam beam;
  writeGmsh(dir.file("beam.msh"), beam.mesh(), "4.1");
  const double omega0 = 2.0 * M_PI * beam.firstFrequency();
  const double dt = 2.0 * M_PI / (200.0 * omega0);
  FemSpec spec = beam.spec(dir.file("beam.msh"));
  spec.rayleigh_alpha = 0.02 / omega0;
  spec.rayleigh_beta = 0.02 * omega0;
  FemBody body(spec, dt, "fem");
  const std::vector<double> x = freeVibration(body, beam, dt, 2400);
  // Peaks (negative side: the tip starts down): parabolic interpolation around each minimum.
  std::vector<double> t;
  std::vector<double> logPeak;
  for (std::size_t i = 1; i + 1 < x.size(); ++i) {
    if (x[i] < x[i - 1] && x[i] <= x[i + 1] && x[i] < 0.0) {
      const double a = 0.5 * (x[i - 1] + x[i + 1]) - x[i];
      const double b = 0.5 * (x[i + 1] - x[i - 1]);
      const double shift = -b / (2.0 * a);
      t.push_back(dt * (static_cast<double>(i) + 1.0 + shift));
      logPeak.push_back(std::log(-(x[i] - b * b / (4.0 * a))));
    }
  }
  ASSERT_GE(t.size(), 6u);
  // Least-squares slope of log(peak) over time, skipping the first peak (higher modes).
  double st = 0, sl = 0, stt = 0, stl = 0;
  const auto n = static_cast<double>(t.size() - 1);
  for (std::size_t i = 1; i < t.size(); ++i) {
    st += t[i];
    sl += logPeak[i];
    stt += t[i] * t[i];
    stl += t[i] * logPeak[i];
  }
  const double sigma = -(n * stl - st * sl) / (n * stt - st * st);
  const double omegaD = 2.0 * M_PI * static_cast<double>(t.size() - 2) / (t.back() - t[1]);
  const double omega = std::sqrt(omegaD * omegaD + sigma * sigma);
  const double zeta = sigma / omega;
  const double expected = spec.rayleigh_alpha * omega / 2.0 + spec.rayleigh_beta / (2.0 * omega);
  std::printf("damping ratio: measured %.5f, alpha omega / 2 + beta / (2 omega) = %.5f\n", zeta, expected);
  EXPECT_NEAR(zeta / expected, 1.0, 0.02);
}

/// The clamped `beam` written to dir/beam.msh, integrated by central differences.
FemSpec explicitSpec(const TempDir& dir, const Beam& beam) {
  writeGmsh(dir.file("beam.msh"), beam.mesh(), "2.2");
  FemSpec spec = beam.spec(dir.file("beam.msh"));
  spec.integrator = FemIntegrator::kCentralDifference;
  return spec;
}

/// The scheme's discrete energy between levels n and n+1 (zero load):
/// |U+ - U|_M^2 / (2 dt^2) + (U+.K U+ + U.K U + U+.K U) / 6, conserved exactly without damping.
double schemeEnergy(const FemBody& body, const Eigen::VectorXd& next, const Eigen::VectorXd& now, double dt) {
  const Eigen::VectorXd d = next - now;
  const auto& k = body.stiffnessMatrix();
  return d.dot(body.massMatrix() * d) / (2.0 * dt * dt) +
         (next.dot(k * next) + now.dot(k * now) + next.dot(k * now)) / 6.0;
}

Eigen::VectorXd displacements(const FemBody& body) {
  Eigen::VectorXd u(3 * static_cast<Eigen::Index>(body.nodeCount()));
  for (std::size_t i = 0; i < body.nodeCount(); ++i)
    u.segment<3>(3 * static_cast<Eigen::Index>(i)) = body.nodeDisplacement(i);
  return u;
}

// The three-level scheme at 10x the explicit (central-difference) limit, 3000 steps: without
// damping its discrete energy stays constant to round-off, with Rayleigh damping it never
// increases. (With the solver paper's printed A4 the first test grows without bound.)
TEST(FemDynamics, ThreeLevelBeyondTheExplicitLimitConservesEnergy) {
  TempDir dir("energy");
  const Beam beam = Beam::coarse(10);
  FemSpec spec = explicitSpec(dir, beam);
  const double limit = FemBody(spec, 1e-6, "fem").criticalTimeStep();
  ASSERT_TRUE(std::isfinite(limit));
  const double dt = 10.0 * limit;
  spec.integrator = FemIntegrator::kThreeLevel;
  for (const double alpha : {0.0, 1e-2}) {
    spec.rayleigh_alpha = alpha;
    FemBody body(spec, dt, "fem");
    EXPECT_TRUE(std::isinf(body.criticalTimeStep()));
    freeVibration(body, beam, dt, 3);  // the released load has left the lagged right-hand side
    Eigen::VectorXd now = displacements(body);
    double first = 0.0;
    double previous = 0.0;
    double largestTip = 0.0;
    for (int i = 0; i < 3000; ++i) {
      body.beginStep(dt, Vec3::Zero());
      body.endStep(dt, Vec3::Zero());
      const Eigen::VectorXd next = displacements(body);
      const double e = schemeEnergy(body, next, now, dt);
      if (i == 0) first = e;
      if (alpha == 0.0) {
        ASSERT_NEAR(e / first, 1.0, 1e-8) << "step " << i;
      } else if (i > 0) {
        ASSERT_LE(e, previous * (1.0 + 1e-12)) << "step " << i;
      }
      previous = e;
      largestTip = std::max(largestTip, std::abs(fem_test::tipZ(body, beam.length)));
      now = next;
    }
    EXPECT_GT(first, 0.0);
    EXPECT_LT(largestTip, 1.5 * beam.tipDeflection(1.0));
    if (alpha > 0.0) {
      EXPECT_LT(previous, 0.5 * first);
    }
  }
}

// Central differences with the lumped mass: stable just below the reported critical step,
// growing without bound just above it.
TEST(FemDynamics, CentralDifferencesStableBelowTheLimitGrowingAbove) {
  TempDir dir("explicit");
  const Beam beam = Beam::coarse(10);
  FemSpec spec = explicitSpec(dir, beam);
  const double limit = FemBody(spec, 1e-6, "fem").criticalTimeStep();
  const double scale = beam.tipDeflection(1.0);
  for (const double factor : {0.98, 1.02}) {
    FemBody body(spec, factor * limit, "fem");
    const std::vector<double> tip = freeVibration(body, beam, factor * limit, 4000);
    double largest = 0.0;
    for (const double z : tip) largest = std::max(largest, std::abs(z));
    if (factor < 1.0) {
      EXPECT_LT(largest, 1.5 * scale) << "dt = " << factor << " x critical";
    } else {
      EXPECT_GT(largest, 1e3 * scale) << "dt = " << factor << " x critical";
    }
  }
}

// M and K of our own assembly written as Matrix Market (K symmetric, M general), the node
// and triangle files beside them: the imported body moves as the assembled one.
TEST(FemDynamics, ImportedMatrixMarketMatchesAssembly) {
  TempDir dir("import");
  const Beam beam = Beam::coarse(8);
  writeGmsh(dir.file("beam.msh"), beam.mesh(), "4.1");
  FemSpec spec = beam.spec(dir.file("beam.msh"));
  spec.rayleigh_alpha = 1e-4;
  spec.rayleigh_beta = 0.5;
  const double dt = 1e-3;
  FemBody assembled(spec, dt, "fem");
  writeMatrixMarket(dir.file("k.mtx"), assembled.stiffnessMatrix(), true);
  writeMatrixMarket(dir.file("m.mtx"), assembled.massMatrix(), false);
  {
    std::FILE* nodes = std::fopen(dir.file("nodes.txt").c_str(), "w");
    std::fprintf(nodes, "# x y z [m]\n");
    for (std::size_t i = 0; i < assembled.nodeCount(); ++i) {
      const Vec3 x = assembled.nodePosition(i);
      std::fprintf(nodes, "%.17g %.17g %.17g\n", x.x(), x.y(), x.z());
    }
    std::fclose(nodes);
    std::FILE* triangles = std::fopen(dir.file("triangles.txt").c_str(), "w");
    for (const auto& t : assembled.surface().triangles())
      std::fprintf(triangles, "%u %u %u\n", t[0], t[1], t[2]);
    std::fclose(triangles);
  }
  FemSpec imported = spec;
  imported.msh_path.clear();
  imported.mass_matrix_path = dir.file("m.mtx");
  imported.stiffness_matrix_path = dir.file("k.mtx");
  imported.nodes_path = dir.file("nodes.txt");
  imported.triangles_path = dir.file("triangles.txt");
  FemBody body(imported, dt, "fem");
  ASSERT_EQ(body.nodeCount(), assembled.nodeCount());
  EXPECT_NEAR(body.totalMass(), assembled.totalMass(), 1e-12);
  const Vec3 g(0, 0, -9.81);
  double largest = 0.0;
  double difference = 0.0;
  for (int i = 0; i < 300; ++i) {
    for (FemBody* b : {&assembled, &body}) {
      b->beginStep(dt, g);
      b->surface().clearForces();
      if (i < 50) fem_test::loadTip(*b, beam.length, Vec3(0, 2.0, -1.0));
      b->endStep(dt, g);
    }
    for (std::size_t n = 0; n < body.nodeCount(); ++n) {
      largest = std::max(largest, assembled.nodeDisplacement(n).norm());
      difference = std::max(difference, (assembled.nodeDisplacement(n) - body.nodeDisplacement(n)).norm());
    }
  }
  EXPECT_GT(largest, 0.1 * beam.tipDeflection(1.0));
  EXPECT_LT(difference, 1e-9 * largest);
  EXPECT_LT((assembled.fixedReaction().force - body.fixedReaction().force).norm(),
            1e-9 * assembled.fixedReaction().force.norm());
}

// save() mid-run, restore() into a fresh body: both continue bit for bit.
TEST(FemDynamics, RestoredBodyContinuesBitIdentically) {
  TempDir dir("restore");
  const Beam beam = Beam::coarse(6);
  writeGmsh(dir.file("beam.msh"), beam.mesh(), "4.1");
  FemSpec spec = beam.spec(dir.file("beam.msh"));
  spec.driven_regions.push_back({Vec3(beam.length - 1e-9, -1.0, -1.0), Vec3(beam.length + 1e-9, 1.0, 1.0)});
  spec.driven_reference = Vec3(beam.length, 0, 0);
  spec.rayleigh_alpha = 1e-4;
  for (const FemIntegrator integrator : {FemIntegrator::kThreeLevel, FemIntegrator::kCentralDifference}) {
    spec.integrator = integrator;
    const double dt = 2e-5;
    const Vec3 g(0, 0, -9.81);
    const auto step = [&](FemBody& b, int i) {
      const double t = dt * (i + 1);
      b.setDrivenPose(spec.driven_reference + Vec3(0, 0, 1e-3 * std::sin(300.0 * t)),
                      Quat(Eigen::AngleAxisd(0.01 * t, Vec3::UnitX())), Vec3(0, 0, 0.3 * std::cos(300.0 * t)),
                      Vec3(0.01, 0, 0));
      b.beginStep(dt, g);
      b.surface().clearForces();
      fem_test::loadTip(b, beam.length / 2, Vec3(0, std::cos(i * 0.1), -1.0));
      b.endStep(dt, g);
    };
    FemBody a(spec, dt, "fem");
    for (int i = 0; i < 100; ++i) step(a, i);
    StateWriter out;
    a.save(out);
    FemBody b(spec, dt, "fem");
    StateReader in(out.bytes(), "memory", "fem");
    b.restore(in);
    EXPECT_TRUE(in.atEnd());
    for (int i = 100; i < 150; ++i) {
      step(a, i);
      step(b, i);
    }
    for (std::size_t n = 0; n < a.nodeCount(); ++n) {
      ASSERT_EQ(a.nodeDisplacement(n), b.nodeDisplacement(n)) << n;
      ASSERT_EQ(a.nodeVelocity(n), b.nodeVelocity(n)) << n;
    }
    EXPECT_EQ(a.drivenReaction().force, b.drivenReaction().force);
    EXPECT_EQ(a.fixedReaction().torque, b.fixedReaction().torque);
    EXPECT_GT(a.drivenReaction().force.norm(), 0.0);
    // A body of another size refuses the checkpoint.
    Beam other = beam;
    other.nx = 5;
    writeGmsh(dir.file("other.msh"), other.mesh(), "4.1");
    FemBody c(other.spec(dir.file("other.msh")), dt, "fem");
    StateReader again(out.bytes(), "memory", "fem");
    EXPECT_THROW(c.restore(again), InputError);
  }
}

}  // namespace
}  // namespace demlink::core
