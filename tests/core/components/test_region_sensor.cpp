// Region sensors: count, mass, mean velocity and centre of mass of a random set
// against sums computed directly (relative 1e-12); a sensor attached to a rotating
// mesh body and one moving with a constant velocity follow their carrier (1e-9 m); an
// empty region writes empty CSV cells with the header's column count, and its checkpoint
// carries the missing values as flags, never as NaN.
#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <memory>
#include <numbers>
#include <unistd.h>

#include "demlink/core/base/input_error.hpp"
#include "demlink/core/components/region_sensor.hpp"
#include "checkpoint_test_support.hpp"
#include "csv_test_support.hpp"
#include "sensor_test_support.hpp"

namespace demlink::core {
namespace {

struct DirectSums {
  std::uint64_t count = 0;
  double mass = 0.0;
  Vec3 momentum = Vec3::Zero();
  Vec3 moment = Vec3::Zero();
};

/// Random, non-overlapping spheres (rejection on a coarse lattice) with random velocities.
void addRandomSpheres(World& world, test::SplitMix& rng, int count) {
  for (int k = 0; k < count; ++k) {
    const Vec3 cell(k % 10, (k / 10) % 10, k / 100);
    const Vec3 position = 0.02 * cell + rng.vector(-0.004, 0.004) - Vec3(0.1, 0.1, 0.02);
    test::addSphere(world, position, rng.uniform(0.002, 0.005), rng.vector(-1.0, 1.0));
  }
}

void expectReadingMatches(const RegionReading& reading, const DirectSums& direct) {
  ASSERT_GT(direct.count, 10u) << "the random set should put several spheres inside";
  EXPECT_EQ(reading.count, direct.count);
  EXPECT_NEAR(reading.mass, direct.mass, 1e-12 * direct.mass);
  const Vec3 velocity = direct.momentum / direct.mass;
  const Vec3 centre = direct.moment / direct.mass;
  EXPECT_LT((reading.mean_velocity - velocity).norm(), 1e-12 * (1.0 + velocity.norm()));
  EXPECT_LT((reading.centre_of_mass - centre).norm(), 1e-12);
}

TEST(RegionSensor, BoxReadingMatchesDirectSumsOfARandomSet) {
  World world(test::sensorSettings());
  world.addMaterial(test::testMaterial(0.5));
  test::SplitMix rng(42);
  addRandomSpheres(world, rng, 300);
  RegionPlacement placement;
  placement.centre = Vec3(0.0, -0.01, 0.0);
  placement.orientation = Quat(Eigen::AngleAxisd(0.4, Vec3(0.3, -1.0, 2.0).normalized()));
  const Vec3 sides(0.09, 0.12, 0.05);
  auto& sensor = static_cast<RegionSensor&>(world.addComponent(std::make_unique<RegionSensor>(
      "box", VolumeShape::box(sides, "box"), placement, SampleSchedule{.every_steps = 5}, "sensor")));
  world.initialize();

  // Direct: project onto the box's three unit axes.
  const Mat3 axes = placement.orientation.toRotationMatrix();
  const ParticleArrays& p = world.particles();
  DirectSums direct;
  for (std::size_t i = 0; i < p.size(); ++i) {
    const Vec3 d = p.position[i] - placement.centre;
    bool inside = true;
    for (int k = 0; k < 3; ++k) inside = inside && std::abs(d.dot(axes.col(k))) <= 0.5 * sides[k];
    if (!inside) continue;
    ++direct.count;
    direct.mass += p.mass[i];
    direct.momentum += p.mass[i] * p.velocity[i];
    direct.moment += p.mass[i] * p.position[i];
  }
  expectReadingMatches(sensor.latest(), direct);
  ASSERT_EQ(sensor.latestRow().size(), sensor.columns().size());
  EXPECT_EQ(sensor.latestRow()[1], static_cast<double>(direct.count));
}

TEST(RegionSensor, SphereReadingMatchesDirectSumsAfterSteps) {
  World world(test::sensorSettings());
  world.addMaterial(test::testMaterial(0.5));
  test::SplitMix rng(7);
  addRandomSpheres(world, rng, 300);
  RegionPlacement placement;
  placement.centre = Vec3(-0.02, 0.0, 0.01);
  const double radius = 0.06;
  auto& sensor = static_cast<RegionSensor&>(world.addComponent(std::make_unique<RegionSensor>(
      "ball", VolumeShape::sphere(radius, "ball"), placement, SampleSchedule{.every_steps = 10}, "sensor")));
  for (int n = 0; n < 30; ++n) world.step();
  ASSERT_EQ(sensor.sampleCount(), 4u) << "initial sample + steps 10, 20, 30";
  EXPECT_DOUBLE_EQ(sensor.latest().time, world.time());
  const ParticleArrays& p = world.particles();
  DirectSums direct;
  for (std::size_t i = 0; i < p.size(); ++i) {
    if ((p.position[i] - placement.centre).norm() > radius) continue;
    ++direct.count;
    direct.mass += p.mass[i];
    direct.momentum += p.mass[i] * p.velocity[i];
    direct.moment += p.mass[i] * p.position[i];
  }
  expectReadingMatches(sensor.latest(), direct);
}

TEST(RegionSensor, EmptyRegionReportsNaNCentre) {
  World world(test::sensorSettings());
  world.addMaterial(test::testMaterial(0.5));
  test::addSphere(world, Vec3::Zero(), 0.003);
  RegionPlacement placement;
  placement.centre = Vec3(1.0, 0.0, 0.0);
  auto& sensor = static_cast<RegionSensor&>(world.addComponent(std::make_unique<RegionSensor>(
      "far", VolumeShape::sphere(0.1, "far"), placement, SampleSchedule{.interval = 1e-4}, "sensor")));
  world.initialize();
  EXPECT_EQ(sensor.sampleEvery(), 10u) << "1e-4 s at dt = 1e-5 s";
  EXPECT_EQ(sensor.latest().count, 0u);
  EXPECT_EQ(sensor.latest().mass, 0.0);
  EXPECT_TRUE(std::isnan(sensor.latest().centre_of_mass.x()));
}

/// The checkpoint of an empty region holds no NaN (the writer refuses one): its missing
/// values travel as flags, and the restored sensor has them missing again, in its reading
/// and in its latest row, while a sensor holding the sphere restores its numbers exactly.
TEST(RegionSensor, EmptyRegionCheckpointHoldsNoNaNAndRestoresTheMissingValues) {
  auto build = [] {
    auto world = std::make_unique<World>(test::sensorSettings());
    world->addMaterial(test::testMaterial(0.5));
    test::addSphere(*world, Vec3::Zero(), 0.003, Vec3(0.1, 0.0, 0.0));
    RegionPlacement far;
    far.centre = Vec3(1.0, 0.0, 0.0);
    world->addComponent(std::make_unique<RegionSensor>("far", VolumeShape::sphere(0.1, "far"), far,
                                                       SampleSchedule{.every_steps = 10}, "far"));
    world->addComponent(std::make_unique<RegionSensor>("near", VolumeShape::sphere(0.1, "near"), RegionPlacement{},
                                                       SampleSchedule{.every_steps = 10}, "near"));
    world->initialize();
    return world;
  };
  const auto a = build();
  for (int n = 0; n < 25; ++n) a->step();
  const std::string bytes = test::saveToBytes(*a);  // throws on a NaN
  const auto b = build();
  b->restoreCheckpoint(std::string_view(bytes), "empty.bin");
  const auto& far = static_cast<const RegionSensor&>(*b->components()[0]);
  const auto& near = static_cast<const RegionSensor&>(*b->components()[1]);
  EXPECT_EQ(far.latest().count, 0u);
  EXPECT_TRUE(far.latest().mean_velocity.hasNaN() && far.latest().centre_of_mass.hasNaN());
  const std::vector<double>& row = far.latestRow();
  ASSERT_EQ(row.size(), 9u);
  EXPECT_EQ(row[1], 0.0) << "count";
  for (std::size_t k = 3; k < 9; ++k) EXPECT_TRUE(std::isnan(row[k])) << "column " << k << " stays missing";
  const auto& nearA = static_cast<const RegionSensor&>(*a->components()[1]);
  EXPECT_EQ(near.latest().mean_velocity, nearA.latest().mean_velocity);
  EXPECT_EQ(near.latestRow(), nearA.latestRow());
  EXPECT_EQ(test::saveToBytes(*b), bytes) << "a restored world saves the same bytes";
}

/// In its CSV file an empty region's mean velocity and centre of mass, which do not exist,
/// are empty cells, never "nan"; every row keeps the header's nine columns (the last six
/// empty), while a sensor holding the sphere writes all nine as numbers.
TEST(RegionSensor, EmptyRegionWritesEmptyCells) {
  World world(test::sensorSettings());
  world.addMaterial(test::testMaterial(0.5));
  test::addSphere(world, Vec3::Zero(), 0.003, Vec3(0.1, 0.0, 0.0));
  RegionPlacement far;
  far.centre = Vec3(1.0, 0.0, 0.0);
  RegionPlacement near;
  world.addComponent(std::make_unique<RegionSensor>("far", VolumeShape::sphere(0.1, "far"), far,
                                                    SampleSchedule{.every_steps = 10}, "far"));
  world.addComponent(std::make_unique<RegionSensor>("near", VolumeShape::sphere(0.1, "near"), near,
                                                    SampleSchedule{.every_steps = 10}, "near"));
  world.initialize();
  const std::filesystem::path dir =
      std::filesystem::temp_directory_path() / ("demlink_empty_region_" + std::to_string(::getpid()));
  std::filesystem::create_directories(dir);
  const std::vector<std::filesystem::path> files = writeSamplesToCsv(world.components(), dir);
  ASSERT_EQ(files.size(), 2u);
  for (int n = 0; n < 30; ++n) world.step();

  const auto farRows = test::readCsvRows(files[0]);
  ASSERT_EQ(farRows.size(), 1u + 4u) << "header, the initial sample and three more";
  ASSERT_EQ(farRows[0].size(), 9u);
  for (std::size_t r = 1; r < farRows.size(); ++r) {
    const std::vector<std::string>& cells = farRows[r];
    ASSERT_EQ(cells.size(), 9u) << "row " << r;
    EXPECT_EQ(cells[1], "0") << "count";
    EXPECT_EQ(cells[2], "0") << "mass";
    for (std::size_t k = 3; k < 9; ++k) EXPECT_EQ(cells[k], "") << farRows[0][k] << " of row " << r;
  }
  const auto nearRows = test::readCsvRows(files[1]);
  ASSERT_EQ(nearRows.size(), farRows.size());
  for (std::size_t r = 1; r < nearRows.size(); ++r) {
    ASSERT_EQ(nearRows[r].size(), 9u);
    EXPECT_EQ(nearRows[r][1], "1");
    EXPECT_EQ(std::strtod(nearRows[r][3].c_str(), nullptr), 0.1) << "mean_vx_m_s, exact";
    for (const std::string& cell : nearRows[r]) EXPECT_FALSE(cell.empty());
  }
  if (!::testing::Test::HasFailure()) std::filesystem::remove_all(dir);
}

/// Eight resting spheres on a circle of radius 0.2 m at 45 degree steps; a small sphere
/// sensor rides on a mesh spinning about z at 45 degrees per sample, 0.2 m from its axis.
TEST(RegionSensor, AttachedSensorFollowsARotatingMesh) {
  World world(test::sensorSettings());
  const auto mat = world.addMaterial(test::testMaterial(0.5));
  std::vector<Vec3> ring;
  for (int k = 0; k < 8; ++k) {
    const double angle = k * std::numbers::pi / 4;
    ring.emplace_back(0.2 * std::cos(angle), 0.2 * std::sin(angle), 0.0);
    test::addSphere(world, ring.back(), 0.003);
  }
  const TriangleMesh hub = rectangleMesh(Vec3::Zero(), 0.01, 0.01, 1, 1);
  MeshBody body("hub", hub.vertices, hub.triangles, mat);
  constexpr std::uint64_t kEvery = 200;
  const double omega = (std::numbers::pi / 4) / (kEvery * 1.0e-5);  // [rad/s]
  body.setVelocity(Vec3::Zero(), Vec3(0.0, 0.0, omega));
  world.addMesh(std::move(body));
  RegionPlacement placement;
  placement.centre = Vec3(0.2, 0.0, 0.0);  // body frame
  placement.attached_mesh = 0;
  auto& sensor = static_cast<RegionSensor&>(world.addComponent(std::make_unique<RegionSensor>(
      "bucket", VolumeShape::sphere(0.02, "bucket"), placement, SampleSchedule{.every_steps = kEvery}, "sensor")));
  world.initialize();
  for (int sample = 0; sample <= 8; ++sample) {
    if (sample > 0) {
      for (std::uint64_t n = 0; n < kEvery; ++n) world.step();
    }
    ASSERT_EQ(sensor.latest().count, 1u) << "sample " << sample;
    EXPECT_LT((sensor.latest().centre_of_mass - ring[static_cast<std::size_t>(sample % 8)]).norm(), 1e-9)
        << "sample " << sample;
  }
}

TEST(RegionSensor, MovingSensorSweepsALine) {
  World world(test::sensorSettings());
  world.addMaterial(test::testMaterial(0.5));
  for (int k = 0; k < 5; ++k) test::addSphere(world, Vec3(0.05 * k, 0.0, 0.0), 0.003);
  RegionPlacement placement;
  placement.velocity = Vec3(5.0, 0.0, 0.0);  // 0.05 m per 1000 steps
  auto& sensor = static_cast<RegionSensor&>(world.addComponent(std::make_unique<RegionSensor>(
      "sweep", VolumeShape::box(Vec3(0.01, 0.01, 0.01), "sweep"), placement, SampleSchedule{.every_steps = 1000},
      "sensor")));
  world.initialize();
  for (int k = 0; k < 5; ++k) {
    if (k > 0) {
      for (int n = 0; n < 1000; ++n) world.step();
    }
    ASSERT_EQ(sensor.latest().count, 1u) << "sample " << k;
    EXPECT_NEAR(sensor.latest().centre_of_mass.x(), 0.05 * k, 1e-12);
  }
}

TEST(RegionSensor, BadScheduleNamesTheField) {
  auto fieldOf = [](SampleSchedule schedule) -> std::string {
    try {
      World world(test::sensorSettings());
      world.addMaterial(test::testMaterial(0.5));
      world.addComponent(std::make_unique<RegionSensor>("s", VolumeShape::sphere(1.0, "s"), RegionPlacement{},
                                                        schedule, "components[4].region_sensor"));
      world.initialize();
    } catch (const InputError& e) {
      return e.field();
    }
    return "(no error)";
  };
  EXPECT_EQ(fieldOf({.interval = 0.0}), "components[4].region_sensor.sample_interval");
  EXPECT_EQ(fieldOf({.interval = -1.0}), "components[4].region_sensor.sample_interval");
  EXPECT_EQ(fieldOf({.interval = 1e-6}), "components[4].region_sensor.sample_interval") << "rounds to 0 steps";
  EXPECT_EQ(fieldOf({.interval = 1e-3}), "(no error)");
}

}  // namespace
}  // namespace demlink::core
