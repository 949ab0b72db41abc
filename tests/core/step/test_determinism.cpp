// Determinism: the same scene gives bit-identical states run after run, and for
// any thread count, one included: work is cut into chunks that depend on the scene only,
// and each slot's pair forces are summed in an order the pair loop's plan fixes (PairLoopPartition).
#include <cstring>
#include <random>
#include <unordered_map>

#include <gtest/gtest.h>

#include "component_scene.hpp"
#include "test_scenes.hpp"
#include "demlink/core/walls/mesh_body.hpp"

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

/// The pour after `steps` steps, taken by World::advance in calls of `stepsPerCall` steps;
/// `layers` layers of 80 particles.
World pouringBed(std::uint32_t threads, int steps = 4000, bool portableKernel = false, int stepsPerCall = 1000,
                 int layers = 10, bool meshFloor = false) {
  SimulationSettings s;
  s.portable_kernel = portableKernel;
  s.watchdog.every_steps = 7;
  s.time_step = 1e-5;
  s.restitution_tolerance = 0.2;  // a step chosen before the restitution limit; determinism is the point
  s.threads = threads;
  World world(s);
  const auto mat = world.addMaterial(test::testMaterial(0.5, 0.5, 0.05));
  if (meshFloor) {
    // Triangles 3 mm wide, a few particles each.
    const TriangleMesh floor = rectangleMesh(Vec3(0.015, 0.015, 0.0), 0.03, 0.03, 20, 20);
    world.addMesh(MeshBody("floor", floor.vertices, floor.triangles, mat));
  } else {
    world.addPlane({"floor", Vec3::Zero(), Vec3::UnitZ(), mat});
  }
  world.addPlane({"x0", Vec3::Zero(), Vec3::UnitX(), mat});
  world.addPlane({"x1", Vec3::Constant(0.03), -Vec3::UnitX(), mat});
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  // 8 x 10 x 10 loose lattice with jitter and random velocities: a pour.
  for (int i = 0; i < 80 * layers; ++i) {
    ParticleSpec p;
    p.radius = 0.001 + 0.0004 * u(rng);
    p.position = Vec3(0.0025 + 0.0035 * (i % 8), 0.0015 + 0.003 * ((i / 8) % 10), 0.002 + 0.0035 * (i / 80)) +
                 Vec3(u(rng), u(rng), u(rng)) * 0.0002;
    p.velocity = (Vec3(u(rng), u(rng), u(rng)) - Vec3::Constant(0.5)) * 0.5;
    world.addParticle(p);
  }
  world.initialize();
  for (int done = 0; done < steps; done += stepsPerCall) {
    world.advance(static_cast<std::uint64_t>(std::min(stepsPerCall, steps - done)));
  }
  return world;
}

/// The largest distance between a particle's positions in two worlds of the same ids [m].
double largestPositionDifference(const ParticleArrays& a, const ParticleArrays& b) {
  std::unordered_map<std::uint64_t, std::size_t> slotOf;
  for (std::size_t i = 0; i < b.size(); ++i) slotOf[b.id[i]] = i;
  double worst = 0.0;
  for (std::size_t i = 0; i < a.size(); ++i) {
    worst = std::max(worst, (a.position[i] - b.position[slotOf.at(a.id[i])]).norm());
  }
  return worst;
}

TEST(Determinism, IdenticalForFixedThreadCount) {
  for (std::uint32_t threads : {1u, 2u}) {
    const World a = pouringBed(threads);
    const World b = pouringBed(threads);
    EXPECT_EQ(stateHash(a.particles()), stateHash(b.particles())) << threads << " threads";
  }
}

TEST(Determinism, SameBitsForAnyThreadCount) {
  // One pair-loop plan for every thread count (one thread runs its chunks in the
  // threads' order): the pour ends in the same bits on 1, 2 and 3 threads. It fails when
  // one thread sums in row order (one chunk over all rows, as before 2026-11-29).
  ASSERT_GE(maxThreads(), 2u);
  const World one = pouringBed(1, 4000);
  const World two = pouringBed(2, 4000);
  const World three = pouringBed(std::min(3u, maxThreads()), 4000);
  ASSERT_GE(one.pairLoopPartition().chunks(), 3u);  // cut, or the comparison would prove nothing
  EXPECT_EQ(one.pairLoopPartition().chunks(), two.pairLoopPartition().chunks());
  EXPECT_EQ(stateHash(one.particles()), stateHash(two.particles()));
  EXPECT_EQ(stateHash(two.particles()), stateHash(three.particles()));
}

TEST(Determinism, PlaneLoadsDoNotDependOnTheThreadCount) {
  // 3,200 particles: each pair chunk adds its own rows' plane contacts, every plane in
  // order (particles in the corners touch two). Particle forces are the same sums on any
  // thread count; the walls' loads are sums of the chunks' loads in chunk order, whoever
  // ran the chunks.
  ASSERT_GE(maxThreads(), 2u);
  const World one = pouringBed(1, 1500, false, 500, 40);
  const World two = pouringBed(2, 1500, false, 500, 40);
  const World three = pouringBed(std::min(3u, maxThreads()), 1500, false, 500, 40);
  ASSERT_EQ(two.planes().size(), 3u);
  EXPECT_EQ(stateHash(one.particles()), stateHash(two.particles()));
  EXPECT_EQ(stateHash(two.particles()), stateHash(three.particles()));
  double largestLoad = 0.0;
  for (std::size_t w = 0; w < two.planes().size(); ++w) {
    const PlaneWall& b = two.planes()[w];
    for (const World* other : {&one, &three}) {
      EXPECT_EQ(b.force, other->planes()[w].force) << b.spec.name;
      EXPECT_EQ(b.torque, other->planes()[w].torque) << b.spec.name;
    }
    largestLoad = std::max(largestLoad, b.force.norm());
    EXPECT_GT(b.near_slots.size(), 0u) << b.spec.name;
  }
  EXPECT_GT(largestLoad, 0.0);  // the bed is on the floor
}

TEST(Determinism, PairKernelsAgreeToRoundOff) {
  // The AVX2/FMA build of the pair loop rounds each fused multiply-add once: the same
  // pour as the portable build to round-off (4e-12 m after 4,000 steps of collisions,
  // a radius being 1e-3 m), and not the same bits (it really ran).
  const World portable = pouringBed(1, 4000, true);
  EXPECT_EQ(portable.pairKernel(), PairKernel::kPortable);
  const World chosen = pouringBed(1, 4000, false);
  if (chosen.pairKernel() == PairKernel::kPortable) {
    GTEST_SKIP() << "this processor lacks AVX2 or FMA: only the portable pair loop can run";
  }
  const ParticleArrays& a = portable.particles();
  const ParticleArrays& b = chosen.particles();
  ASSERT_EQ(a.size(), b.size());
  const double worst = largestPositionDifference(a, b);
  EXPECT_LT(worst, 1e-10) << worst;
  EXPECT_NE(stateHash(a), stateHash(b));
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

TEST(Determinism, OwedHalfKicksLeaveTheStepByStepState) {
  // advance() owes a step's second half kick to the next step's first kick; afterwards
  // every column (velocities, forces and springs included) holds the bits of step() x N.
  // The watchdog inspects every 7th step: those steps pay their kick as usual.
  const World stepped = pouringBed(1, 2000, false, 1);
  EXPECT_EQ(stepped.fusedKicks(), 0u);
  const World advanced = pouringBed(1, 2000, false, 500);
  ASSERT_TRUE(advanced.kickDeferrable());
  // Per call of 500 steps: not the last step, nor one whose end the watchdog inspects.
  std::uint64_t owed = 0;
  for (std::uint64_t step = 0; step < 2000; ++step) owed += (step % 500 != 499) && ((step + 1) % 7 != 0);
  EXPECT_EQ(advanced.fusedKicks(), owed);
  EXPECT_EQ(columnsHash(advanced.particles()), columnsHash(stepped.particles()));
  if (maxThreads() >= 2) {
    EXPECT_EQ(columnsHash(pouringBed(2, 2000, false, 500).particles()),
              columnsHash(pouringBed(2, 2000, false, 1).particles()));
  }
}

TEST(Determinism, MeshFloorSameBitsForAnyThreadCount) {
  // The mesh contacts run in the pair chunks and the floor gets the chunks' loads in chunk
  // order, whichever thread ran them: the same particle and wrench bits on 1 and 2 threads.
  const World one = pouringBed(1, 2000, false, 500, 10, true);
  ASSERT_LT(one.meshes()[0].force().z(), 0.0);  // the bed presses on the floor
  if (maxThreads() < 2) GTEST_SKIP() << "one hardware thread";
  const World two = pouringBed(2, 2000, false, 500, 10, true);
  EXPECT_EQ(columnsHash(two.particles()), columnsHash(one.particles()));
  EXPECT_TRUE(two.meshes()[0].force() == one.meshes()[0].force());
  EXPECT_TRUE(two.meshes()[0].torque() == one.meshes()[0].torque());
}

TEST(Determinism, ScenesWithComponentsPayEveryHalfKick) {
  // A sensor reads velocities after the second half kick: nothing may be owed.
  test::ComponentScene scene = test::buildComponentScene(7);
  EXPECT_FALSE(scene.world->kickDeferrable());
  scene.world->advance(200);
  EXPECT_EQ(scene.world->fusedKicks(), 0u);
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
