// Particle sinks and trackers.
//  - A sink removes exactly the spheres whose centre is in its region at the start of
//    the step, and its tally equals the mass the world lost (relative 1e-12).
//  - A moving sink sweeps a line; per-interval tallies add up to the total.
//  - Tracker CSV rows equal the particle and mesh state (exact: shortest round-trip
//    text), and a removed particle is reported as removed with empty (missing) cells.
//  - An infinite reading stops the run (SimulationFault) and is never written.
#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <limits>
#include <memory>
#include <set>
#include <unistd.h>

#include "demlink/core/base/input_error.hpp"
#include "demlink/core/components/particle_sink.hpp"
#include "demlink/core/components/particle_tracker.hpp"
#include "demlink/core/step/watchdog.hpp"
#include "csv_test_support.hpp"
#include "sensor_test_support.hpp"

namespace demlink::core {
namespace {

TEST(ParticleSink, RemovesExactlyTheSpheresInsideAndBalancesMass) {
  World world(test::sensorSettings());
  world.addMaterial(test::testMaterial(0.5));
  test::SplitMix rng(11);
  for (int k = 0; k < 400; ++k) {
    const Vec3 cell(k % 10, (k / 10) % 10, k / 100);
    test::addSphere(world, 0.02 * cell + rng.vector(-0.004, 0.004), rng.uniform(0.002, 0.005),
                    rng.vector(-0.5, 0.5));
  }
  RegionPlacement placement;
  placement.centre = Vec3(0.09, 0.1, 0.03);
  const double radius = 0.05;
  auto& sink = static_cast<ParticleSink&>(world.addComponent(std::make_unique<ParticleSink>(
      "drain", VolumeShape::sphere(radius, "drain"), placement, SampleSchedule{.every_steps = 1}, "sink")));
  world.initialize();
  std::set<std::uint64_t> expected;
  double expectedMass = 0.0;
  const ParticleArrays& p = world.particles();
  for (std::size_t i = 0; i < p.size(); ++i) {
    if ((p.position[i] - placement.centre).norm() <= radius) {
      expected.insert(p.id[i]);
      expectedMass += p.mass[i];
    }
  }
  ASSERT_GT(expected.size(), 20u);
  const double massBefore = world.totalMass();
  const std::size_t countBefore = p.size();
  world.step();
  std::set<std::uint64_t> remaining(p.id.begin(), p.id.end());
  for (std::uint64_t id : expected) EXPECT_EQ(remaining.count(id), 0u) << "id " << id << " should be removed";
  EXPECT_EQ(p.size(), countBefore - expected.size());
  EXPECT_EQ(sink.total().count, expected.size());
  EXPECT_NEAR(sink.total().mass, expectedMass, 1e-12 * expectedMass);
  EXPECT_NEAR(massBefore - world.totalMass(), sink.total().mass, 1e-12 * massBefore);
  EXPECT_EQ(sink.lastInterval().count, expected.size());
  EXPECT_EQ(sink.latestRow()[3], static_cast<double>(expected.size()));
}

TEST(ParticleSink, MovingBoxSweepsALineAndIntervalsAddUp) {
  World world(test::sensorSettings());
  world.addMaterial(test::testMaterial(0.5));
  for (int k = 0; k < 10; ++k) test::addSphere(world, Vec3(0.01 + 0.02 * k, 0.0, 0.0), 0.002 + 0.0002 * k);
  RegionPlacement placement;
  placement.velocity = Vec3(10.0, 0.0, 0.0);  // 0.2 m in 2000 steps
  auto& sink = static_cast<ParticleSink&>(world.addComponent(std::make_unique<ParticleSink>(
      "broom", VolumeShape::box(Vec3(0.005, 0.01, 0.01), "broom"), placement, SampleSchedule{.every_steps = 300},
      "sink")));
  world.initialize();
  const double massBefore = world.totalMass();
  std::uint64_t intervalSum = 0;
  double intervalMass = 0.0;
  for (int n = 1; n <= 2400; ++n) {
    world.step();
    if (n % 300 == 0) {
      intervalSum += sink.lastInterval().count;
      intervalMass += sink.lastInterval().mass;
    }
  }
  EXPECT_EQ(world.particles().size(), 0u);
  EXPECT_EQ(sink.total().count, 10u);
  EXPECT_EQ(intervalSum, 10u);
  EXPECT_NEAR(sink.total().mass, massBefore, 1e-12 * massBefore);
  EXPECT_NEAR(intervalMass, massBefore, 1e-12 * massBefore);
}

TEST(ParticleTracker, CsvRowsMatchTheStateAndRemovalIsNoted) {
  World world(test::sensorSettings(Vec3(0.0, 0.0, -9.81)));
  const auto mat = world.addMaterial(test::testMaterial(0.5));
  world.addPlane({"floor", Vec3::Zero(), Vec3::UnitZ(), mat});
  const std::uint64_t a = test::addSphere(world, Vec3(0.0, 0.0, 0.0021), 0.002, Vec3(0.3, 0.0, -0.1));
  const std::uint64_t b = test::addSphere(world, Vec3(0.05, 0.0, 0.01), 0.003, Vec3(0.0, 0.2, 0.0));
  const TriangleMesh plate = rectangleMesh(Vec3::Zero(), 0.01, 0.01, 1, 1);
  MeshBody body("paddle", plate.vertices, plate.triangles, mat);
  body.setPose(Vec3(0.5, 0.5, 0.5), Quat::Identity());
  body.setVelocity(Vec3(0.1, 0.0, 0.0), Vec3(0.0, 0.0, 2.0));
  world.addMesh(std::move(body));
  const std::uint64_t notYet = 99;
  auto& tracker = static_cast<ParticleTracker&>(world.addComponent(std::make_unique<ParticleTracker>(
      "track", std::vector<std::uint64_t>{a, b, notYet}, std::vector<std::size_t>{0},
      SampleSchedule{.every_steps = 25}, "tracker")));
  world.initialize();
  const std::filesystem::path dir =
      std::filesystem::temp_directory_path() / ("demlink_tracker_" + std::to_string(::getpid()));
  std::filesystem::create_directories(dir);
  const std::vector<std::filesystem::path> files = writeSamplesToCsv(world.components(), dir);
  ASSERT_EQ(files.size(), 1u);
  EXPECT_EQ(files[0].filename(), "tracker_track.csv");

  std::vector<std::vector<double>> expected;  // per sample: time, then a's and b's state
  auto record = [&] {
    std::vector<double> row{world.time()};
    for (std::uint64_t id : {a, b}) {
      const std::size_t i = test::slotOf(world, id);
      if (i == world.particles().size()) {
        row.push_back(-1.0);
        continue;
      }
      row.push_back(1.0);
      const ParticleArrays& p = world.particles();
      for (const Vec3* v : {&p.position[i], &p.velocity[i], &p.angular_velocity[i], &p.force[i]}) {
        row.insert(row.end(), {v->x(), v->y(), v->z()});
      }
    }
    const MeshBody& m = world.meshes()[0];
    row.insert(row.end(), {m.position().x(), m.orientation().w(), m.orientation().z(), m.torque().z()});
    expected.push_back(row);
  };
  record();
  for (int n = 1; n <= 100; ++n) {
    world.step();
    if (n == 60) {
      RemovalTally tally;
      const std::size_t slot = test::slotOf(world, b);
      world.removeParticlesIf([&](std::size_t i) { return i == slot; }, tally);
    }
    if (n % 25 == 0) record();
  }
  ASSERT_EQ(tracker.particles().size(), 3u);
  EXPECT_EQ(tracker.particles()[1].status, TrackedParticle::Status::Removed);
  EXPECT_EQ(tracker.particles()[2].status, TrackedParticle::Status::NotYetPresent);

  const auto rows = test::readCsvRows(files[0]);
  ASSERT_EQ(rows.size(), 1 + expected.size());
  const std::vector<std::string>& header = rows[0];
  ASSERT_EQ(header.size(), 1u + 3u * 13u + 19u);
  EXPECT_EQ(header[1], "p1_status");
  EXPECT_EQ(header[2], "p1_x_m");
  EXPECT_EQ(header[40], "paddle_x_m");
  for (std::size_t r = 0; r < expected.size(); ++r) {
    const std::vector<std::string>& cells = rows[r + 1];
    ASSERT_EQ(cells.size(), header.size()) << "row " << r;
    const std::vector<double>& want = expected[r];
    EXPECT_EQ(std::strtod(cells[0].c_str(), nullptr), want[0]);
    // Particle a: status + 12 values, exact.
    for (std::size_t k = 0; k < 13; ++k) EXPECT_EQ(std::strtod(cells[1 + k].c_str(), nullptr), want[1 + k]);
    // Particle b: present until removed at step 60.
    EXPECT_EQ(std::strtod(cells[14].c_str(), nullptr), want[14]) << "row " << r;
    if (want[14] > 0.0) {
      for (std::size_t k = 1; k < 13; ++k) EXPECT_EQ(std::strtod(cells[14 + k].c_str(), nullptr), want[14 + k]);
    } else {
      EXPECT_EQ(cells[15], "") << "a removed particle has no position: an empty cell";
    }
    // Not-yet-present id 99: status 0, values missing (empty cells).
    EXPECT_EQ(cells[27], "0");
    EXPECT_EQ(cells[28], "");
    EXPECT_EQ(cells[39], "");
    // Mesh: x, qw, qz and tz.
    const std::size_t meshCol = 40;
    const std::size_t wantMesh = want.size() - 4;
    EXPECT_EQ(std::strtod(cells[meshCol].c_str(), nullptr), want[wantMesh]);
    EXPECT_EQ(std::strtod(cells[meshCol + 3].c_str(), nullptr), want[wantMesh + 1]);
    EXPECT_EQ(std::strtod(cells[meshCol + 6].c_str(), nullptr), want[wantMesh + 2]);
    EXPECT_EQ(std::strtod(cells[meshCol + 18].c_str(), nullptr), want[wantMesh + 3]);
  }
  EXPECT_GT(std::strtod(rows.back()[40].c_str(), nullptr), 0.5) << "the mesh moved along +x";
  if (!::testing::Test::HasFailure()) std::filesystem::remove_all(dir);
}

/// An infinite reading can only come from a state that is no longer finite: the sample is
/// refused as the watchdog would stop the run (SimulationFault "non_finite_output" naming
/// the column), before anything is recorded or written.
TEST(ParticleTracker, InfiniteValueStopsTheRunAndIsNeverWritten) {
  World world(test::sensorSettings());
  world.addMaterial(test::testMaterial(0.5));
  const std::uint64_t id = test::addSphere(world, Vec3::Zero(), 0.002);
  auto& tracker = static_cast<ParticleTracker&>(world.addComponent(std::make_unique<ParticleTracker>(
      "spin", std::vector<std::uint64_t>{id}, std::vector<std::size_t>{}, SampleSchedule{.every_steps = 5},
      "tracker")));
  world.initialize();
  const std::filesystem::path dir =
      std::filesystem::temp_directory_path() / ("demlink_tracker_inf_" + std::to_string(::getpid()));
  std::filesystem::create_directories(dir);
  const std::vector<std::filesystem::path> files = writeSamplesToCsv(world.components(), dir);
  world.step();
  world.particles().angular_velocity[test::slotOf(world, id)].x() = std::numeric_limits<double>::infinity();
  try {
    for (int n = 0; n < 4; ++n) world.step();
    ADD_FAILURE() << "a sample with an infinite spin was taken";
  } catch (const SimulationFault& fault) {
    EXPECT_EQ(fault.check(), "non_finite_output");
    EXPECT_NE(std::string(fault.what()).find("p1_wx_rad_s is +inf"), std::string::npos) << fault.what();
  }
  EXPECT_EQ(tracker.sampleCount(), 1u) << "only the initial sample";
  const auto rows = test::readCsvRows(files.at(0));
  ASSERT_EQ(rows.size(), 2u) << "header and the initial sample";
  for (const std::string& cell : rows[1]) EXPECT_FALSE(test::spellsNonFinite(cell)) << cell;
  if (!::testing::Test::HasFailure()) std::filesystem::remove_all(dir);
}

TEST(ParticleTracker, BadInputNamesTheField) {
  auto fieldOf = [](std::vector<std::uint64_t> ids, std::vector<std::size_t> meshes) -> std::string {
    try {
      World world(test::sensorSettings());
      world.addMaterial(test::testMaterial(0.5));
      world.addComponent(std::make_unique<ParticleTracker>("t", std::move(ids), std::move(meshes),
                                                           SampleSchedule{.every_steps = 1}, "components[2].tracker"));
      world.initialize();
    } catch (const InputError& e) {
      return e.field();
    }
    return "(no error)";
  };
  EXPECT_EQ(fieldOf({}, {}), "components[2].tracker.particle_ids");
  EXPECT_EQ(fieldOf({3, 0}, {}), "components[2].tracker.particle_ids[1]");
  EXPECT_EQ(fieldOf({3, 4, 3}, {}), "components[2].tracker.particle_ids[2]");
  EXPECT_EQ(fieldOf({1}, {0}), "components[2].tracker.mesh_bodies[0]") << "the world has no mesh";
  EXPECT_EQ(fieldOf({1}, {}), "(no error)") << "an id not (yet) present is allowed";
}

TEST(ParticleSink, AttachmentToAMissingMeshNamesTheField) {
  World world(test::sensorSettings());
  world.addMaterial(test::testMaterial(0.5));
  RegionPlacement placement;
  placement.attached_mesh = 0;
  world.addComponent(std::make_unique<ParticleSink>("s", VolumeShape::sphere(0.1, "s"), placement,
                                                    SampleSchedule{.every_steps = 1}, "components[7].particle_sink"));
  try {
    world.initialize();
    ADD_FAILURE() << "expected an InputError";
  } catch (const InputError& e) {
    EXPECT_EQ(e.field(), "components[7].particle_sink.region.attached_to");
  }
}

}  // namespace
}  // namespace demlink::core
