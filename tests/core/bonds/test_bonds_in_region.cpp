/// Region sensors count parallel bonds by their midpoint: two bonded pairs pulled apart
/// at different speeds, one sensor over both and one over the first pair's midpoint only
/// (a box narrower than the gap between the centres, so it holds no particle). The
/// broken counts follow the world's BondSet step by step, stay 0 while the bond force is
/// below the closed-form breaking load sigma_t A, and reach it within 1e-3. A restored
/// sensor reports the bond counts of the uninterrupted run at once and then the same rows.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstring>
#include <memory>
#include <numbers>
#include <sstream>
#include <string_view>

#include "bonds/bond_test_scenes.hpp"
#include "demlink/core/components/region_sensor.hpp"
#include "demlink/core/base/input_error.hpp"

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

/// Three bonded pairs flying apart at 0.5, 0.1 and 0.05 m/s: the fastest pair's bond
/// breaks (peak force sqrt(kn A m/2) v above sigma_t A), the others hold. One region
/// sensor over all of them, sampled every 10 steps.
struct FlyingPairs {
  std::unique_ptr<World> world;
  RegionSensor* sensor = nullptr;
};

FlyingPairs flyingPairs() {
  ParallelBondProperties props = test::bondProperties();
  props.tensile_strength = 1.0e5;  // [Pa]: sigma_t A = 0.31 N, broken above 0.24 m/s
  SimulationSettings settings = test::bondSettings(1.0e-7);
  settings.watchdog.every_steps = 0;  // the pairs move faster than the scene's impact speed
  FlyingPairs scene{std::make_unique<World>(settings)};
  World& world = *scene.world;
  world.addMaterial(test::bondedMaterial());
  const double speeds[] = {0.5, 0.1, 0.05};  // [m/s]
  for (int k = 0; k < 3; ++k) {
    const Vec3 at(0.0, k * kPairOffset, 0.0);
    addSphere(world, at, Vec3(-0.5 * speeds[k], 0.0, 0.0));
    addSphere(world, at + Vec3(kSpacing, 0.0, 0.0), Vec3(0.5 * speeds[k], 0.0, 0.0));
  }
  world.addBondRule(test::everywhere(props));
  RegionPlacement placement;
  placement.centre = Vec3(0.5 * kSpacing, kPairOffset, 0.0);
  scene.sensor = &static_cast<RegionSensor&>(world.addComponent(std::make_unique<RegionSensor>(
      "pairs", VolumeShape::box(Vec3(0.1, 0.1, 0.1), "pairs"), placement, SampleSchedule{.every_steps = 10}, "pairs")));
  world.initialize();
  return scene;
}

/// A restored region sensor reports the bond counts the uninterrupted run reports at the
/// same step (read at once, before any new sample), and both runs go on to the same bits.
TEST(BondsInRegion, RestoredSensorReportsTheUninterruptedBondCounts) {
  constexpr int kSteps = 400;
  FlyingPairs a = flyingPairs();
  for (int n = 0; n < kSteps / 2; ++n) a.world->step();
  const RegionReading atHalf = a.sensor->latest();
  ASSERT_EQ(atHalf.bonds_intact, 2u) << "the slower pairs hold";
  ASSERT_EQ(atHalf.bonds_broken, 1u) << "the fastest pair broke";
  ASSERT_EQ(atHalf.bonds_intact, a.world->bonds().counts().intact);

  FlyingPairs b = flyingPairs();
  for (int n = 0; n < kSteps / 2; ++n) b.world->step();
  std::ostringstream checkpoint;
  b.world->saveCheckpoint(checkpoint);
  FlyingPairs restored = flyingPairs();
  restored.world->restoreCheckpoint(std::string_view(checkpoint.str()), "b.bin");
  EXPECT_EQ(restored.sensor->latest().bonds_intact, atHalf.bonds_intact);
  EXPECT_EQ(restored.sensor->latest().bonds_broken, atHalf.bonds_broken);
  EXPECT_EQ(restored.sensor->latest().count, atHalf.count);
  EXPECT_EQ(restored.sensor->latestRow(), a.sensor->latestRow());

  for (int n = kSteps / 2; n < kSteps; ++n) {
    a.world->step();
    restored.world->step();
    const std::vector<double>& rowA = a.sensor->latestRow();
    const std::vector<double>& rowB = restored.sensor->latestRow();
    ASSERT_EQ(rowA.size(), rowB.size());
    ASSERT_EQ(std::memcmp(rowA.data(), rowB.data(), rowA.size() * sizeof(double)), 0)
        << "sensor rows differ at step " << a.world->stepCount();
    ASSERT_EQ(restored.sensor->latest().bonds_intact, a.sensor->latest().bonds_intact) << a.world->stepCount();
    ASSERT_EQ(restored.sensor->latest().bonds_broken, a.sensor->latest().bonds_broken) << a.world->stepCount();
  }
  EXPECT_EQ(a.sensor->sampleCount(), restored.sensor->sampleCount());
}

/// A checkpoint whose latest row holds a bond count that is not a whole number >= 0 is
/// refused naming the sensor's section.
TEST(BondsInRegion, RestoreRefusesABondCountThatIsNotACount) {
  FlyingPairs a = flyingPairs();
  for (int n = 0; n < 50; ++n) a.world->step();
  std::ostringstream out;
  a.world->saveCheckpoint(out);
  std::string bytes = out.str();
  // The latest row's last value (bonds_broken) is stored as a double; find it after the
  // row's time (the first value) and replace it with -1.5.
  const std::vector<double>& row = a.sensor->latestRow();
  std::string needle(reinterpret_cast<const char*>(row.data()), row.size() * sizeof(double));
  const std::size_t at = bytes.find(needle);
  ASSERT_NE(at, std::string::npos);
  const double bad = -1.5;
  std::memcpy(bytes.data() + at + (row.size() - 1) * sizeof(double), &bad, sizeof bad);
  FlyingPairs b = flyingPairs();
  try {
    b.world->restoreCheckpoint(std::string_view(bytes), "bad.bin");
    ADD_FAILURE() << "a bond count of -1.5 was accepted";
  } catch (const InputError& error) {
    EXPECT_NE(std::string(error.what()).find("bonds_broken"), std::string::npos) << error.what();
    EXPECT_NE(error.field().find("pairs"), std::string::npos) << error.field();
  }
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
