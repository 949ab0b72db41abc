// Determinism: the same scene gives bit-identical states run after run, and for
// any thread count: work is cut into chunks that depend on the scene only, and the
// pair loop's per-chunk forces are summed in chunk order (PairLoopPartition).
#include <cstring>
#include <random>

#include <gtest/gtest.h>

#include "component_scene.hpp"
#include "test_scenes.hpp"

namespace demlink::core {
namespace {

/// FNV-1a over the bytes of positions, velocities and angular velocities, in id order.
std::uint64_t stateHash(const ParticleArrays& p) {
  std::vector<std::size_t> order(p.size());
  for (std::size_t i = 0; i < p.size(); ++i) order[i] = i;
  std::sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) { return p.id[a] < p.id[b]; });
  std::uint64_t h = 1469598103934665603ull;
  auto mix = [&](const Vec3& v) {
    unsigned char bytes[sizeof(double) * 3];
    std::memcpy(bytes, v.data(), sizeof bytes);
    for (unsigned char b : bytes) h = (h ^ b) * 1099511628211ull;
  };
  for (std::size_t i : order) {
    mix(p.position[i]);
    mix(p.velocity[i]);
    mix(p.angular_velocity[i]);
  }
  return h;
}

World pouringBed(std::uint32_t threads) {
  SimulationSettings s;
  s.time_step = 1e-5;
  s.restitution_tolerance = 0.2;  // a step chosen before the restitution limit; determinism is the point
  s.threads = threads;
  World world(s);
  const auto mat = world.addMaterial(test::testMaterial(0.5, 0.5, 0.05));
  world.addPlane({"floor", Vec3::Zero(), Vec3::UnitZ(), mat});
  world.addPlane({"x0", Vec3::Zero(), Vec3::UnitX(), mat});
  world.addPlane({"x1", Vec3::Constant(0.03), -Vec3::UnitX(), mat});
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  // 8 x 10 x 10 loose lattice with jitter and random velocities: a pour.
  for (int i = 0; i < 800; ++i) {
    ParticleSpec p;
    p.radius = 0.001 + 0.0004 * u(rng);
    p.position = Vec3(0.0025 + 0.0035 * (i % 8), 0.0015 + 0.003 * ((i / 8) % 10), 0.002 + 0.0035 * (i / 80)) +
                 Vec3(u(rng), u(rng), u(rng)) * 0.0002;
    p.velocity = (Vec3(u(rng), u(rng), u(rng)) - Vec3::Constant(0.5)) * 0.5;
    world.addParticle(p);
  }
  world.initialize();
  for (int n = 0; n < 4000; ++n) world.step();
  return world;
}

TEST(Determinism, IdenticalForFixedThreadCount) {
  for (std::uint32_t threads : {1u, 2u}) {
    const World a = pouringBed(threads);
    const World b = pouringBed(threads);
    EXPECT_EQ(stateHash(a.particles()), stateHash(b.particles())) << threads << " threads";
  }
}

TEST(Determinism, BitIdenticalForAnyThreadCount) {
  const World one = pouringBed(1);
  // The pair loop must really be cut, or the test would prove nothing.
  ASSERT_GE(one.pairLoopPartition().chunks(), 3u);
  const std::uint64_t reference = stateHash(one.particles());
  for (std::uint32_t threads = 2; threads <= std::min(3u, maxThreads()); ++threads) {
    EXPECT_EQ(stateHash(pouringBed(threads).particles()), reference) << threads << " threads";
  }
}

/// FNV-1a over the bytes of every particle column, in slot order.
std::uint64_t columnsHash(const ParticleArrays& p) {
  std::uint64_t h = 1469598103934665603ull;
  p.forEachColumn([&](const char*, const auto& column) {
    const auto* bytes = reinterpret_cast<const unsigned char*>(column.data());
    for (std::size_t k = 0; k < column.size() * sizeof(column[0]); ++k) h = (h ^ bytes[k]) * 1099511628211ull;
  });
  return h;
}

TEST(Determinism, SeededSourceWithSinkAndSensorsIsBitIdentical) {
  // Insertion, sink and bounds removals (slot compaction) and sensors.
  std::vector<std::uint64_t> hashes;
  std::vector<std::uint64_t> crossings;
  for (int run = 0; run < 2; ++run) {
    test::ComponentScene scene = test::buildComponentScene(7);
    for (int n = 0; n < 1500; ++n) scene.world->step();
    ASSERT_GT(scene.source->report().inserted_count, 100u);
    ASSERT_GT(scene.sink->total().count, 0u);
    hashes.push_back(columnsHash(scene.world->particles()));
    crossings.push_back(scene.flow->total().negative_count);
  }
  EXPECT_EQ(hashes[0], hashes[1]);
  EXPECT_EQ(crossings[0], crossings[1]);
  // Another seed gives another state: the hash depends on the source's draws.
  test::ComponentScene other = test::buildComponentScene(8);
  for (int n = 0; n < 1500; ++n) other.world->step();
  EXPECT_NE(columnsHash(other.world->particles()), hashes[0]);
}

}  // namespace
}  // namespace demlink::core
