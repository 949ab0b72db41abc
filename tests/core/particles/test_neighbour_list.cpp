// The Verlet list must find exactly the brute-force contact set, on sparse and
// dense random configurations, at every step (before and after rebuilds, across
// cell sorts that reorder slots), name each pair's row, and carry contact history
// across rebuilds.
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
  const auto rows = world.neighbourList().rows();
  EXPECT_EQ(rows.size(), partners.size());
  std::set<std::pair<std::uint32_t, std::uint32_t>> slotPairs;
  for (std::size_t i = 0; i < p.size(); ++i) {
    for (std::uint32_t k = offsets[i]; k < offsets[i + 1]; ++k) {
      if (k < rows.size()) {
        EXPECT_EQ(rows[k], i) << "rows() must name the row of every listed pair";
      }
      EXPECT_GT(partners[k], i) << "half list must hold each pair once, owned by the lower slot";
      EXPECT_TRUE(slotPairs.emplace(static_cast<std::uint32_t>(i), partners[k]).second) << "pair listed twice";
    }
  }
  return test::listedContacts(world);
}

/// Random spheres in a cube of side `box` with random velocities; radiusOf(u) maps a
/// uniform draw in [0, 1) to a radius [m] (default: uniform in [0.5, 1.5] mm).
World randomWorld(std::size_t n, double box, std::uint64_t seed, std::uint32_t threads = 1,
                  double (*radiusOf)(double) = [](double u) { return 0.001 * (0.5 + u); }) {
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
    p.radius = radiusOf(u(rng));
    p.position = Vec3(u(rng), u(rng), u(rng)) * box;
    p.velocity = (Vec3(u(rng), u(rng), u(rng)) - Vec3::Constant(0.5)) * 2.0;
    world.addParticle(p);
  }
  world.initialize();
  return world;
}

/// After a step every listed pair that does not touch has released its spring (the pair
/// loop reads a separating pair's history only where NeighbourList::sprung() says it may
/// be set). Returns how many listed pairs hold a spring.
std::size_t expectApartPairsHaveNoSpring(const World& world, int step) {
  const ParticleArrays& p = world.particles();
  const auto offsets = world.neighbourList().offsets();
  const auto partners = world.neighbourList().partners();
  const auto history = world.neighbourList().history();
  std::size_t springs = 0;
  for (std::size_t i = 0; i + 1 < offsets.size(); ++i) {
    for (std::uint32_t k = offsets[i]; k < offsets[i + 1]; ++k) {
      const std::uint32_t j = partners[k];
      const double reach = p.radius[i] + p.radius[j];
      const bool touches = !((p.position[j] - p.position[i]).squaredNorm() >= reach * reach);
      if (!history[k].isZero(0.0)) ++springs;
      EXPECT_TRUE(touches || history[k].isZero(0.0)) << "apart pair (" << i << ", " << j << ") keeps a spring at step "
                                                     << step;
    }
  }
  return springs;
}

void expectListMatchesBruteForce(World& world, int steps) {
  const std::uint64_t buildsBefore = world.neighbourList().buildCount();
  std::size_t contactsSeen = 0;
  std::size_t springsSeen = 0;
  for (int s = 0; s < steps; ++s) {
    const auto expected = bruteForceContacts(world.particles());
    ASSERT_EQ(checkedListContacts(world), expected) << "step " << s;
    contactsSeen += expected.size();
    world.step();
    springsSeen += expectApartPairsHaveNoSpring(world, s + 1);
  }
  EXPECT_GT(springsSeen, 0u) << "no spring ever built up: the release test proves nothing";
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

/// Slot pairs (i < j) within r_i + r_j + skin, by brute force, with the list's own
/// floating-point test.
std::set<std::pair<std::uint32_t, std::uint32_t>> bruteForceListPairs(const ParticleArrays& p, double skin) {
  std::set<std::pair<std::uint32_t, std::uint32_t>> pairs;
  for (std::uint32_t i = 0; i < p.size(); ++i) {
    for (std::uint32_t j = i + 1; j < p.size(); ++j) {
      const double cutoff = p.radius[i] + p.radius[j] + skin;
      if ((p.position[j] - p.position[i]).squaredNorm() < cutoff * cutoff) pairs.emplace(i, j);
    }
  }
  return pairs;
}

/// The listed slot pairs (each held once, by its lower slot).
std::set<std::pair<std::uint32_t, std::uint32_t>> listPairs(const World& world) {
  const auto offsets = world.neighbourList().offsets();
  const auto partners = world.neighbourList().partners();
  std::set<std::pair<std::uint32_t, std::uint32_t>> pairs;
  for (std::uint32_t i = 0; i + 1 < offsets.size(); ++i) {
    for (std::uint32_t k = offsets[i]; k < offsets[i + 1]; ++k) pairs.emplace(i, partners[k]);
  }
  return pairs;
}

/// After initialize and after every step that rebuilt the list, the list holds exactly
/// the brute-force pairs within r_i + r_j + skin (positions are those of the build);
/// in between, the contacts match brute force.
void expectExactPairsAtEveryBuild(World& world, int steps) {
  const double skin = world.neighbourList().skin();
  std::uint64_t builds = world.neighbourList().buildCount();
  int checkedBuilds = 0;
  for (int s = 0; s <= steps; ++s) {
    if (s == 0 || world.neighbourList().buildCount() != builds) {
      builds = world.neighbourList().buildCount();
      const auto expected = bruteForceListPairs(world.particles(), skin);
      ASSERT_EQ(listPairs(world), expected) << "build at step " << s;
      ++checkedBuilds;
    }
    ASSERT_EQ(checkedListContacts(world), bruteForceContacts(world.particles())) << "step " << s;
    if (s < steps) world.step();
  }
  EXPECT_GE(checkedBuilds, 3) << "rebuilds must have happened";
}

TEST(NeighbourList, OneToTenRadiusRatioMatchesBruteForce) {
  // One sphere in ten is ten times larger: two grid levels, pairs between them found
  // from the small sphere whatever the slot order.
  World world = randomWorld(500, 0.03, 11, 1, [](double u) { return u < 0.1 ? 0.004 : 0.0004; });
  ASSERT_GE(world.neighbourList().grid().levelCount(), 2u);
  expectExactPairsAtEveryBuild(world, 200);
}

TEST(NeighbourList, ContinuousOneToFiveRadiiMatchBruteForce) {
  World world = randomWorld(500, 0.02, 12, 2, [](double u) { return 0.0004 * (1.0 + 4.0 * u); });
  ASSERT_GE(world.neighbourList().grid().levelCount(), 3u);
  expectExactPairsAtEveryBuild(world, 200);
}

TEST(NeighbourList, OneFarParticleMatchesBruteForceWithoutEmptyCells) {
  // Without domain bounds one particle far away must neither grow the cells nor
  // allocate the space in between: the grid holds only occupied cells.
  SimulationSettings s = test::fineSettings(2e-6, 3.0);
  s.watchdog.every_steps = 0;
  s.sort_every_builds = 3;
  World world(s);
  world.addMaterial(test::testMaterial(0.5, 0.3));
  std::mt19937_64 rng(13);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  for (int i = 0; i < 400; ++i) {
    ParticleSpec p;
    p.radius = 0.001 * (0.5 + u(rng));
    p.position = Vec3(u(rng), u(rng), u(rng)) * 0.012;
    p.velocity = (Vec3(u(rng), u(rng), u(rng)) - Vec3::Constant(0.5)) * 2.0;
    world.addParticle(p);
  }
  ParticleSpec far;
  far.radius = 0.001;
  far.position = Vec3(3.0e5, -2.0e5, 1.0e5);
  world.addParticle(far);
  world.initialize();
  const CellGrid& grid = world.neighbourList().grid();
  std::size_t cells = 0;
  for (std::size_t level = 0; level < grid.levelCount(); ++level) {
    cells += grid.cellCount(level);
    EXPECT_LT(grid.cellSize(level), 0.004) << "the cell edge follows the radii, not the extent";
  }
  EXPECT_LE(cells, world.particles().size());
  expectExactPairsAtEveryBuild(world, 200);
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
