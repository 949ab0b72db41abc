// Contact output (World::setContactOutput, contact_record.hpp): a resting column's
// wall contacts carry its weight to 0.5 %; every particle's recorded contact forces
// add up to its contact force; the loads on a mesh floor's triangles add up to the
// mesh wrench and their impulse to weight x time; snapshots land on their steps;
// the recording pass runs only when asked for, and recording does not change the
// trajectory.
#include <gtest/gtest.h>

#include <map>

#include "demlink/core/output/vtk_writer.hpp"
#include "test_scenes.hpp"

namespace demlink::core {
namespace {

constexpr double kRadius = 0.002;  // [m]
constexpr double kDt = 1.0e-5;     // [s]
constexpr int kColumn = 5;         // spheres in the column

SimulationSettings restingSettings() {
  SimulationSettings settings = test::fineSettings(kDt, 0.5);
  settings.gravity = Vec3(0.0, 0.0, -9.81);
  return settings;
}

/// A column of kColumn spheres, centred on x = y = 0, resting on z = 0 (plane or mesh added by the caller).
void addColumn(World& world, std::uint32_t material) {
  for (int k = 0; k < kColumn; ++k) {
    ParticleSpec s;
    s.radius = kRadius;
    s.material = material;
    s.position = Vec3(0.0, 0.0, kRadius + 2.0 * kRadius * k);
    world.addParticle(s);
  }
}

double columnWeight(const World& world) { return world.totalMass() * 9.81; }

TEST(ContactOutput, RestingColumnsWallContactsCarryItsWeight) {
  World world(restingSettings());
  const auto material = world.addMaterial(test::testMaterial(0.3, 0.5));
  world.addPlane({"floor", Vec3::Zero(), Vec3::UnitZ(), material});
  addColumn(world, material);
  world.setContactOutput({1000, false});
  world.initialize();
  for (int n = 0; n < 30'000; ++n) world.step();  // 0.3 s: settled
  const ContactSnapshot& snapshot = world.contactSnapshot();
  ASSERT_TRUE(snapshot.valid);
  EXPECT_EQ(snapshot.step, world.stepCount());
  double wallNormal = 0.0;
  std::size_t pairs = 0;
  for (const ContactRecord& c : snapshot.contacts) {
    if (c.kind == ContactKind::kPlane) wallNormal += c.normal_force.dot(c.normal);
    if (c.kind == ContactKind::kParticle) ++pairs;
  }
  EXPECT_EQ(pairs, static_cast<std::size_t>(kColumn - 1));
  EXPECT_NEAR(wallNormal / columnWeight(world), 1.0, 0.005);
}

TEST(ContactOutput, RecordedForcesAddUpToEachParticlesContactForce) {
  World world(restingSettings());
  const auto grains = test::addBoxedLattice(world);
  world.addPlane({"floor", Vec3::Zero(), Vec3::UnitZ(), grains});
  world.setContactOutput({500, false});
  world.initialize();
  for (int n = 0; n < 6'000; ++n) world.step();  // grains falling and colliding
  const ContactSnapshot& snapshot = world.contactSnapshot();
  ASSERT_EQ(snapshot.step, 6'000u);
  std::map<std::uint64_t, Vec3> sum;
  double largest = 0.0;  // [N] the largest contact force
  for (const ContactRecord& c : snapshot.contacts) {
    const Vec3 f = c.normal_force + c.tangential_force;
    largest = std::max(largest, f.norm());
    sum.try_emplace(c.particle, Vec3::Zero()).first->second += f;
    // The partner feels the reaction.
    if (c.kind == ContactKind::kParticle) sum.try_emplace(c.other, Vec3::Zero()).first->second -= f;
  }
  const ParticleArrays& p = world.particles();
  ASSERT_GT(snapshot.contacts.size(), 100u);
  for (std::size_t i = 0; i < p.size(); ++i) {
    const auto it = sum.find(p.id[i]);
    const Vec3 recorded = it != sum.end() ? it->second : Vec3::Zero();
    EXPECT_LT((recorded - p.force[i]).norm(), 1.0e-13 * largest)
        << "particle " << p.id[i] << " force " << p.force[i].transpose() << " recorded " << recorded.transpose();
  }
}

TEST(ContactOutput, TriangleLoadsAddUpToTheMeshWrenchAndTheirImpulseToWeightTimesTime) {
  World world(restingSettings());
  const auto material = world.addMaterial(test::testMaterial(0.3, 0.5));
  // 4 x 4 cells, 32 triangles; the column stands on an inner vertex shared by six triangles.
  const TriangleMesh floor = rectangleMesh(Vec3::Zero(), 0.01, 0.01, 4, 4);
  world.addMesh(MeshBody("floor", floor.vertices, floor.triangles, material));
  addColumn(world, material);
  world.setContactOutput({0, true});
  world.initialize();
  constexpr int kSteps = 30'000;
  for (int n = 0; n < kSteps; ++n) world.step();
  const std::span<const TriangleLoad> loads = world.meshLoads(0);
  ASSERT_EQ(loads.size(), floor.triangles.size());
  Vec3 force = Vec3::Zero();
  double normal = 0.0, impulse = 0.0;
  for (const TriangleLoad& load : loads) {
    force += load.force;
    normal += load.normal_force;
    impulse += load.normal_impulse;
  }
  const Vec3 wrench = world.meshes()[0].force();
  EXPECT_LT((force - wrench).norm(), 1.0e-12 * wrench.norm());
  EXPECT_NEAR(-force.z() / columnWeight(world), 1.0, 0.005);
  EXPECT_NEAR(normal / columnWeight(world), 1.0, 0.005);
  // The floor carried the weight for the whole run after a short fall of ~0 m: the
  // momentum balance says impulse = weight x time + the column's (zero) final momentum.
  EXPECT_NEAR(impulse / (columnWeight(world) * kSteps * kDt), 1.0, 0.01);
}

TEST(ContactOutput, WearWorkOfASphereThatSlidesUntilItRollsMatchesTheClosedForm) {
  // A sphere launched at v0 without spin slides until v = 5/7 v0 (slip speed
  // v0 - 3.5 mu g t): slip distance s = v0^2 / (7 mu g), so the Archard work
  // F_n s = m v0^2 / (7 mu) and the friction work mu F_n s = m v0^2 / 7 (the kinetic
  // energy the sliding loses).
  constexpr double kV0 = 0.1;  // [m/s]
  constexpr double kMu = 0.3;
  World world(restingSettings());
  const auto material = world.addMaterial(test::testMaterial(0.3, kMu));
  const TriangleMesh floor = rectangleMesh(Vec3::Zero(), 0.02, 0.02, 4, 4);
  world.addMesh(MeshBody("floor", floor.vertices, floor.triangles, material));
  ParticleSpec s;
  s.radius = kRadius;
  s.material = material;
  s.position = Vec3(-0.01, 0.001, kRadius);
  s.velocity = Vec3(kV0, 0.0, 0.0);
  world.addParticle(s);
  world.setContactOutput({0, true});
  world.initialize();
  for (int n = 0; n < 5'000; ++n) world.step();  // 50 ms; sliding ends after 9.7 ms
  double archard = 0.0, friction = 0.0;
  for (const TriangleLoad& load : world.meshLoads(0)) {
    archard += load.archard_work;
    friction += load.friction_work;
  }
  const double m = world.totalMass();
  EXPECT_NEAR(friction / (m * kV0 * kV0 / 7.0), 1.0, 0.03);
  EXPECT_NEAR(archard / (m * kV0 * kV0 / (7.0 * kMu)), 1.0, 0.03);
}

TEST(ContactOutput, SnapshotsLandOnTheirStepsAndRecordingLeavesTheTrajectory) {
  World quiet(restingSettings());
  World recorded(restingSettings());
  for (World* world : {&quiet, &recorded}) {
    const auto grains = test::addBoxedLattice(*world);
    world->addPlane({"floor", Vec3::Zero(), Vec3::UnitZ(), grains});
  }
  recorded.setContactOutput({300, true});
  quiet.initialize();
  recorded.initialize();
  ASSERT_EQ(recorded.contactSnapshot().step, 0u);
  for (int n = 1; n <= 1'000; ++n) {
    quiet.step();
    recorded.step();
    EXPECT_EQ(recorded.contactSnapshot().step, static_cast<std::uint64_t>(n / 300 * 300));
  }
  for (std::size_t i = 0; i < quiet.particles().size(); ++i) {
    ASSERT_EQ(quiet.particles().position[i], recorded.particles().position[i]) << i;
  }
}

TEST(ContactOutput, RecordingPassRunsOnlyWhenAsked) {
  World world(restingSettings());
  const auto material = world.addMaterial(test::testMaterial(0.3, 0.5));
  world.addPlane({"floor", Vec3::Zero(), Vec3::UnitZ(), material});
  addColumn(world, material);
  world.initialize();
  auto recording = [&] {
    const std::vector<std::string> stages = world.activeStages();
    return std::count(stages.begin(), stages.end(), "contact_recording");
  };
  EXPECT_EQ(recording(), 0);
  world.setContactOutput({10, false});
  EXPECT_EQ(recording(), 1);
  world.setContactOutput({});
  EXPECT_EQ(recording(), 0);
}

}  // namespace
}  // namespace demlink::core
