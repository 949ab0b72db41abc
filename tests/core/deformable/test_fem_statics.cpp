// Linear FEM body, statics: cantilever tip deflection against Euler-Bernoulli, the lumped
// masses, reactions at fixed and driven nodes, von Mises stress.
#include <gtest/gtest.h>

#include <cstdio>

#include "deformable/fem_test_support.hpp"
#include "demlink/core/deformable/fem_assembly.hpp"

namespace demlink::core {
namespace {

using fem_test::Beam;
using fem_test::TempDir;

double staticTip(const Beam& beam, const TempDir& dir, double load) {
  const std::string path = dir.file("beam.msh");
  writeGmsh(path, beam.mesh(), "4.1");
  FemBody body(beam.spec(path), 1e-4, "fem");
  fem_test::loadTip(body, beam.length, Vec3(0, 0, -load));
  body.solveStatic(Vec3::Zero());
  return -fem_test::tipZ(body, beam.length);
}

// Quadratic tetrahedra, 20 x 2 x 2 cells (480 elements, 1025 nodes), L/h = 20: within 2% of
// P L^3 / (3 E I) (Timoshenko's shear term adds 0.2% to the exact 3D answer).
TEST(FemStatics, QuadraticCantileverTipDeflectionMatchesEulerBernoulli) {
  TempDir dir("statics");
  const Beam beam;
  const double load = 10.0;
  const double tip = staticTip(beam, dir, load);
  EXPECT_NEAR(tip / beam.tipDeflection(load), 1.0, 0.02) << tip << " vs " << beam.tipDeflection(load);
}

// Refinement: linear tetrahedra lock in bending (far too stiff at this size) and improve
// slowly; quadratic ones converge from below and are within 2% from 20 x 2 x 2 cells on. The printout is the
// convergence table quoted in docs/deformable.md.
TEST(FemStatics, RefinementConvergesFromBelow) {
  TempDir dir("refine");
  const double load = 10.0;
  double previousLinear = 0.0;
  double previousQuadratic = 0.0;
  for (const int n : {1, 2, 3}) {
    Beam linear;
    linear.order = 1;
    linear.nx = 10 * n;
    linear.ny = linear.nz = n;
    Beam quadratic = linear;
    quadratic.order = 2;
    const double exact = linear.tipDeflection(load);
    const double l = staticTip(linear, dir, load) / exact;
    const double q = staticTip(quadratic, dir, load) / exact;
    std::printf("cells %3d x %d x %d: tip / Euler-Bernoulli  linear %.4f  quadratic %.4f\n", linear.nx, n, n,
                l, q);
    EXPECT_GT(l, previousLinear);
    EXPECT_LT(l, 1.0);
    EXPECT_GT(q, previousQuadratic);
    EXPECT_LT(q, 1.0);
    if (n >= 2) {
      EXPECT_NEAR(q, 1.0, 0.02);
    }
    previousLinear = l;
    previousQuadratic = q;
  }
}

// HRZ lumping of quadratic tetrahedra keeps every mass positive and the total rho V; the
// consistent mass has the same total; a rigid translation is strain-free.
TEST(FemStatics, MassMatricesAndRigidMotion) {
  const Beam beam;
  const TetMesh mesh = beam.mesh();
  const ElasticMaterial material{beam.youngs_modulus, beam.poisson_ratio, beam.density};
  const double mass = beam.density * beam.length * beam.area();
  for (const bool lumped : {true, false}) {
    const FemMatrices m = assembleTetMesh(mesh, material, lumped);
    Eigen::VectorXd ex = Eigen::VectorXd::Zero(m.mass.rows());
    for (Eigen::Index i = 0; i < ex.size(); i += 3) ex[i] = 1.0;
    EXPECT_NEAR(ex.dot(m.mass * ex), mass, 1e-9 * mass);
    EXPECT_GT(m.mass.diagonal().minCoeff(), 0.0);
    EXPECT_LT((m.stiffness * ex).norm(), 1e-6 * m.stiffness.norm());
    // A rigid rotation about z is strain-free too.
    Eigen::VectorXd rz = Eigen::VectorXd::Zero(m.mass.rows());
    for (std::size_t i = 0; i < mesh.nodes.size(); ++i) {
      rz[3 * static_cast<Eigen::Index>(i)] = -mesh.nodes[i].y();
      rz[3 * static_cast<Eigen::Index>(i) + 1] = mesh.nodes[i].x();
    }
    EXPECT_LT((m.stiffness * rz).norm(), 1e-6 * m.stiffness.norm());
  }
}

// At rest under gravity and a tip load the clamp carries both: force -(m g + P), torque about
// the origin the opposite of the loads' moment.
TEST(FemStatics, FixedReactionBalancesTheLoads) {
  TempDir dir("reaction");
  const Beam beam = Beam::coarse(10);
  const std::string path = dir.file("beam.msh");
  writeGmsh(path, beam.mesh(), "2.2");
  FemBody body(beam.spec(path), 1e-4, "fem");
  const Vec3 g(0, 0, -9.81);
  const Vec3 p(0, 0, -5.0);
  fem_test::loadTip(body, beam.length, p);
  body.solveStatic(g);
  const double m = body.totalMass();
  EXPECT_NEAR(m, beam.density * beam.length * beam.area(), 1e-9);
  const Vec3 expected = -(m * g + p);
  EXPECT_LT((body.fixedReaction().force - expected).norm(), 1e-6 * expected.norm());
  // Moment of the loads about the origin (undeformed centroids; small displacements).
  const Vec3 centroid(beam.length / 2, beam.width / 2, beam.height / 2);
  const Vec3 tip(beam.length, beam.width / 2, beam.height / 2);
  const Vec3 moment = centroid.cross(m * g) + tip.cross(p);
  EXPECT_LT((body.fixedReaction().torque + moment).norm(), 1e-3 * moment.norm());
  // Stepping on from rest keeps the same reaction (the body stays in equilibrium).
  for (int i = 0; i < 5; ++i) {
    body.beginStep(1e-4, g);
    body.endStep(1e-4, g);
  }
  EXPECT_LT((body.fixedReaction().force - expected).norm(), 1e-6 * expected.norm());
  EXPECT_LT(fem_test::tipZ(body, beam.length) / tip.z(), 0.0);
  // Bending stress at the clamp: M c / I with M = P L, c = h/2 (von Mises = |sigma_xx| there;
  // centroids sit inside the section and the clamp's corners concentrate stress, hence the band).
  const std::vector<double> vm = body.vonMisesStress();
  ASSERT_EQ(vm.size(), body.elements().size());
  const double sigma = 5.0 * beam.length * (beam.height / 2) / beam.inertia();
  const double largest = *std::max_element(vm.begin(), vm.end());
  EXPECT_GT(largest, 0.3 * sigma);
  EXPECT_LT(largest, 2.0 * sigma);
}

// Driven end moved rigidly (the only constraint): the whole beam follows, strain-free, with
// zero reaction; the surface nodes move with the driven pose's velocity.
TEST(FemStatics, DrivenNodesFollowTheirPose) {
  TempDir dir("driven");
  Beam beam = Beam::coarse(6);
  beam.order = 1;
  const std::string path = dir.file("beam.msh");
  writeGmsh(path, beam.mesh(), "4.1");
  FemSpec spec = beam.spec(path);
  spec.driven_regions = spec.fixed_regions;
  spec.fixed_regions.clear();
  spec.driven_reference = Vec3(0, 0.025, 0.025);
  FemBody body(spec, 1e-4, "fem");
  ASSERT_TRUE(body.hasDrivenNodes());
  const Vec3 shift(0.01, -0.02, 0.005);
  const Vec3 velocity(0.3, 0.0, 0.0);
  body.setDrivenPose(spec.driven_reference + shift, Quat::Identity(), velocity, Vec3::Zero());
  body.solveStatic(Vec3::Zero());
  for (std::size_t i = 0; i < body.nodeCount(); ++i) {
    EXPECT_LT((body.nodeDisplacement(i) - shift).norm(), 1e-9) << i;
  }
  EXPECT_LT(body.drivenReaction().force.norm(), 1e-6);
  EXPECT_LT(body.strainEnergy(), 1e-9);  // [J]; a 1 mm bending tip would store ~1e-2 J
  int driven = 0;
  for (std::size_t i = 0; i < body.surface().velocities().size(); ++i) {
    if (body.surface().velocities()[i] == velocity) ++driven;
  }
  EXPECT_EQ(driven, 4);  // the 4 corner nodes of the clamped end
}

}  // namespace
}  // namespace demlink::core
