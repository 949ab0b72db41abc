/// Region sensors count parallel bonds by their midpoint: two bonded pairs pulled apart
/// at different speeds, one sensor over both and one over the first pair's midpoint only
/// (a box narrower than the gap between the centres, so it holds no particle). The
/// broken counts follow the world's BondSet step by step, stay 0 while the bond force is
/// below the closed-form breaking load sigma_t A, and reach it within 1e-3.
#include <gtest/gtest.h>

#include <algorithm>
#include <memory>
#include <numbers>

#include "bonds/bond_test_scenes.hpp"
#include "demlink/core/components/region_sensor.hpp"

namespace demlink::core {
namespace {

using test::addSphere;
using test::kBondGap;
using test::kBondRadius;

constexpr double kSpacing = 2.0 * kBondRadius + kBondGap;  // centre distance of bonded neighbours [m]
constexpr double kPairOffset = 0.01;                         // the second pair's distance along y [m]

RegionSensor& addBoxSensor(World& world, const std::string& name, const Vec3& centre, const Vec3& size) {
  RegionPlacement placement;
  placement.centre = centre;
  return static_cast<RegionSensor&>(world.addComponent(std::make_unique<RegionSensor>(
      name, VolumeShape::box(size, name), placement, SampleSchedule{.every_steps = 1}, name)));
}

/// Sets the particle's velocity so that after the step's first half kick it is `velocity`.
void driveNextStep(World& world, std::size_t slot, const Vec3& velocity) {
  ParticleArrays& p = world.particles();
  const double h = 0.5 * world.settings().time_step;
  p.velocity[slot] = velocity - p.force[slot] * p.inv_mass[slot] * h;
  p.angular_velocity[slot] = Vec3::Zero();
}

TEST(BondsInRegion, SensorsCountBrokenBondsByMidpointAsTheBondSetDoes) {
  ParallelBondProperties props = test::bondProperties();
  props.tensile_strength = 5.0e6;  // [Pa]
  const double area = std::numbers::pi * kBondRadius * kBondRadius;
  const double load = props.tensile_strength * area;  // sigma_t A [N]
  const double dt = 1.0e-7;
  // The first pair reaches the load in 2e4 steps, the second in 4e4.
  const double speed = load / (props.normal_stiffness_per_area * area) / (2.0e4 * dt);
  SimulationSettings settings = test::bondSettings(dt);
  settings.watchdog.every_steps = 0;  // the test drives the pairs
  World world(settings);
  world.addMaterial(test::bondedMaterial());
  const Vec3 second(0.0, kPairOffset, 0.0);
  const std::uint64_t first = addSphere(world, Vec3::Zero());
  addSphere(world, Vec3(kSpacing, 0.0, 0.0));
  addSphere(world, second);
  addSphere(world, second + Vec3(kSpacing, 0.0, 0.0));
  world.addBondRule(test::everywhere(props));
  const Vec3 midpoint(0.5 * kSpacing, 0.0, 0.0);
  RegionSensor& all = addBoxSensor(world, "all", Vec3(0.5 * kSpacing, 0.5 * kPairOffset, 0.0),
                                   Vec3(0.01, 0.02, 0.01));
  RegionSensor& middle = addBoxSensor(world, "middle", midpoint, Vec3(0.5 * kSpacing, 0.5 * kSpacing, 0.5 * kSpacing));
  world.initialize();
  world.step();
  ASSERT_EQ(world.bonds().counts().intact, 2u);
  world.step();  // the sensors sample at each step's end
  ASSERT_EQ(middle.latest().count, 0u) << "the middle box holds no particle centre";
  ASSERT_EQ(middle.latest().bonds_intact, 1u) << "but the first pair's bond midpoint";
  ASSERT_EQ(all.latest().bonds_intact, 2u);
  const std::vector<std::string> columns = all.columns();
  ASSERT_EQ(columns.size(), 11u);
  EXPECT_EQ(columns[9], "bonds_intact");
  EXPECT_EQ(columns[10], "bonds_broken");

  ParticleArrays& p = world.particles();
  double largestBeforeFirstBreak = 0.0;
  std::uint64_t previousBroken = 0;
  for (int n = 0; n < 100000 && world.bonds().counts().broken < 2; ++n) {
    for (std::size_t i = 0; i < p.size(); ++i) {
      const double along = p.position[i].x() < midpoint.x() ? -0.5 : 0.5;
      const double rate = p.position[i].y() > 0.5 * kPairOffset ? 0.5 : 1.0;  // the second pair: half speed
      driveNextStep(world, i, along * rate * speed * Vec3::UnitX());
    }
    world.step();
    const BondCounts& counts = world.bonds().counts();
    const RegionReading& everything = all.latest();
    ASSERT_EQ(everything.bonds_broken, counts.broken) << "at step " << world.stepCount();
    ASSERT_EQ(everything.bonds_intact, counts.intact) << "at step " << world.stepCount();
    ASSERT_EQ(all.latestRow()[10], static_cast<double>(counts.broken)) << "the CSV row carries the count";
    ASSERT_EQ(middle.latest().bonds_intact + middle.latest().bonds_broken, 1u) << "the first pair's bond only";
    // The first pair's bond force (bonds load their particles only, no contact: the gap stays open).
    const double force = p.force[test::slotOf(world, first)].norm();
    if (counts.broken == 0) {
      largestBeforeFirstBreak = std::max(largestBeforeFirstBreak, force);
      EXPECT_LT(force, load * (1.0 + 1.0e-3));
      EXPECT_EQ(middle.latest().bonds_broken, 0u);
    }
    if (counts.broken == 1 && previousBroken == 0) {
      EXPECT_EQ(middle.latest().bonds_broken, 1u) << "the faster pair breaks first";
      EXPECT_NEAR(largestBeforeFirstBreak / load, 1.0, 1.0e-3)
          << "largest " << largestBeforeFirstBreak << " N, sigma_t A = " << load << " N";
    }
    previousBroken = counts.broken;
  }
  EXPECT_EQ(world.bonds().counts().broken, 2u);
  EXPECT_EQ(all.latest().bonds_broken, 2u);
  EXPECT_EQ(all.latest().bonds_intact, 0u);
  EXPECT_EQ(middle.latest().bonds_broken, 1u) << "the second pair's bond lies outside the middle box";
  EXPECT_EQ(world.bonds().counts().created(), 2u);
}

TEST(BondsInRegion, SensorsOfAWorldWithoutBondsKeepTheirColumns) {
  World world(test::bondSettings(1.0e-6));
  world.addMaterial(test::bondedMaterial());
  addSphere(world, Vec3::Zero());
  RegionSensor& sensor = addBoxSensor(world, "box", Vec3::Zero(), Vec3(0.01, 0.01, 0.01));
  world.initialize();
  world.step();
  EXPECT_EQ(sensor.columns().size(), 9u);
  EXPECT_EQ(sensor.latestRow().size(), 9u);
  EXPECT_EQ(sensor.latest().bonds_intact + sensor.latest().bonds_broken, 0u);
}

}  // namespace
}  // namespace demlink::core
