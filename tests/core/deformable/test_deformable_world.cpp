/// Deformable bodies in the World: stages, contacts with particles, reactions,
/// the time-step check and the checkpoint.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "checkpoint_test_support.hpp"
#include "deformable/deformable_test_scenes.hpp"
#include "demlink/core/base/input_error.hpp"
#include "test_scenes.hpp"

namespace demlink::core {
namespace {

constexpr double kG = 9.81;

SimulationSettings gravitySettings(double dt) {
  SimulationSettings s = test::fineSettings(dt, 1.0);
  s.gravity = Vec3(0.0, 0.0, -kG);
  return s;
}

MassSpringBody& addSheet(World& world, const MassSpringSpec& spec) {
  const std::size_t index = world.addDeformableBody(std::make_unique<MassSpringBody>(spec, "sheet"), "sheet");
  return static_cast<MassSpringBody&>(world.deformableBody(index));
}

TEST(DeformableWorld, StagesOfADeformableSceneNameTheBody) {
  World world(gravitySettings(2.0e-5));
  world.addMaterial(test::testMaterial(0.5));
  addSheet(world, test::sheetSpec(0.2, 0.02, 0.0, 0.05, 2000.0, 0.2, -1.0));
  const std::vector<std::string> expected{"velocity_verlet",  "mass_spring:sheet", "neighbour_list",
                                          "forces",           "particle_contacts:hertz_mindlin",
                                          "deformable_contacts", "mass_spring:sheet", "second_half_kick",
                                          "advance_clock",    "watchdog"};
  EXPECT_EQ(world.activeStages(), expected);
}

TEST(DeformableWorld, AddingABodyChecksMaterialNameFrameAndTime) {
  const MassSpringSpec spec = test::sheetSpec(0.1, 0.02, 0.0, 0.01, 2000.0, 0.5, -1.0);
  const auto expectError = [](World& world, const MassSpringSpec& body, const std::string& field) {
    try {
      world.addDeformableBody(std::make_unique<MassSpringBody>(body, "sheets[1]"), "sheets[1]");
      ADD_FAILURE() << "no error for " << field;
    } catch (const InputError& e) {
      EXPECT_EQ(e.field(), field) << e.what();
    }
  };
  World world(gravitySettings(2.0e-5));
  MassSpringSpec elsewhere = spec;
  elsewhere.material = 1;
  world.addMaterial(test::testMaterial(0.5));
  expectError(world, elsewhere, "sheets[1].material");
  addSheet(world, spec);
  expectError(world, spec, "sheets[1].name");
  FrameMotion shaking;
  shaking.linear_acceleration = Vec3(1.0, 0.0, 0.0);
  EXPECT_THROW(world.setFrameMotion(shaking), InputError);
  MassSpringSpec second = spec;
  second.name = "second";
  world.initialize();
  expectError(world, second, "sheets[1].name");
  EXPECT_EQ(world.deformableBodies().size(), 1u);
}

TEST(DeformableWorld, ASceneWithoutDeformablesRunsNoneOfTheirStages) {
  World world(gravitySettings(2.0e-5));
  world.addMaterial(test::testMaterial(0.5));
  world.addPlane({"floor", Vec3::Zero(), Vec3::UnitZ(), 0});
  world.addMesh(MeshBody("plate", {Vec3::Zero(), Vec3(1, 0, 0), Vec3(0, 1, 0)}, {{0, 1, 2}}, 0));
  ParticleSpec ball;
  ball.radius = 0.01;
  ball.position = Vec3(0.2, 0.2, 0.5);
  world.addParticle(ball);
  const std::vector<std::string> expected{"mesh_motion",  "velocity_verlet", "neighbour_list",
                                          "forces",       "particle_contacts:hertz_mindlin",
                                          "plane_contacts", "mesh_contacts", "second_half_kick",
                                          "advance_clock",  "watchdog"};
  EXPECT_EQ(world.activeStages(), expected);
}

TEST(DeformableWorld, SphereOnASingleLayerSheetIsHeld) {
  World world(gravitySettings(2.0e-5));
  world.addMaterial(test::testMaterial(0.5));
  MassSpringBody& sheet = addSheet(world, test::sheetSpec(0.2, 0.02, 0.0, 0.05, 2000.0, 1.0, 0.001));
  const double radius = 0.01;
  ParticleSpec ball;
  ball.radius = radius;
  ball.position = Vec3(0.001, 0.002, radius + 0.005);
  world.addParticle(ball);
  world.initialize();
  for (int k = 0; k < 20000; ++k) world.step();  // 0.4 s
  const double centreNode = sheet.nodePosition(60).z();  // node (5, 5): the centre
  const double z = world.particles().position[0].z();
  EXPECT_GT(centreNode, -0.05);
  EXPECT_LT(centreNode, 0.0) << "the sheet sags under the sphere";
  EXPECT_GT(z, centreNode + 0.9 * radius) << "the sphere rests on the sheet, not below it";
  EXPECT_LT(std::abs(world.particles().velocity[0].z()), 0.05) << "it stays with the sheet";
}

/// A bed of spheres on a sheet pinned along its edges, released just above it.
struct BedOnSheet {
  std::unique_ptr<World> world;
  MassSpringBody* sheet = nullptr;
  double bed_mass = 0.0;
};

BedOnSheet bedOnSheet() {
  BedOnSheet scene;
  scene.world = std::make_unique<World>(gravitySettings(2.0e-5));
  scene.world->addMaterial(test::testMaterial(0.3, 0.5, 0.1));
  scene.sheet = &addSheet(*scene.world, test::sheetSpec(0.2, 0.02, 0.0, 0.05, 2000.0, 1.0, 0.001, 100.0));
  const double radius = 0.01;
  for (int i = -2; i <= 2; ++i) {
    for (int j = -1; j <= 1; ++j) {
      ParticleSpec ball;
      ball.radius = radius;
      ball.position = Vec3(0.021 * i + 0.001 * j, 0.021 * j, radius + 0.002 + 0.001 * std::abs(i));
      scene.world->addParticle(ball);
      scene.bed_mass += test::sphereMass(radius, 2500.0);
    }
  }
  return scene;
}

TEST(DeformableWorld, MomentumOfSphereAndFreeSheetIsConservedThroughImpact) {
  World world(test::fineSettings(2.0e-5, 2.0));
  world.addMaterial(test::testMaterial(0.5, 0.3));
  MassSpringBody& sheet = addSheet(world, test::sheetSpec(0.1, 0.02, 0.0, 0.01, 2000.0, 0.5, 0.0));
  ParticleSpec ball;
  ball.radius = 0.01;
  ball.position = Vec3(0.013, -0.007, 0.0105);
  ball.velocity = Vec3(0.3, 0.1, -1.0);
  ball.angular_velocity = Vec3(0.0, 20.0, 0.0);
  world.addParticle(ball);
  world.initialize();
  const auto momentum = [&] {
    Vec3 p = world.particles().mass[0] * world.particles().velocity[0];
    const double nodeMass = sheet.totalMass() / static_cast<double>(sheet.nodeCount());
    for (std::size_t k = 0; k < sheet.nodeCount(); ++k) p += nodeMass * sheet.nodeVelocity(k);
    return p;
  };
  const Vec3 before = momentum();
  for (int n = 0; n < 1500; ++n) world.step();
  ASSERT_GT(sheet.kineticEnergy(), 1e-3 * world.kineticEnergy()) << "the sphere must have hit the sheet";
  EXPECT_LT((momentum() - before).norm(), 1e-12 * before.norm());
}

TEST(DeformableWorld, PinsCarryTheBedAndTheSheetOnceSettled) {
  BedOnSheet scene = bedOnSheet();
  World& world = *scene.world;
  world.initialize();
  // Settled: over a whole 0.05 s window the kinetic energy of spheres and sheet stayed below
  // 1e-7 of the bed's weight times the sheet's side; the reaction is averaged over that window.
  const double weight = (scene.bed_mass + scene.sheet->totalMass()) * kG;
  const double settled = 1e-7 * scene.bed_mass * kG * 0.2;
  const test::SettledWindow w = test::settleInWindows(
      world, 2500, settled, 60, [&] { return world.kineticEnergy() + scene.sheet->kineticEnergy(); },
      [&] { return scene.sheet->fixedReaction().force.z(); });
  ASSERT_LE(w.motion_max, settled) << w.steps << " steps";
  EXPECT_NEAR(w.mean_reaction / weight, 1.0, 0.01) << "after " << w.steps << " steps";
  EXPECT_NEAR(scene.sheet->fixedReaction().force.z() / weight, 1.0, 0.01);
  // Each sphere rests on the sheet: its centre about a radius above the sheet's nearest node.
  for (std::size_t i = 0; i < world.particles().size(); ++i) {
    const Vec3& x = world.particles().position[i];
    std::size_t nearest = 0;
    for (std::size_t k = 1; k < scene.sheet->nodeCount(); ++k) {
      const Vec3 d = scene.sheet->nodePosition(k) - x;
      const Vec3 best = scene.sheet->nodePosition(nearest) - x;
      if (d.head<2>().norm() < best.head<2>().norm()) nearest = k;
    }
    EXPECT_GT(x.z(), scene.sheet->nodePosition(nearest).z() + 0.5 * 0.01) << "sphere " << i;
  }
  std::printf("settled after %d steps; pins %.6g N, weight %.6g N\n", w.steps, w.mean_reaction, weight);
}

TEST(DeformableWorld, CheckpointMidRunContinuesBitIdentically) {
  BedOnSheet a = bedOnSheet();
  for (int n = 0; n < 600; ++n) a.world->step();
  const std::string bytes = test::saveToBytes(*a.world);
  for (int n = 0; n < 600; ++n) a.world->step();
  BedOnSheet b = bedOnSheet();
  b.world->restoreCheckpoint(std::string_view(bytes), "mid-run");
  for (int n = 0; n < 600; ++n) b.world->step();
  EXPECT_TRUE(test::differingColumns(*a.world, *b.world).empty());
  for (std::size_t k = 0; k < a.sheet->nodeCount(); ++k) {
    ASSERT_EQ(a.sheet->nodePosition(k), b.sheet->nodePosition(k)) << "node " << k;
    ASSERT_EQ(a.sheet->nodeVelocity(k), b.sheet->nodeVelocity(k)) << "node " << k;
  }
  EXPECT_EQ(test::saveToBytes(*a.world), test::saveToBytes(*b.world));
}

TEST(DeformableWorld, CheckpointOfAnotherSceneIsRefusedAndLeavesTheBodyAsItWas) {
  BedOnSheet a = bedOnSheet();
  for (int n = 0; n < 10; ++n) a.world->step();
  const std::string bytes = test::saveToBytes(*a.world);
  // Same particles, no sheet: the file has a body the scene lacks.
  World plain(gravitySettings(2.0e-5));
  plain.addMaterial(test::testMaterial(0.3, 0.3));
  for (std::size_t i = 0; i < a.world->particles().size(); ++i) {
    ParticleSpec ball;
    ball.radius = 0.01;
    plain.addParticle(ball);
  }
  EXPECT_THROW(plain.restoreCheckpoint(std::string_view(bytes), "mid-run"), InputError);
  // A sheet of another size: refused, and the body keeps its state.
  World other(gravitySettings(2.0e-5));
  other.addMaterial(test::testMaterial(0.3, 0.3));
  MassSpringBody& small = addSheet(other, test::sheetSpec(0.1, 0.02, 0.0, 0.05, 2000.0, 1.0, 0.001));
  for (std::size_t i = 0; i < a.world->particles().size(); ++i) {
    ParticleSpec ball;
    ball.radius = 0.01;
    ball.position = Vec3(0.0, 0.0, 0.1 + 0.03 * static_cast<double>(i));
    other.addParticle(ball);
  }
  other.initialize();
  const Vec3 before = small.nodePosition(3);
  EXPECT_THROW(other.restoreCheckpoint(std::string_view(bytes), "mid-run"), InputError);
  EXPECT_EQ(small.nodePosition(3), before);
}

TEST(DeformableWorld, TooLargeAStepForTheSheetIsRefusedNamingIt) {
  SimulationSettings settings = gravitySettings(2.0e-5);
  World probe(settings);
  probe.addMaterial(test::testMaterial(0.5));
  const MassSpringSpec spec = test::sheetSpec(0.2, 0.02, 0.0, 0.05, 2.0e6, 0.0, 0.001);
  MassSpringBody& sheet = addSheet(probe, spec);
  const double limit = sheet.criticalTimeStep();
  ASSERT_LT(limit, 2.0e-5);
  try {
    probe.initialize();
    ADD_FAILURE() << "no error";
  } catch (const InputError& e) {
    EXPECT_EQ(e.field(), "settings.time_step");
    EXPECT_NE(e.reason().find("sheet"), std::string::npos) << e.what();
  }
  settings.allow_unsafe_time_step = true;
  World unsafe(settings);
  unsafe.addMaterial(test::testMaterial(0.5));
  addSheet(unsafe, spec);
  unsafe.initialize();
  EXPECT_EQ(unsafe.timeStepReport().limit, limit);
  EXPECT_EQ(unsafe.timeStepReport().limited_by, "deformable sheet")
      << unsafe.timeStepReport().limited_by;
}

/// A fixed square of two triangles at z = 0 under a sphere resting on triangle (0, 1, 2);
/// with `tear` the spring along its edge 0-1 tears in the first step.
double sphereHeightOverSquare(bool tear) {
  World world(gravitySettings(2.0e-5));
  world.addMaterial(test::testMaterial(0.5));
  MassSpringSpec spec;
  spec.name = "square";
  spec.total_mass = 0.1;
  spec.nodes = {Vec3(-0.1, -0.1, 0.0), Vec3(0.1, -0.1, 0.0), Vec3(0.1, 0.1, 0.0), Vec3(-0.1, 0.1, 0.0)};
  spec.springs = {{0, 1, 100.0, 0.0, tear ? 0.1 : -1.0},
                  {1, 2, 100.0, 0.0, -1.0},
                  {2, 3, 100.0, 0.0, -1.0},
                  {3, 0, 100.0, 0.0, -1.0},
                  {0, 2, 100.0, 0.0, -1.0}};
  spec.triangles = {{0, 1, 2}, {0, 2, 3}};
  spec.fixed_nodes = {0, 1, 2, 3};
  spec.break_strain = 0.5;
  world.addDeformableBody(std::make_unique<MassSpringBody>(spec, "square"), "square");
  ParticleSpec ball;
  ball.radius = 0.01;
  ball.position = Vec3(0.05, -0.03, 0.0099);  // above triangle (0, 1, 2) only
  world.addParticle(ball);
  world.initialize();
  for (int n = 0; n < 10000; ++n) world.step();  // 0.2 s: a free fall of 0.2 m
  return world.particles().position[0].z();
}

TEST(DeformableWorld, ASphereFallsThroughATriangleThatLostItsSupport) {
  EXPECT_GT(sphereHeightOverSquare(false), 0.009);
  EXPECT_LT(sphereHeightOverSquare(true), -0.1);
}

}  // namespace
}  // namespace demlink::core
