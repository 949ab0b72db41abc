// The run-time watchdog and the speeds the time step is validated for: a
// bounce at 10x the accepted step is stopped by name (or warned about once), a
// NaN stops the run, a declared impact speed below a particle's speed is
// replaced and reported, a speed beyond the validated one warns once or (strict)
// stops, inputs whose first step overflows are refused naming the field, and
// rigid walls take the particle's stiffness alone.
#include <algorithm>
#include <cmath>
#include <limits>
#include <random>
#include <string>
#include <thread>

#include <gtest/gtest.h>

#include "demlink/core/contact/contact_pair_table.hpp"
#include "demlink/core/base/input_error.hpp"
#include "test_scenes.hpp"

namespace demlink::core {
namespace {

constexpr double kRadius = 0.01;  // [m]

/// A sphere on a floor at `speed`, at `stepFactor` x the accepted limit.
World bounce(double speed, double stepFactor, double e, const WatchdogSettings& watchdog = {}) {
  SimulationSettings probe = test::fineSettings(1e-12, speed);
  World limit(probe);
  limit.addMaterial(test::testMaterial(e));
  test::addFloorAndSphere(limit, 0, kRadius, Vec3(0.0, 0.0, -speed), 1e-4);
  limit.initialize();
  SimulationSettings s = test::fineSettings(stepFactor * limit.timeStepReport().limit, speed);
  s.allow_unsafe_time_step = stepFactor > 1.0;
  s.watchdog = watchdog;
  s.watchdog.every_steps = 1;
  World world(s);
  world.addMaterial(test::testMaterial(e));
  test::addFloorAndSphere(world, 0, kRadius, Vec3(0.0, 0.0, -speed), 1e-4);
  world.initialize();
  return world;
}

std::string faultOf(World& world, int steps, std::string* message = nullptr) {
  try {
    for (int k = 0; k < steps; ++k) world.step();
  } catch (const SimulationFault& fault) {
    if (message != nullptr) *message = fault.what();
    return fault.check();
  }
  return "(none)";
}

/// A 14 x 14 x 14 lattice of touching spheres with jittered overlaps and random
/// velocities, on `threads` threads.
World overlappingLattice(std::uint32_t threads) {
  SimulationSettings s;
  s.threads = threads;
  s.time_step = 1e-6;
  World world(s);
  world.addMaterial(test::testMaterial(0.5));  // material 0, every sphere's
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  for (int i = 0; i < 14 * 14 * 14; ++i) {
    ParticleSpec p;
    p.radius = 0.001;
    p.position = Vec3(i % 14, (i / 14) % 14, i / 196) * 0.00198 + Vec3(u(rng), u(rng), u(rng)) * 1e-5;
    p.velocity = (Vec3(u(rng), u(rng), u(rng)) - Vec3::Constant(0.5)) * 0.2;
    world.addParticle(p);
  }
  world.initialize();
  return world;
}

TEST(Watchdog, ThreadedReadingNamesWhatASerialScanFindsFirst) {
  // The reading is gathered in chunks over the pool and combined in chunk order: ties go
  // to the first slot, as in one scan, and the energies match one thread's to round-off.
  const std::uint32_t threads = std::clamp(std::thread::hardware_concurrency(), 1u, 2u);
  World world = overlappingLattice(threads);
  ParticleArrays& p = world.particles();
  ASSERT_GT(p.size(), 2000u);
  // Two equal top speeds in different chunks: the earlier slot is the fastest.
  p.velocity[300] = p.velocity[2500] = Vec3(3.0, 0.0, 0.0);
  const WatchdogReading r = world.watch();
  EXPECT_EQ(r.fastest, "particle " + std::to_string(p.id[300]));
  EXPECT_DOUBLE_EQ(r.max_speed, 3.0);
  // The deepest contact by a scan of the list in row order (first of equals).
  const auto offsets = world.neighbourList().offsets();
  const auto partners = world.neighbourList().partners();
  double deepest = 0.0;
  std::string name;
  for (std::size_t i = 0; i + 1 < offsets.size(); ++i) {
    for (std::uint32_t k = offsets[i]; k < offsets[i + 1]; ++k) {
      const std::uint32_t j = partners[k];
      const double fraction =
          (p.radius[i] + p.radius[j] - (p.position[j] - p.position[i]).norm()) / std::min(p.radius[i], p.radius[j]);
      if (fraction > deepest) {
        deepest = fraction;
        name = "particles " + std::to_string(p.id[i]) + " and " + std::to_string(p.id[j]);
      }
    }
  }
  ASSERT_GT(deepest, 0.0);
  EXPECT_EQ(r.max_overlap_fraction, deepest);
  EXPECT_EQ(r.deepest, name);
  World one = overlappingLattice(1);
  one.particles().velocity = p.velocity;
  const WatchdogReading serial = one.watch();
  EXPECT_GT(r.elastic_energy, 0.0);
  EXPECT_NEAR(r.elastic_energy, serial.elastic_energy, 1e-12 * serial.elastic_energy);
  EXPECT_NEAR(r.total_energy, serial.total_energy, 1e-12 * std::abs(serial.total_energy));
  // Non-finite values in two chunks: the earlier slot is named.
  p.position[2600].x() = std::numeric_limits<double>::quiet_NaN();
  p.force[400].y() = std::numeric_limits<double>::infinity();
  EXPECT_EQ(world.watch().non_finite, "particle " + std::to_string(p.id[400]) + " (position, velocity, spin or force)");
}

TEST(Watchdog, StopsABounceAtTenTimesTheLimitByName) {
  // At 10x the limit an elastic bounce gains or loses energy depending on the
  // onset phase; with e = 1 any gain beyond 10 % of the energy in motion stops it.
  World world = bounce(1.0, 10.0, 1.0);
  const std::string check = faultOf(world, 20'000);
  EXPECT_TRUE(check == "energy" || check == "overlap" || check == "speed_bound") << check;
}

TEST(Watchdog, AcceptedStepRunsWithoutAFault) {
  World world = bounce(1.0, 0.99, 1.0);
  EXPECT_EQ(faultOf(world, 2'000), "(none)");
}

TEST(Watchdog, WarnPolicyWarnsOncePerCheck) {
  WatchdogSettings warn;
  warn.policy = GuardPolicy::Warn;
  World world = bounce(1.0, 10.0, 1.0, warn);
  EXPECT_EQ(faultOf(world, 20'000), "(none)");
  ASSERT_FALSE(world.warnings().empty());
  for (const std::string& w : world.warnings()) EXPECT_NE(w.find("watchdog"), std::string::npos) << w;
  const std::size_t before = world.warnings().size();
  (void)faultOf(world, 2'000);
  EXPECT_EQ(world.warnings().size(), before) << "each check warns once";
}

TEST(Watchdog, NonFiniteAlwaysStops) {
  WatchdogSettings warn;
  warn.policy = GuardPolicy::Warn;
  World world = bounce(1.0, 0.5, 0.5, warn);
  world.particles().velocity[0].x() = std::numeric_limits<double>::quiet_NaN();
  EXPECT_EQ(faultOf(world, 1), "non_finite");
}

TEST(Watchdog, OffRemovesTheStage) {
  SimulationSettings s = test::fineSettings(1e-6, 1.0);
  s.watchdog.every_steps = 0;
  World off(s);
  off.addMaterial(test::testMaterial(0.5));
  off.initialize();
  for (const std::string& stage : off.activeStages()) EXPECT_NE(stage, "watchdog");
  World on(test::fineSettings(1e-6, 1.0));
  on.addMaterial(test::testMaterial(0.5));
  on.initialize();
  EXPECT_EQ(on.activeStages().back(), "watchdog");
}

TEST(Speeds, DeclaredImpactSpeedBelowAParticlesIsReplacedAndReported) {
  // The user's check: 3.9 m/s with max_impact_velocity 0.01 was accepted silently.
  SimulationSettings s = test::fineSettings(1e-7, 0.01);
  World world(s);
  world.addMaterial(test::testMaterial(0.5));
  test::addFloorAndSphere(world, 0, kRadius, Vec3(0.0, 0.0, -3.9), 1e-3);
  world.initialize();
  EXPECT_DOUBLE_EQ(world.validatedImpactSpeed(), 3.9);
  ASSERT_EQ(world.warnings().size(), 1u);
  EXPECT_NE(world.warnings()[0].find("particle 1"), std::string::npos) << world.warnings()[0];
  EXPECT_NE(world.warnings()[0].find("max_impact_velocity"), std::string::npos) << world.warnings()[0];
  // The limit is the one for 3.9 m/s: t_c ~ v^(-1/5).
  World declared(test::fineSettings(1e-7, 3.9));
  declared.addMaterial(test::testMaterial(0.5));
  test::addFloorAndSphere(declared, 0, kRadius, Vec3(0.0, 0.0, -3.9), 1e-3);
  declared.initialize();
  EXPECT_DOUBLE_EQ(world.timeStepReport().limit, declared.timeStepReport().limit);
}

/// A triangle "paddle" at z = 0 moving at `velocity` with a declared speed limit, and
/// a sphere 0.5 m above it; initialised.
void addPaddleAndSphere(World& world, const Vec3& velocity, double speedLimit) {
  world.addMaterial(test::testMaterial(0.5));
  MeshBody mesh("paddle", {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0)}, {{0, 1, 2}}, 0);
  mesh.setVelocity(velocity, Vec3::Zero());
  mesh.setSpeedLimit(speedLimit);
  world.addMesh(std::move(mesh));
  ParticleSpec p;
  p.radius = kRadius;
  p.position = Vec3(0.2, 0.2, 0.5);
  world.addParticle(p);
  world.initialize();
}

TEST(Speeds, MeshMotionAndItsDeclaredLimitCount) {
  World world(test::fineSettings(1e-7, 0.5));
  addPaddleAndSphere(world, Vec3(2.0, 0.0, 0.0), 5.0);
  EXPECT_DOUBLE_EQ(world.validatedImpactSpeed(), 5.0);
  EXPECT_NE(world.seenSpeeds().front().what.find("mesh paddle"), std::string::npos);
}

TEST(Speeds, FasterThanValidatedWarnsOnceOrStopsWhenStrict) {
  for (const GuardPolicy policy : {GuardPolicy::Warn, GuardPolicy::Stop}) {
    SimulationSettings s = test::fineSettings(1e-5, 0.5);
    s.gravity = Vec3(0.0, 0.0, -9.81);
    s.watchdog.speed_policy = policy;
    World world(s);
    world.addMaterial(test::testMaterial(0.5));
    ParticleSpec p;
    p.radius = kRadius;
    world.addParticle(p);  // falls freely: 0.5 m/s after 0.051 s
    world.initialize();
    std::string message;
    const std::string check = faultOf(world, 10'000, &message);
    if (policy == GuardPolicy::Stop) {
      EXPECT_EQ(check, "speed");
      EXPECT_NE(message.find("particle 1 moves at"), std::string::npos) << message;
      EXPECT_TRUE(world.warnings().empty());
    } else {
      EXPECT_EQ(check, "(none)");
      ASSERT_EQ(world.warnings().size(), 1u);
      EXPECT_NE(world.warnings()[0].find("particle 1"), std::string::npos) << world.warnings()[0];
    }
  }
}

// A mesh driven at run time faster than the speed the step was validated for (its
// declared limit) is named: a warning once, or a stop under the strict policy.
TEST(Speeds, AMeshDrivenFasterThanValidatedIsNamed) {
  for (const GuardPolicy policy : {GuardPolicy::Warn, GuardPolicy::Stop}) {
    SimulationSettings s = test::fineSettings(1e-6, 1.0);
    s.watchdog.speed_policy = policy;
    s.watchdog.every_steps = 10;
    World world(s);
    addPaddleAndSphere(world, Vec3::Zero(), 1.0);
    ASSERT_DOUBLE_EQ(world.validatedImpactSpeed(), 1.0);
    EXPECT_EQ(faultOf(world, 20), "(none)");  // at rest
    world.mesh(0).setVelocity(Vec3(0.0, 0.0, 1.5), Vec3::Zero());
    std::string message;
    const std::string check = faultOf(world, 100, &message);
    if (policy == GuardPolicy::Stop) {
      EXPECT_EQ(check, "speed");
      EXPECT_NE(message.find("mesh paddle moves at 1.5 m/s"), std::string::npos) << message;
    } else {
      EXPECT_EQ(check, "(none)");
      ASSERT_EQ(world.warnings().size(), 1u);
      EXPECT_NE(world.warnings()[0].find("mesh paddle"), std::string::npos) << world.warnings()[0];
    }
  }
}

TEST(FirstStep, OverflowingInputsAreRefusedNamingTheField) {
  auto fieldOf = [](SimulationSettings s) {
    try {  // the settings' own bounds may refuse it already at construction
      World world(s);
      world.addMaterial(test::testMaterial(0.5));
      ParticleSpec p;
      p.radius = kRadius;
      p.position = Vec3(0.1, 0.0, 0.0);
      world.addParticle(p);
      world.initialize();
    } catch (const InputError& error) {
      return error.field();
    }
    return std::string("(accepted)");
  };
  SimulationSettings s = test::fineSettings(1e-5, 1.0);
  s.allow_unsafe_time_step = true;
  EXPECT_EQ(fieldOf(s), "(accepted)");
  SimulationSettings g = s;
  g.gravity = Vec3(0.0, 0.0, -1e308);
  EXPECT_EQ(fieldOf(g).rfind("settings.gravity", 0), 0u) << fieldOf(g);  // "settings.gravity[2]" from the bounds
  SimulationSettings spin = s;
  spin.frame.angular_velocity = Vec3(0.0, 0.0, 1e308);
  EXPECT_EQ(fieldOf(spin).rfind("settings.frame.angular_velocity", 0), 0u) << fieldOf(spin);
}

TEST(RigidWalls, TheParticleAloneSetsTheStiffness) {
  World world(test::fineSettings(1e-6, 1.0));
  Material grains = test::testMaterial(0.5);
  const auto g = world.addMaterial(grains);
  Material soft = test::testMaterial(0.5);
  soft.name = "soft";
  soft.youngs_modulus = 1e3;
  const auto w = world.addMaterial(soft);
  world.addPlane({"floor", Vec3::Zero(), Vec3::UnitZ(), w, true});
  ParticleSpec p;
  p.radius = kRadius;
  p.position = Vec3(0.0, 0.0, 0.5);
  world.addParticle(p);
  world.initialize();
  const std::uint32_t twin = world.planes()[0].spec.material;
  EXPECT_NE(twin, w);
  EXPECT_EQ(world.materials()[twin].name, "soft (rigid)");
  const ContactPairParams& pair = world.pairTable()(g, twin);
  const double nu = grains.poisson_ratio;
  EXPECT_DOUBLE_EQ(pair.effective_youngs, grains.youngs_modulus / (1.0 - nu * nu));
  EXPECT_DOUBLE_EQ(pair.effective_shear, grains.shearModulus() / (2.0 - nu));
}

}  // namespace
}  // namespace demlink::core
