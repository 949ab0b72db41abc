/// FEM bodies in the World: a sphere carried by a plate, a sphere rebounding off a
/// stiff block, through the same contact code as a rigid plane.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "deformable/deformable_test_scenes.hpp"
#include "deformable/fem_test_support.hpp"
#include "demlink/core/components/deformable_attachment.hpp"
#include "demlink/core/deformable/tet_mesh.hpp"
#include "test_scenes.hpp"

namespace demlink::core {
namespace {

constexpr double kG = 9.81;
constexpr double kRadius = 0.02;  // [m]

/// A linear-tetrahedron FEM box [lo, hi] of nx x ny x nz cells written to `path`.
FemSpec boxSpec(const std::string& path, const Vec3& lo, const Vec3& hi, int nx, int ny, int nz) {
  writeGmsh(path, boxTetMesh(lo, hi, nx, ny, nz, 1), "4.1");
  FemSpec spec;
  spec.name = "fem";
  spec.msh_path = path;
  spec.poisson_ratio = 0.3;
  return spec;
}

FemBody& addFem(World& world, const FemSpec& spec) {
  const std::size_t index =
      world.addDeformableBody(std::make_unique<FemBody>(spec, world.settings().time_step, "fem"), "fem");
  return static_cast<FemBody&>(world.deformableBody(index));
}

TEST(FemWorld, EdgeReactionsOfAPlateCarryTheSphereAndThePlateOnceSettled) {
  fem_test::TempDir dir("plate");
  SimulationSettings settings = test::fineSettings(2.0e-5, 1.0);
  settings.gravity = Vec3(0.0, 0.0, -kG);
  World world(settings);
  world.addMaterial(test::testMaterial(0.3, 0.5, 0.1));  // friction: a frictionless sphere rolls in the dip
  // A plate of 0.2 x 0.2 x 0.005 m, 1000 kg/m^3 (0.2 kg) under a sphere of 0.084 kg: a reversed
  // coupling force (-0.82 N instead of +0.82 N on 2.78 N) misses by 59%. The contact force reaches
  // the FEM solve one step late, i.e. explicitly, so its damping (sized for the sphere's mass,
  // ~25 N s/m at e = 0.3) must stay below 2 m_node / dt on the surface nodes: at 100 kg/m^3
  // (top nodes ~1e-4 kg) the tangential force chatters at the Coulomb limit.
  const double h = 0.1;
  const double t = 0.005;
  FemSpec spec = boxSpec(dir.file("plate.msh"), Vec3(-h, -h, -t), Vec3(h, h, 0.0), 10, 10, 1);
  spec.youngs_modulus = 1.0e7;
  spec.density = 1000.0;
  // Damping: alpha for the mesh's high modes, beta = 200/s (zeta of order 1 at the plate's first
  // modes with the sphere on it) so plate and sphere come to rest within a few tenths of a second.
  spec.rayleigh_alpha = 1.0e-5;
  spec.rayleigh_beta = 200.0;
  const double e = 1e-9;
  for (const double s : {-1.0, 1.0}) {
    spec.fixed_regions.push_back({Vec3(s * h - e, -h - e, -t - e), Vec3(s * h + e, h + e, e)});
    spec.fixed_regions.push_back({Vec3(-h - e, s * h - e, -t - e), Vec3(h + e, s * h + e, e)});
  }
  FemBody& plate = addFem(world, spec);
  ParticleSpec ball;
  ball.radius = kRadius;
  ball.position = Vec3(0.003, -0.002, kRadius + 1e-4);
  world.addParticle(ball);
  world.initialize();
  const double weight = (world.particles().mass[0] + plate.totalMass()) * kG;
  // Settled: over a 0.02 s window the sphere's speed stayed below 1e-4 m/s; the reaction is
  // averaged over that window.
  const test::SettledWindow w = test::settleInWindows(
      world, 1000, 1e-4, 100, [&] { return world.particles().velocity[0].norm(); },
      [&] { return plate.fixedReaction().force.z(); });
  ASSERT_LE(w.motion_max, 1e-4) << w.steps << " steps; sphere at " << world.particles().position[0].transpose();
  EXPECT_GT(world.particles().position[0].z(), 0.5 * kRadius) << "the sphere rests on the plate";
  EXPECT_NEAR(w.mean_reaction / weight, 1.0, 0.01) << "after " << w.steps << " steps";
  EXPECT_NEAR(plate.fixedReaction().force.z() / weight, 1.0, 0.01);
  EXPECT_LT(plate.fixedReaction().force.head<2>().norm(), 1e-3 * weight);
  std::printf("settled after %d steps; edges %.6g N, sphere + plate %.6g N\n", w.steps, w.mean_reaction, weight);
}

/// Rebound speed over impact speed of a sphere thrown at 1 m/s onto z = 0 (no gravity), off a
/// plane or off the top face of an FEM block whose bottom is fixed; `impulse` gets the time
/// integral of the block's fixed-node reaction [N s].
double restitutionOff(bool block, double* impulse) {
  fem_test::TempDir dir("block");
  World world(test::fineSettings(2.0e-5, 1.0));
  world.addMaterial(test::testMaterial(0.5));
  FemBody* body = nullptr;
  if (block) {
    // E = 1e10 Pa, 0.1 x 0.1 x 0.05 m: first mode ~c / (4 H) = 16 kHz (c = 3.2 km/s), period
    // 6e-5 s, against a Hertz contact of ~7 ms (E = 1e7 Pa, R = 0.02 m, 1 m/s). The block
    // responds quasi-statically; the energy it stores at the peak force (~20 N, axial stiffness
    // ~2e9 N/m) is 1e-7 J against the sphere's 0.04 J, so it rebounds as off a rigid plane.
    FemSpec spec = boxSpec(dir.file("block.msh"), Vec3(-0.05, -0.05, -0.05), Vec3(0.05, 0.05, 0.0), 4, 4, 2);
    spec.youngs_modulus = 1.0e10;
    spec.density = 1000.0;
    spec.rayleigh_alpha = 1.0e-6;
    spec.fixed_regions.push_back({Vec3(-0.06, -0.06, -0.0501), Vec3(0.06, 0.06, -0.0499)});
    body = &addFem(world, spec);
  } else {
    world.addPlane({"floor", Vec3::Zero(), Vec3::UnitZ(), 0});
  }
  ParticleSpec ball;
  ball.radius = kRadius;
  ball.position = Vec3(0.004, 0.007, kRadius + 1e-4);  // inside a triangle of the top face
  ball.velocity = Vec3(0.0, 0.0, -1.0);
  world.addParticle(ball);
  world.initialize();
  *impulse = 0.0;
  const double dt = world.settings().time_step;
  // 0.03 s: the contact (~7 ms) is over and the block's vibrations have died out.
  for (int n = 0; n < 1500; ++n) {
    world.step();
    if (body != nullptr) *impulse += body->fixedReaction().force.z() * dt;
  }
  return world.particles().velocity[0].z() / 1.0;
}

TEST(FemWorld, SphereReboundsOffAStiffBlockAsOffAPlaneOfTheSameMaterial) {
  double planeImpulse = 0.0;
  double blockImpulse = 0.0;
  const double plane = restitutionOff(false, &planeImpulse);
  const double block = restitutionOff(true, &blockImpulse);
  ASSERT_GT(plane, 0.3);
  EXPECT_NEAR(block / plane, 1.0, 0.02) << "plane " << plane << ", block " << block;
  // The ground took the sphere's momentum change through the block.
  const double mass = test::sphereMass(kRadius, 2500.0);
  EXPECT_NEAR(blockImpulse / (mass * (1.0 + block)), 1.0, 0.02);
  std::printf("restitution: plane %.6f, block %.6f; impulse %.6g N s for %.6g\n", plane, block, blockImpulse,
              mass * (1.0 + block));
}

// A mass-spring sheet and an FEM beam attached to one moving, turning mesh: after every step
// the driven nodes of both sit where the mesh carries them, p(t) + R(t) R(0)^-1 (X - p(0)),
// and move with its velocity (one pose rule for both kinds; a body lagging one step would be
// off by v dt = 1e-5 m).
TEST(FemWorld, DrivenNodesOfBothKindsFollowTheirRigidBodyInTheSameStep) {
  fem_test::TempDir dir("attached");
  const double dt = 1.0e-4;
  World world(test::fineSettings(dt, 1.0));
  world.addMaterial(test::testMaterial(0.5));
  const std::size_t mesh = world.addMesh(
      MeshBody("carrier", {Vec3(0, 0, 0), Vec3(0.01, 0, 0), Vec3(0, 0.01, 0)}, {{0, 1, 2}}, 0));
  world.mesh(mesh).setPose(Vec3(0.02, -0.01, 0.3), Quat(Eigen::AngleAxisd(0.3, Vec3(1, 2, 3).normalized())));
  world.mesh(mesh).setVelocity(Vec3(0.1, -0.05, 0.02), Vec3(0.5, -1.0, 2.0));
  const Vec3 p0 = world.mesh(mesh).position();
  const Quat q0 = world.mesh(mesh).orientation();

  MassSpringSpec sheetSpec = test::sheetSpec(0.1, 0.02, 0.0, 0.01, 100.0, 0.0, 0.0);
  sheetSpec.driven_regions.push_back({Vec3(-0.051, -0.051, -0.01), Vec3(-0.049, 0.051, 0.01)});
  sheetSpec.driven_reference = p0;
  const std::size_t sheet =
      world.addDeformableBody(std::make_unique<MassSpringBody>(sheetSpec, "sheet"), "sheet");
  fem_test::Beam beam = fem_test::Beam::coarse(4);
  beam.order = 1;
  writeGmsh(dir.file("beam.msh"), beam.mesh(), "4.1");
  FemSpec beamSpec = beam.spec(dir.file("beam.msh"));
  beamSpec.driven_regions = beamSpec.fixed_regions;
  beamSpec.fixed_regions.clear();
  beamSpec.driven_reference = p0;
  const std::size_t fem = world.addDeformableBody(std::make_unique<FemBody>(beamSpec, dt, "beam"), "beam");
  world.addComponent(std::make_unique<DeformableAttachment>("sheet", sheet, mesh));
  world.addComponent(std::make_unique<DeformableAttachment>("beam", fem, mesh));
  world.initialize();

  // Driven nodes and their positions as built.
  const auto drivenNodes = [](const DeformableBody& body, const NodeConstraintSpec& spec) {
    std::vector<std::pair<std::size_t, Vec3>> out;
    for (std::size_t n = 0; n < body.nodeCount(); ++n) {
      const Vec3 x = body.nodePosition(n);
      for (const NodeRegion& r : spec.driven_regions) {
        if ((x.array() >= r.lo.array()).all() && (x.array() <= r.hi.array()).all()) out.emplace_back(n, x);
      }
    }
    return out;
  };
  const auto sheetNodes = drivenNodes(*world.deformableBodies()[sheet], sheetSpec);
  const auto beamNodes = drivenNodes(*world.deformableBodies()[fem], beamSpec);
  ASSERT_EQ(sheetNodes.size(), 6u);
  ASSERT_EQ(beamNodes.size(), 4u);
  double worst = 0.0;
  double worstVelocity = 0.0;
  for (int step = 0; step < 50; ++step) {
    world.step();
    const MeshBody& carrier = world.meshes()[mesh];
    const Mat3 r = (carrier.orientation() * q0.conjugate()).toRotationMatrix();
    for (const auto& [index, nodes] : {std::pair{sheet, &sheetNodes}, std::pair{fem, &beamNodes}}) {
      const DeformableBody& body = *world.deformableBodies()[index];
      for (const auto& [node, built] : *nodes) {
        const Vec3 expected = carrier.position() + r * (built - p0);
        worst = std::max(worst, (body.nodePosition(node) - expected).norm());
        worstVelocity = std::max(worstVelocity, (body.nodeVelocity(node) - carrier.velocityAt(expected)).norm());
      }
    }
  }
  EXPECT_LT(worst, 1e-14) << "[m]";
  EXPECT_LT(worstVelocity, 1e-13) << "[m/s]";
  std::printf("largest distance of a driven node from its place on the mesh: %.3g m, %.3g m/s\n", worst,
              worstVelocity);
}

}  // namespace
}  // namespace demlink::core
