/// MassSpringBody on its own: closed-form oscillation, energy and momentum
/// conservation, tearing thresholds and triangle support, reactions, validation.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <numbers>
#include <vector>

#include "deformable/deformable_test_scenes.hpp"
#include "demlink/core/deformable/mass_spring_body.hpp"
#include "demlink/core/base/input_error.hpp"
#include "demlink/core/state/state_stream.hpp"
#include "demlink/core/geometry/stl_reader.hpp"

namespace demlink::core {
namespace {

/// Two nodes `length` apart on x with one spring of rest length `rest`.
MassSpringSpec pairSpec(double totalMass, double stiffness, double length, double rest) {
  MassSpringSpec spec;
  spec.name = "pair";
  spec.total_mass = totalMass;
  spec.nodes = {Vec3::Zero(), Vec3(length, 0.0, 0.0)};
  spec.springs = {{0, 1, stiffness, 0.0, rest}};
  return spec;
}

void step(MassSpringBody& body, double dt, const Vec3& gravity) {
  body.beginStep(dt, gravity);
  body.surface().clearForces();
  body.endStep(dt, gravity);
}

TEST(MassSpringBody, TwoMassOscillatorHasThePeriodOfItsReducedMass) {
  const double k = 1000.0;     // N/m
  const double m = 1.0;        // kg per node
  const double mu = 0.5 * m;   // reduced mass
  const double period = 2.0 * std::numbers::pi * std::sqrt(mu / k);
  MassSpringBody body(pairSpec(2.0 * m, k, 1.1, 1.0), "pair");
  const double dt = period / 400.0;
  ASSERT_LT(dt, body.criticalTimeStep());
  // Upward zero crossings of the stretch, linearly interpolated.
  std::vector<double> crossings;
  double previous = body.nodePosition(1).x() - body.nodePosition(0).x() - 1.0;
  for (int n = 1; n <= 4000; ++n) {  // 10 periods
    step(body, dt, Vec3::Zero());
    const double stretch = body.nodePosition(1).x() - body.nodePosition(0).x() - 1.0;
    if (previous < 0.0 && stretch >= 0.0) crossings.push_back(dt * (n - 1 + previous / (previous - stretch)));
    previous = stretch;
  }
  ASSERT_GE(crossings.size(), 9u);
  const double measured = (crossings.back() - crossings.front()) / static_cast<double>(crossings.size() - 1);
  EXPECT_NEAR(measured / period, 1.0, 0.005) << "measured " << measured << " s, expected " << period << " s";
  std::printf("period %.9g s, 2 pi sqrt(mu/k) = %.9g s\n", measured, period);
}

TEST(MassSpringBody, UndampedEnergyDriftsLessThan1e4Over100Periods) {
  // A triangle of unequal springs, released stretched: several coupled modes.
  MassSpringSpec spec;
  spec.name = "triangle";
  spec.total_mass = 3.0;
  spec.nodes = {Vec3::Zero(), Vec3(1.2, 0.0, 0.0), Vec3(0.4, 1.1, 0.0)};
  spec.springs = {{0, 1, 800.0, 0.0, 1.0}, {1, 2, 1200.0, 0.0, 1.0}, {2, 0, 1000.0, 0.0, 1.0}};
  MassSpringBody body(spec, "triangle");
  const double slowest = 2.0 * std::numbers::pi * std::sqrt(1.0 / 800.0);  // an upper bound on every period
  const double dt = 0.01 * body.criticalTimeStep();
  const double e0 = body.kineticEnergy() + body.springEnergy();
  ASSERT_GT(e0, 0.0);
  double worst = 0.0;
  const int steps = static_cast<int>(100.0 * slowest / dt);
  for (int n = 0; n < steps; ++n) {
    step(body, dt, Vec3::Zero());
    worst = std::max(worst, std::abs(body.kineticEnergy() + body.springEnergy() - e0) / e0);
  }
  EXPECT_LT(worst, 1.0e-4) << steps << " steps";
  std::printf("largest relative energy error %.3g over %d steps\n", worst, steps);
}

/// Both nodes fixed: the spring keeps its load; does it break after one step?
bool breaksUnder(double loadFraction, bool byForce) {
  const double k = 500.0;
  MassSpringSpec spec = pairSpec(1.0, k, 1.02, 1.0);  // force 10 N, strain 0.02
  spec.fixed_nodes = {0, 1};
  if (byForce) {
    spec.break_force = 10.0 / loadFraction;
  } else {
    spec.break_strain = 0.02 / loadFraction;
  }
  MassSpringBody body(spec, "pair");
  step(body, 1.0e-3, Vec3::Zero());
  return body.brokenCount() == 1;
}

TEST(MassSpringBody, SpringBreaksJustAboveItsThresholds) {
  EXPECT_FALSE(breaksUnder(0.999, true));
  EXPECT_TRUE(breaksUnder(1.001, true));
  EXPECT_FALSE(breaksUnder(0.999, false));
  EXPECT_TRUE(breaksUnder(1.001, false));
}

TEST(MassSpringBody, ABrokenSpringIsRecordedAndNeverActsAgain) {
  MassSpringSpec spec = pairSpec(1.0, 500.0, 1.02, 1.0);
  spec.break_force = 5.0;
  MassSpringBody body(spec, "pair");
  step(body, 1.0e-3, Vec3::Zero());
  ASSERT_EQ(body.brokenSprings().size(), 1u);
  const BrokenSpring& broken = body.brokenSprings()[0];
  EXPECT_EQ(broken.spring, 0u);
  EXPECT_DOUBLE_EQ(broken.time, 1.0e-3);
  // It broke at the step's end positions (the first half kick moved the nodes a little).
  const double length = (body.nodePosition(1) - body.nodePosition(0)).norm();
  EXPECT_NEAR(broken.force, 500.0 * (length - 1.0), 1e-9);
  EXPECT_NEAR(broken.strain, length - 1.0, 1e-12);
  EXPECT_NEAR(broken.position.x(), 0.5 * (body.nodePosition(0).x() + body.nodePosition(1).x()), 1e-12);
  EXPECT_EQ(body.intact()[0], 0);
  // The spring's first half kick moved the nodes towards each other; after the tear they drift freely.
  const Vec3 v0 = body.nodeVelocity(0);
  for (int n = 0; n < 100; ++n) step(body, 1.0e-3, Vec3::Zero());
  EXPECT_EQ(body.nodeVelocity(0), v0);
  EXPECT_EQ(body.brokenCount(), 1u);
}

TEST(MassSpringBody, MomentumIsConservedThroughATear) {
  // A free chain released stretched; its stiffest spring tears while the chain oscillates.
  MassSpringSpec spec;
  spec.name = "chain";
  spec.total_mass = 4.0;
  spec.nodes = {Vec3::Zero(), Vec3(1.1, 0.05, 0.0), Vec3(2.0, -0.1, 0.02), Vec3(3.3, 0.0, 0.1)};
  spec.springs = {{0, 1, 900.0, 0.0, 1.0}, {1, 2, 1500.0, 0.0, 1.0}, {2, 3, 600.0, 0.0, 1.0},
                  {0, 2, 300.0, 0.0, 2.0}};
  spec.break_force = 120.0;
  MassSpringBody body(spec, "chain");
  Vec3 centre0 = Vec3::Zero();
  for (std::size_t n = 0; n < body.nodeCount(); ++n) centre0 += body.nodePosition(n);
  const double dt = 0.1 * body.criticalTimeStep();
  double scale = 0.0;  // largest |m v| of a node, for the tolerance
  for (int n = 0; n < 20000; ++n) {
    step(body, dt, Vec3::Zero());
    for (std::size_t k = 0; k < body.nodeCount(); ++k) scale = std::max(scale, body.nodeVelocity(k).norm());
  }
  ASSERT_GE(body.brokenCount(), 1u) << "the test needs a tear";
  Vec3 momentum = Vec3::Zero();
  Vec3 centre = Vec3::Zero();
  for (std::size_t n = 0; n < body.nodeCount(); ++n) {
    momentum += body.nodeVelocity(n);  // equal node masses
    centre += body.nodePosition(n);
  }
  EXPECT_LT(momentum.norm(), 1e-12 * scale);
  EXPECT_LT((centre - centre0).norm(), 1e-9);
}

TEST(MassSpringBody, SavedMidTearRunContinuesBitIdentically) {
  MassSpringSpec spec;
  spec.name = "chain";
  spec.total_mass = 3.0;
  spec.nodes = {Vec3::Zero(), Vec3(1.2, 0.1, 0.0), Vec3(2.5, 0.0, 0.1)};
  spec.springs = {{0, 1, 900.0, 0.5, 1.0}, {1, 2, 1500.0, 0.5, 1.0}, {0, 2, 100.0, 0.1, 2.0}};
  spec.triangles = {{0, 1, 2}};
  spec.break_force = 200.0;
  MassSpringBody a(spec, "chain");
  const double dt = 0.1 * a.criticalTimeStep();
  for (int n = 0; n < 3000; ++n) step(a, dt, Vec3(0.0, 0.0, -9.81));
  ASSERT_GE(a.brokenCount(), 1u) << "save after a tear";
  StateWriter out;
  a.save(out);
  MassSpringBody b(spec, "chain");
  StateReader in(out.bytes(), "memory", "body");
  b.restore(in);
  EXPECT_EQ(b.surface().active(), a.surface().active()) << "the body restores what its springs support";
  for (int n = 0; n < 3000; ++n) {
    step(a, dt, Vec3(0.0, 0.0, -9.81));
    step(b, dt, Vec3(0.0, 0.0, -9.81));
  }
  StateWriter endA;
  StateWriter endB;
  a.save(endA);
  b.save(endB);
  EXPECT_EQ(endA.bytes(), endB.bytes());
  EXPECT_EQ(a.brokenCount(), b.brokenCount());
}

TEST(MassSpringBody, ATriangleLosesItsSupportWhenAnEdgeSpringTears) {
  // A square of two triangles (0,1,2), (0,2,3); springs on every edge and the diagonal.
  MassSpringSpec spec;
  spec.name = "square";
  spec.total_mass = 1.0;
  spec.nodes = {Vec3::Zero(), Vec3(1.0, 0.0, 0.0), Vec3(1.0, 1.0, 0.0), Vec3(0.0, 1.0, 0.0)};
  spec.springs = {{0, 1, 100.0, 0.0, 0.5},  // stretched to strain 1: tears
                  {1, 2, 100.0, 0.0, -1.0}, {2, 3, 100.0, 0.0, -1.0}, {3, 0, 100.0, 0.0, -1.0},
                  {0, 2, 100.0, 0.0, -1.0}};
  spec.triangles = {{0, 1, 2}, {0, 2, 3}};
  spec.break_strain = 0.5;
  MassSpringBody body(spec, "square");
  EXPECT_EQ(body.surface().active(), (std::vector<char>{1, 1}));
  step(body, 1.0e-4, Vec3::Zero());
  ASSERT_EQ(body.brokenCount(), 1u);
  EXPECT_EQ(body.surface().active(), (std::vector<char>{0, 1}));
}

TEST(MassSpringBody, PinnedSheetAtRestCarriesItsWeightOnThePins) {
  const double mass = 0.05;
  MassSpringBody sheet(test::sheetSpec(0.2, 0.04, 0.0, mass, 2000.0, 1.0, -1.0, 20.0), "sheet");
  const Vec3 g(0.0, 0.0, -9.81);
  const double dt = 0.5 * sheet.criticalTimeStep();
  // Settled: the kinetic energy stayed below 1e-9 of the sheet's weight times its side
  // over a whole 0.2 s window (so not a turning point of a swing).
  const double settled = 1e-9 * mass * 9.81 * 0.2;
  const int window = static_cast<int>(0.2 / dt);
  double windowMax = 0.0;
  int n = 0;
  do {
    windowMax = 0.0;
    for (int k = 0; k < window; ++k, ++n) {
      step(sheet, dt, g);
      windowMax = std::max(windowMax, sheet.kineticEnergy());
    }
  } while (windowMax > settled && n < 100 * window);
  ASSERT_LE(windowMax, settled) << n << " steps";
  EXPECT_NEAR(sheet.fixedReaction().force.z() / (mass * 9.81), 1.0, 0.005);
  std::printf("settled after %d steps; pins %.6g N, weight %.6g N\n", n, sheet.fixedReaction().force.z(), mass * 9.81);
  EXPECT_NEAR(sheet.fixedReaction().force.x(), 0.0, 1e-6);
}

TEST(MassSpringBody, DrivenEdgesAtRestCarryTheWeightWithNoTorqueAboutTheCentre) {
  const double mass = 0.05;
  MassSpringSpec spec = test::sheetSpec(0.2, 0.04, 0.0, mass, 2000.0, 1.0, 0.001, 20.0);
  spec.driven_regions = spec.fixed_regions;  // all four edges, held by a pose at rest
  spec.fixed_regions.clear();
  spec.driven_reference = Vec3(0.01, 0.0, 0.0);  // off centre: the torque is about it
  MassSpringBody sheet(spec, "sheet");
  sheet.setDrivenPose(spec.driven_reference, Quat::Identity(), Vec3::Zero(), Vec3::Zero());
  const Vec3 g(0.0, 0.0, -9.81);
  const double dt = 0.5 * sheet.criticalTimeStep();
  for (int n = 0; n < static_cast<int>(2.0 / dt); ++n) step(sheet, dt, g);
  ASSERT_LT(sheet.kineticEnergy(), 1e-12);
  const NodeReaction r = sheet.drivenReaction();
  EXPECT_NEAR(r.force.z() / (mass * 9.81), 1.0, 1e-4);
  // The weight acts at the centre, 0.01 m along -x from the reference; its moment there is
  // -0.01 W about y, which the constraint balances.
  EXPECT_NEAR(r.torque.y(), 0.01 * mass * 9.81, 1e-6);
  EXPECT_NEAR(r.torque.x(), 0.0, 1e-6);
  EXPECT_EQ(sheet.fixedReaction().force, Vec3::Zero());
}

/// A lattice over the box [0, hi] at 0.1 m, 1 kg, 100 N/m.
MassSpringSpec latticeSpec(const std::string& name, const Vec3& hi) {
  MassSpringSpec spec;
  spec.name = name;
  spec.total_mass = 1.0;
  spec.stiffness = 100.0;
  spec.box = MassSpringSpec::Box{Vec3::Zero(), hi, 0.1};
  return spec;
}

TEST(MassSpringBody, LatticeCountsAndSurface) {
  MassSpringSpec spec = latticeSpec("block", Vec3(0.3, 0.2, 0.1));
  MassSpringBody block(spec, "block");
  EXPECT_EQ(block.nodeCount(), 4u * 3u * 2u);
  // Structural springs: 3*3*2 + 4*2*2 + 4*3*1.
  EXPECT_EQ(block.springs().size(), 18u + 16u + 12u);
  // Two triangles per outer quad: 2 * (3*2 + 3*1 + 2*1) * 2 faces.
  EXPECT_EQ(block.surface().triangles().size(), 2u * 2u * (6u + 3u + 2u));
  spec.shear_factor = 0.5;
  spec.bending_factor = 0.25;
  MassSpringBody braced(spec, "block");
  // Shear: two per cell face (xy: 3*2*2 faces, yz: 2*1*4, zx: 1*3*3); bending: 2*3*2 along x, 1*4*2 along y.
  EXPECT_EQ(braced.springs().size(), 46u + 2u * (12u + 8u + 9u) + 12u + 8u);
  // The outward normals of a closed surface sum to zero.
  Vec3 sum = Vec3::Zero();
  for (const auto& t : block.surface().triangles()) {
    const Vec3 a = block.nodePosition(t[0]);
    sum += (block.nodePosition(t[1]) - a).cross(block.nodePosition(t[2]) - a);
  }
  EXPECT_LT(sum.norm(), 1e-12);
}

TEST(MassSpringBody, DrivenNodesFollowTheirPoseRigidly) {
  MassSpringSpec spec = latticeSpec("flag", Vec3(0.2, 0.2, 0.01));
  spec.driven_regions = {{Vec3(-0.01, -0.01, -0.01), Vec3(0.01, 0.21, 0.01)}};  // the x = 0 edge
  spec.driven_reference = Vec3(0.0, 0.1, 0.0);
  MassSpringBody flag(spec, "flag");
  ASSERT_TRUE(flag.hasDrivenNodes());
  const Vec3 r0 = flag.nodePosition(0) - spec.driven_reference;
  const Vec3 w(0.0, 0.0, 2.0);
  flag.setDrivenPose(Vec3(0.0, 0.1, 0.0), Quat::Identity(), Vec3(0.5, 0.0, 0.0), w);
  const double dt = 1.0e-3;
  for (int n = 0; n < 100; ++n) step(flag, dt, Vec3::Zero());
  // x = p + R(w t) r0 for node 0 (a driven corner).
  const double t = 100 * dt;
  const Vec3 p(0.5 * t, 0.1, 0.0);
  const Vec3 expected = p + Eigen::AngleAxisd(2.0 * t, Vec3::UnitZ()) * r0;
  EXPECT_LT((flag.nodePosition(0) - expected).norm(), 1e-12);
  EXPECT_LT((flag.nodeVelocity(0) - (Vec3(0.5, 0.0, 0.0) + w.cross(expected - p))).norm(), 1e-12);
}

TEST(MassSpringBody, StlSurfaceGivesOneNodePerVertexAndOneSpringPerEdge) {
  // A tetrahedron: 4 vertices, 6 edges, 4 faces (each vertex repeated in the file).
  const std::vector<Vec3> vertices{Vec3::Zero(), Vec3(0.1, 0.0, 0.0), Vec3(0.0, 0.1, 0.0), Vec3(0.0, 0.0, 0.1)};
  const std::vector<std::array<std::uint32_t, 3>> faces{{0, 2, 1}, {0, 1, 3}, {1, 2, 3}, {0, 3, 2}};
  const std::string path = ::testing::TempDir() + "mass_spring_tetra.stl";
  writeStlAscii(path, vertices, faces);
  MassSpringSpec spec;
  spec.name = "tetra";
  spec.total_mass = 0.4;
  spec.stiffness = 50.0;
  spec.stl_path = path;
  MassSpringBody tetra(spec, "tetra");
  EXPECT_EQ(tetra.nodeCount(), 4u);
  EXPECT_EQ(tetra.springs().size(), 6u);
  EXPECT_EQ(tetra.surface().triangles().size(), 4u);
  EXPECT_DOUBLE_EQ(tetra.totalMass(), 0.4);
  for (const SpringSpec& spring : tetra.springs()) {
    EXPECT_DOUBLE_EQ(spring.rest_length, (tetra.nodePosition(spring.a) - tetra.nodePosition(spring.b)).norm());
    EXPECT_EQ(spring.stiffness, 50.0);
  }
}

void expectInputError(const MassSpringSpec& spec, const std::string& field) {
  try {
    MassSpringBody body(spec, "ms");
    ADD_FAILURE() << "no error for " << field;
  } catch (const InputError& e) {
    EXPECT_EQ(e.field(), field) << e.what();
  }
}

TEST(MassSpringBody, BadSpecsNameTheField) {
  MassSpringSpec good = pairSpec(1.0, 100.0, 1.0, -1.0);
  MassSpringSpec s = good;
  s.total_mass = 0.0;
  expectInputError(s, "ms.total_mass");
  s = good;
  s.springs[0].stiffness = -1.0;
  expectInputError(s, "ms.springs[0].stiffness");
  s = good;
  s.springs[0].b = 7;
  expectInputError(s, "ms.springs[0]");
  s = good;
  s.fixed_nodes = {2};
  expectInputError(s, "ms.fixed.nodes[0]");
  s = good;
  s.fixed_nodes = {0};
  s.driven_nodes = {0};
  expectInputError(s, "ms.driven.nodes[0]");
  s = good;
  s.fixed_regions = {{Vec3(5, 5, 5), Vec3(6, 6, 6)}};
  expectInputError(s, "ms.fixed.regions[0]");
  s = good;
  s.triangles = {{0, 1, 4}};
  expectInputError(s, "ms.triangles[0]");
  s = good;
  s.break_force = 0.0;
  expectInputError(s, "ms.break_force");
  s = good;
  s.box = MassSpringSpec::Box{Vec3::Zero(), Vec3::Ones(), 0.1};
  expectInputError(s, "ms");  // two sources
  MassSpringSpec box;
  box.name = "b";
  box.total_mass = 1.0;
  box.stiffness = 10.0;
  box.box = MassSpringSpec::Box{Vec3::Zero(), Vec3(1.0, 0.0, 1.0), 0.1};
  expectInputError(box, "ms.box.hi");
  box.box = MassSpringSpec::Box{Vec3::Zero(), Vec3::Ones(), 0.0};
  expectInputError(box, "ms.box.node_spacing");
  box.box = MassSpringSpec::Box{Vec3::Zero(), Vec3::Ones(), 0.001};  // 1001^3 nodes
  expectInputError(box, "ms.box.node_spacing");
  box.box = MassSpringSpec::Box{Vec3::Zero(), Vec3::Ones(), 0.1};
  box.stiffness = 0.0;
  expectInputError(box, "ms.stiffness");
  box.stiffness = 10.0;
  box.stl_path = "/nonexistent/file.stl";
  box.box.reset();
  expectInputError(box, "ms.stl_path");
}

}  // namespace
}  // namespace demlink::core
