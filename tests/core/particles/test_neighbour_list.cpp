// The Verlet list must find exactly the brute-force contact set, on sparse and
// dense random configurations, at every step (before and after rebuilds, across
// cell sorts that reorder slots), and carry contact history across rebuilds.
#include <random>
#include <set>

#include <gtest/gtest.h>

#include "test_scenes.hpp"

namespace demlink::core {
namespace {

using IdPair = std::pair<std::uint64_t, std::uint64_t>;

std::set<IdPair> bruteForceContacts(const ParticleArrays& p) {
  std::set<IdPair> contacts;
  for (std::size_t i = 0; i < p.size(); ++i) {
    for (std::size_t j = i + 1; j < p.size(); ++j) {
      if ((p.position[j] - p.position[i]).norm() < p.radius[i] + p.radius[j]) {
        contacts.emplace(std::min(p.id[i], p.id[j]), std::max(p.id[i], p.id[j]));
      }
    }
  }
  return contacts;
}

/// The list's contact set, checking on the way that each pair is held once, by
/// its lower slot.
std::set<IdPair> checkedListContacts(const World& world) {
  const ParticleArrays& p = world.particles();
  const auto offsets = world.neighbourList().offsets();
  const auto partners = world.neighbourList().partners();
  std::set<std::pair<std::uint32_t, std::uint32_t>> slotPairs;
  for (std::size_t i = 0; i < p.size(); ++i) {
    for (std::uint32_t k = offsets[i]; k < offsets[i + 1]; ++k) {
      EXPECT_GT(partners[k], i) << "half list must hold each pair once, owned by the lower slot";
      EXPECT_TRUE(slotPairs.emplace(static_cast<std::uint32_t>(i), partners[k]).second) << "pair listed twice";
    }
  }
  return test::listedContacts(world);
}

/// Random polydisperse spheres in a cube of side `box` with random velocities.
World randomWorld(std::size_t n, double box, std::uint64_t seed, std::uint32_t threads = 1) {
  SimulationSettings s = test::fineSettings(2e-6, 3.0);
  s.watchdog.every_steps = 0;  // deliberately dense, deep overlaps: the list is what is tested
  s.sort_every_builds = 3;  // exercise reordering often
  s.threads = threads;
  World world(s);
  world.addMaterial(test::testMaterial(0.5, 0.3));
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  for (std::size_t i = 0; i < n; ++i) {
    ParticleSpec p;
    p.radius = 0.001 * (0.5 + u(rng));
    p.position = Vec3(u(rng), u(rng), u(rng)) * box;
    p.velocity = (Vec3(u(rng), u(rng), u(rng)) - Vec3::Constant(0.5)) * 2.0;
    world.addParticle(p);
  }
  world.initialize();
  return world;
}

void expectListMatchesBruteForce(World& world, int steps) {
  const std::uint64_t buildsBefore = world.neighbourList().buildCount();
  std::size_t contactsSeen = 0;
  for (int s = 0; s < steps; ++s) {
    const auto expected = bruteForceContacts(world.particles());
    ASSERT_EQ(checkedListContacts(world), expected) << "step " << s;
    contactsSeen += expected.size();
    world.step();
  }
  EXPECT_GT(world.neighbourList().buildCount(), buildsBefore + 2) << "rebuilds must have happened";
  EXPECT_GT(contactsSeen, 0u);
}

TEST(NeighbourList, SparseConfigurationMatchesBruteForce) {
  World world = randomWorld(300, 0.05, 1);
  expectListMatchesBruteForce(world, 600);
}

TEST(NeighbourList, DenseConfigurationMatchesBruteForce) {
  World world = randomWorld(400, 0.012, 2);  // heavily overlapping start
  expectListMatchesBruteForce(world, 300);
}

TEST(NeighbourList, ThreadedBuildMatchesBruteForce) {
  World world = randomWorld(400, 0.012, 3, 2);  // rows built by two threads
  expectListMatchesBruteForce(world, 300);
}

/// A frictional oblique collision of two spheres while a fast third particle
/// triggers neighbour rebuilds; returns the final relative velocity of the pair.
Vec3 obliqueCollision(double skin, std::uint32_t sortEvery, std::uint64_t* builds) {
  SimulationSettings s = test::fineSettings(1e-6, 5.0);
  s.watchdog.every_steps = 0;  // deliberately dense, deep overlaps: the list is what is tested
  s.neighbour_skin = skin;
  s.sort_every_builds = sortEvery;
  World world(s);
  world.addMaterial(test::testMaterial(0.5, 0.8));
  ParticleSpec runner;
  runner.radius = 0.001;
  runner.position = Vec3(0.05, 0.05, 0.05);
  runner.velocity = Vec3(-4.0, 0.0, 0.0);
  ParticleSpec a;
  a.radius = 0.001;
  a.position = Vec3(0.0, 0.0, 0.0);
  a.velocity = Vec3(0.1, -0.05, 0.0);
  ParticleSpec b = a;
  b.position = Vec3(0.00201, 0.0, 0.0);
  b.velocity = Vec3(-0.1, 0.05, 0.0);
  world.addParticle(runner);  // slot 0 first, so cell sorts move the pair's slots
  world.addParticle(a);
  world.addParticle(b);
  world.initialize();
  for (int i = 0; i < 400; ++i) world.step();
  *builds = world.neighbourList().buildCount();
  const auto& p = world.particles();
  Vec3 va = Vec3::Zero();
  Vec3 vb = Vec3::Zero();
  for (std::size_t i = 0; i < p.size(); ++i) {
    if (p.id[i] == 2) va = p.velocity[i];
    if (p.id[i] == 3) vb = p.velocity[i];
  }
  return vb - va;
}

TEST(NeighbourList, HistoryCarriedAcrossRebuildsAndSorts) {
  // The tangential spring of the colliding pair must survive rebuilds and slot
  // reorderings: the run that rebuilds nearly every step (tiny skin, a cell sort
  // at each build) must give the same collision as the run that never rebuilds.
  std::uint64_t buildsCalm = 0;
  std::uint64_t buildsBusy = 0;
  const Vec3 calm = obliqueCollision(0.01, 0, &buildsCalm);
  const Vec3 busy = obliqueCollision(2e-6, 1, &buildsBusy);
  ASSERT_LE(buildsCalm, 1u);
  ASSERT_GT(buildsBusy, 100u);
  EXPECT_GT(std::abs(calm.y() + 0.1), 0.01) << "friction must have changed the tangential motion";
  EXPECT_LT((busy - calm).norm(), 1e-12);
}

}  // namespace
}  // namespace demlink::core
