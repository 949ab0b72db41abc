// Checkpoints of the state that the scene components add to the world: clump bodies
// (pose, momentum, member slots), the moving frame (Omega advanced every step),
// growing bounds and facet-body collision windows. A run continued from a
// checkpoint in a freshly built world must equal the run that never stopped, bit
// for bit, including a gate that opens after the checkpoint was taken.
#include <cstring>
#include <sstream>

#include <gtest/gtest.h>

#include "demlink/core/base/input_error.hpp"
#include "demlink/core/world.hpp"
#include "checkpoint_test_support.hpp"
#include "test_scenes.hpp"

namespace demlink::core {
namespace {

std::string save(const World& world) { return test::saveToBytes(world); }

/// The differing column names joined, "" when all are bit-identical.
std::string differingColumns(const World& a, const World& b) {
  std::string joined;
  for (const std::string& name : test::differingColumns(a, b)) joined += (joined.empty() ? "" : ", ") + name;
  return joined;
}

/// Tumbling three-sphere clumps dropped onto a floor.
std::unique_ptr<World> clumpScene() {
  SimulationSettings s = test::fineSettings(2e-5, 1.0);
  auto world = std::make_unique<World>(s);
  const auto material = world->addMaterial(test::testMaterial(0.4, 0.5));
  world->addPlane({"floor", Vec3::Zero(), Vec3::UnitZ(), material});
  const auto shape = world->addClumpTemplate(
      ClumpTemplate("rod", {{Vec3(-0.003, 0, 0), 0.002}, {Vec3(0, 0.0005, 0), 0.0022}, {Vec3(0.003, 0, 0), 0.002}}));
  for (int k = 0; k < 6; ++k) {
    ClumpSpec spec;
    spec.template_index = shape;
    spec.material = material;
    spec.position = Vec3(0.004 * (k % 3), 0.005 * (k / 3), 0.004 + 0.003 * k);
    spec.orientation = Quat(Eigen::AngleAxisd(0.4 * k, Vec3(1, 2, 3).normalized()));
    spec.velocity = Vec3(0.02 * k, 0.0, -0.3);
    spec.angular_velocity = Vec3(5.0, -3.0 * k, 2.0);
    world->addClump(spec);
  }
  world->initialize();
  return world;
}

TEST(CheckpointFrameClumps, ClumpRunContinuesBitIdentically) {
  const auto a = clumpScene();
  for (int n = 0; n < 1500; ++n) a->step();
  const std::string file = save(*a);
  for (int n = 0; n < 1500; ++n) a->step();

  const auto b = clumpScene();
  b->restoreCheckpoint(std::string_view(file), "clumps.bin");
  EXPECT_EQ(save(*b), file);
  for (int n = 0; n < 1500; ++n) b->step();
  EXPECT_EQ(differingColumns(*a, *b), "");
  EXPECT_EQ(a->kineticEnergy(), b->kineticEnergy());
  // The clumps must have touched down and turned, or the test shows little.
  EXPECT_LT(a->planes()[0].force.z(), 0.0) << "force on the floor by the clumps points down";
}

/// A rotating, spinning-up frame with growing bounds; spheres rest on a mesh gate
/// that stops colliding at t = 0.03 s (after the checkpoint at 0.02 s).
std::unique_ptr<World> roomScene() {
  SimulationSettings s = test::fineSettings(2e-5, 1.0);
  s.gravity = Vec3(0.0, 0.0, -9.81);
  s.frame.angular_velocity = Vec3(0.0, 0.0, 1.5);
  s.frame.angular_acceleration = Vec3(0.0, 0.0, 4.0);
  s.frame.linear_acceleration = Vec3(1.0, 0.0, 0.0);
  DomainBounds bounds{Vec3(-0.01, -0.01, -0.001), Vec3(0.01, 0.01, 0.01)};
  bounds.growing = true;
  bounds.limit_lower = Vec3(-0.05, -0.05, -0.05);
  bounds.limit_upper = Vec3(0.05, 0.05, 0.05);
  s.bounds = bounds;
  auto world = std::make_unique<World>(s);
  const auto material = world->addMaterial(test::testMaterial(0.4, 0.5));
  const TriangleMesh plate = rectangleMesh(Vec3(0.0, 0.0, 0.0), 0.02, 0.02, 2, 2);
  MeshBody gate("gate", plate.vertices, plate.triangles, material);
  gate.setCollisionWindow(-1.0, 0.03);
  world->addMesh(std::move(gate));
  for (int k = 0; k < 9; ++k) {
    ParticleSpec p;
    p.radius = 0.0015;
    p.position = Vec3(0.0035 * (k % 3 - 1), 0.0035 * (k / 3 - 1), 0.0016);
    world->addParticle(p);
  }
  world->initialize();
  return world;
}

TEST(CheckpointFrameClumps, FrameGrowingBoundsAndGateContinueBitIdentically) {
  const auto a = roomScene();
  for (int n = 0; n < 1000; ++n) a->step();  // t = 0.02 s: still on the gate
  const std::string file = save(*a);
  for (int n = 0; n < 2000; ++n) a->step();  // the gate opens at 0.03 s

  const auto b = roomScene();
  b->restoreCheckpoint(std::string_view(file), "frame_clumps.bin");
  for (int n = 0; n < 2000; ++n) b->step();
  EXPECT_EQ(differingColumns(*a, *b), "");
  ASSERT_TRUE(a->currentBounds() && b->currentBounds());
  EXPECT_TRUE(a->currentBounds()->lower == b->currentBounds()->lower);
  EXPECT_TRUE(a->currentBounds()->upper == b->currentBounds()->upper);
  EXPECT_TRUE(a->settings().frame.angular_velocity == b->settings().frame.angular_velocity);
  // The gate opened: the spheres fell below it, and the bounds grew to follow them.
  double lowest = 1.0;
  for (const Vec3& x : a->particles().position) lowest = std::min(lowest, x.z());
  EXPECT_LT(lowest, -0.002);
  EXPECT_LT(a->currentBounds()->lower.z(), -0.001);
}

TEST(CheckpointFrameClumps, ClumpsInARotatingFrameAreRefused) {
  SimulationSettings s = test::fineSettings(2e-5, 1.0);
  s.frame.angular_velocity = Vec3(0.0, 0.0, 1.0);
  World world(s);
  const auto material = world.addMaterial(test::testMaterial(0.4, 0.5));
  const auto shape = world.addClumpTemplate(ClumpTemplate("pair", {{Vec3(-0.001, 0, 0), 0.002}, {Vec3(0.001, 0, 0), 0.002}}));
  ClumpSpec spec;
  spec.template_index = shape;
  spec.material = material;
  world.addClump(spec);
  try {
    world.initialize();
    FAIL() << "expected an InputError";
  } catch (const InputError& error) {
    EXPECT_EQ(error.field(), "settings.frame.angular_velocity");
  }
}

}  // namespace
}  // namespace demlink::core
