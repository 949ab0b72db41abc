/// Deformable bodies in the World: stages, contacts with particles, reactions,
/// the time-step check and the checkpoint.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "checkpoint_test_support.hpp"
#include "deformable/deformable_test_scenes.hpp"
#include "demlink/core/input_error.hpp"
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
                                          "advance_clock"};
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

}  // namespace
}  // namespace demlink::core
