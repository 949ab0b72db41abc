// Flow sensors: N spheres falling through a disc give exactly N crossings against the
// normal and their mass (relative 1e-12), spheres passing outside the radius are not
// counted, an oscillating sphere counts every crossing per direction but nets 0 or 1,
// removals and insertions next to the surface produce no false crossings, and
// per-interval counts add up to the totals.
#include <gtest/gtest.h>

#include <memory>

#include "demlink/core/components/flow_sensor.hpp"
#include "demlink/core/base/input_error.hpp"
#include "sensor_test_support.hpp"

namespace demlink::core {
namespace {

constexpr double kRadius = 0.002;  // [m]

FlowSensor& addDisc(World& world, double radius, const Vec3& normal, std::uint64_t every, const Vec3& centre = Vec3::Zero()) {
  RegionPlacement placement;
  placement.centre = centre;
  placement.orientation = surfaceOrientation(normal, Vec3::Zero(), "disc");
  return static_cast<FlowSensor&>(world.addComponent(std::make_unique<FlowSensor>(
      "disc", SurfaceShape::disc(radius, "disc"), placement, SampleSchedule{.every_steps = every}, "flow")));
}

TEST(FlowSensor, SpheresFallingThroughADiscAreCountedOnce) {
  World world(test::sensorSettings(Vec3(0.0, 0.0, -9.81)));
  world.addMaterial(test::testMaterial(0.5));
  // 4 x 4 x 3 spheres above a disc of radius 0.05 (all within 0.035 m of the axis),
  // plus a ring of 8 falling outside it (0.07 m from the axis).
  double massInside = 0.0;
  int inside = 0;
  for (int iz = 0; iz < 3; ++iz) {
    for (int iy = 0; iy < 4; ++iy) {
      for (int ix = 0; ix < 4; ++ix) {
        const Vec3 x(-0.024 + 0.016 * ix, -0.024 + 0.016 * iy, 0.005 + 0.01 * iz);
        test::addSphere(world, x, kRadius, Vec3(0.0, 0.0, -2.0));
        massInside += test::sphereMass(kRadius, 2500.0);
        ++inside;
      }
    }
  }
  for (int k = 0; k < 8; ++k) {
    const double angle = k * 0.785398;
    test::addSphere(world, Vec3(0.07 * std::cos(angle), 0.07 * std::sin(angle), 0.004), kRadius,
                    Vec3(0.0, 0.0, -2.0));
  }
  FlowSensor& flow = addDisc(world, 0.05, Vec3::UnitZ(), 500);
  world.initialize();
  for (int n = 0; n < 2500; ++n) world.step();  // every sphere ends below z = -0.02
  for (const Vec3& x : world.particles().position) ASSERT_LT(x.z(), -0.01);
  EXPECT_EQ(flow.total().negative_count, static_cast<std::uint64_t>(inside));
  EXPECT_EQ(flow.total().positive_count, 0u);
  EXPECT_EQ(flow.total().netCount(), -inside);
  EXPECT_NEAR(flow.total().negative_mass, massInside, 1e-12 * massInside);
  EXPECT_NEAR(flow.total().netMass(), -massInside, 1e-12 * massInside);
  EXPECT_LT(flow.trackedCount(), world.particles().size()) << "only spheres near the disc are remembered";
}

/// One sphere moving along z at 1 m/s through a disc in z = 0, reversing every
/// `halfPeriod` steps; it starts at z = +1 mm moving down, so it crosses at steps 100,
/// 100 + 400, ... Returns the sensor after `reversals` half periods.
struct Oscillation {
  std::uint64_t positive;
  std::uint64_t negative;
  std::int64_t net;
  std::uint64_t intervalPositiveSum;
  std::uint64_t intervalNegativeSum;
};

Oscillation oscillate(int halfPeriods, const Vec3& offset) {
  World world(test::sensorSettings());
  world.addMaterial(test::testMaterial(0.5));
  test::addSphere(world, offset + Vec3(0.0, 0.0, 0.001), kRadius, Vec3(0.0, 0.0, -1.0));
  FlowSensor& flow = addDisc(world, 0.01, Vec3::UnitZ(), 150);
  world.initialize();
  Oscillation o{0, 0, 0, 0, 0};
  for (int half = 0; half < halfPeriods; ++half) {
    for (int n = 0; n < 400; ++n) {
      world.step();
      if (world.stepCount() % 150 == 0) {
        o.intervalPositiveSum += flow.lastInterval().positive_count;
        o.intervalNegativeSum += flow.lastInterval().negative_count;
      }
    }
    world.particles().velocity[0] *= -1.0;
  }
  // Close the last interval.
  while (world.stepCount() % 150 != 0) world.step();
  o.intervalPositiveSum += flow.lastInterval().positive_count;
  o.intervalNegativeSum += flow.lastInterval().negative_count;
  o.positive = flow.total().positive_count;
  o.negative = flow.total().negative_count;
  o.net = flow.total().netCount();
  return o;
}

TEST(FlowSensor, OscillatingSphereCountsEveryCrossingButNetsZeroOrOne) {
  const Oscillation even = oscillate(4, Vec3::Zero());  // down, up, down, up: ends above
  EXPECT_EQ(even.negative, 2u);
  EXPECT_EQ(even.positive, 2u);
  EXPECT_EQ(even.net, 0);
  EXPECT_EQ(even.intervalPositiveSum, even.positive);
  EXPECT_EQ(even.intervalNegativeSum, even.negative);
  const Oscillation odd = oscillate(5, Vec3::Zero());  // ends below
  EXPECT_EQ(odd.negative, 3u);
  EXPECT_EQ(odd.positive, 2u);
  EXPECT_EQ(odd.net, -1);
  EXPECT_EQ(odd.intervalPositiveSum, odd.positive);
  EXPECT_EQ(odd.intervalNegativeSum, odd.negative);
  const Oscillation outside = oscillate(5, Vec3(0.0101, 0.0, 0.0));  // just outside r = 0.01
  EXPECT_EQ(outside.negative + outside.positive, 0u);
}

TEST(FlowSensor, RemovalsAndInsertionsBesideTheSurfaceAreNotCrossings) {
  World world(test::sensorSettings());
  world.addMaterial(test::testMaterial(0.5));
  // At rest on both sides of the disc plane, 0.5 mm from it, well apart.
  const std::uint64_t above = test::addSphere(world, Vec3(0.0, 0.0, 0.0005), kRadius);
  test::addSphere(world, Vec3(0.01, 0.0, -0.0005), kRadius);
  test::addSphere(world, Vec3(-0.01, 0.0, 0.0005), kRadius);
  FlowSensor& flow = addDisc(world, 0.05, Vec3::UnitZ(), 10);
  world.initialize();
  for (int n = 0; n < 20; ++n) world.step();
  ASSERT_GT(flow.trackedCount(), 0u);
  // Remove the sphere above: the one below moves into a lower slot.
  RemovalTally tally;
  const std::size_t slot = test::slotOf(world, above);
  world.removeParticlesIf([&](std::size_t i) { return i == slot; }, tally);
  ASSERT_EQ(tally.count, 1u);
  for (int n = 0; n < 20; ++n) world.step();
  // Insert new spheres on both sides, where earlier slots had the other side.
  test::addSphere(world, Vec3(0.0, 0.02, -0.0005), kRadius);
  const std::uint64_t insertedAbove = test::addSphere(world, Vec3(0.0, -0.02, 0.0005), kRadius);
  for (int n = 0; n < 20; ++n) world.step();
  EXPECT_EQ(flow.total().positive_count + flow.total().negative_count, 0u);
  // A real crossing afterwards is still seen: 1 mm down at 1 m/s.
  world.particles().velocity[test::slotOf(world, insertedAbove)] = Vec3(0.0, 0.0, -1.0);
  for (int n = 0; n < 100; ++n) world.step();
  EXPECT_EQ(flow.total().negative_count, 1u);
  EXPECT_EQ(flow.total().positive_count, 0u);
}

TEST(FlowSensor, TiltedRectangleCountsAlongItsNormal) {
  World world(test::sensorSettings());
  world.addMaterial(test::testMaterial(0.5));
  // A rectangle 0.04 x 0.01 in the plane x = 0.05 (normal +x), length along y.
  RegionPlacement placement;
  placement.centre = Vec3(0.05, 0.0, 0.0);
  placement.orientation = surfaceOrientation(Vec3::UnitX(), Vec3::UnitY(), "rect");
  auto& flow = static_cast<FlowSensor&>(world.addComponent(std::make_unique<FlowSensor>(
      "rect", SurfaceShape::rectangle(0.04, 0.01, "rect"), placement, SampleSchedule{.every_steps = 100}, "flow")));
  // Moving +x at 2 m/s: y within +-0.02 and z within +-0.005 cross it; others miss.
  test::addSphere(world, Vec3(0.0, 0.019, 0.0), kRadius, Vec3(2.0, 0.0, 0.0));
  test::addSphere(world, Vec3(0.0, -0.019, 0.0045), kRadius, Vec3(2.0, 0.0, 0.0));
  test::addSphere(world, Vec3(0.0, 0.0, 0.0055), kRadius, Vec3(2.0, 0.0, 0.0));
  test::addSphere(world, Vec3(0.0, 0.021, -0.01), kRadius, Vec3(2.0, 0.0, 0.0));
  world.initialize();
  for (int n = 0; n < 5000; ++n) world.step();
  EXPECT_EQ(flow.total().positive_count, 2u);
  EXPECT_EQ(flow.total().negative_count, 0u);
}

TEST(FlowSensor, MovingDiscMeetsRestingSpheres) {
  World world(test::sensorSettings());
  world.addMaterial(test::testMaterial(0.5));
  for (int k = 0; k < 3; ++k) test::addSphere(world, Vec3(0.01 * k, 0.0, 0.01 + 0.01 * k), kRadius);
  RegionPlacement placement;
  placement.orientation = surfaceOrientation(Vec3::UnitZ(), Vec3::Zero(), "disc");
  placement.velocity = Vec3(0.0, 0.0, 1.0);  // the disc rises through the spheres
  auto& flow = static_cast<FlowSensor&>(world.addComponent(std::make_unique<FlowSensor>(
      "lift", SurfaceShape::disc(0.05, "lift"), placement, SampleSchedule{.every_steps = 100}, "flow")));
  world.initialize();
  for (int n = 0; n < 5000; ++n) world.step();  // disc at z = 0.05
  EXPECT_EQ(flow.total().negative_count, 3u) << "relative to the disc, the spheres move against its normal";
  EXPECT_EQ(flow.total().positive_count, 0u);
}

}  // namespace
}  // namespace demlink::core
