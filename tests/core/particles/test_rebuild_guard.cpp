// The rebuild guard may call the lists fresh only when they still hold every contact:
// for random beds displaced as a whole, in two sliding halves, by random jiggles or by
// one particle thrown at the others, whenever the guard says "fresh" every touching pair
// must be listed and every particle touching a plane must be in its near list (brute
// force). It must also earn its keep: a bed carried as one body is fresh however far it
// went, where the skin/2 rule would rebuild.
#include <array>
#include <random>

#include <gtest/gtest.h>

#include "test_scenes.hpp"

#include "demlink/core/particles/neighbour_list.hpp"
#include "demlink/core/world.hpp"
#include "demlink/core/particles/rebuild_guard.hpp"
#include "demlink/core/parallel/thread_pool.hpp"
#include "demlink/core/walls/plane_wall.hpp"

namespace demlink::core {
namespace {

constexpr double kSkin = 2e-4;  // [m]

struct Bed {
  ParticleArrays particles;
  NeighbourList list{kSkin};
  std::vector<PlaneWall> planes;
  RebuildGuard guard;
};

/// A bed of `specs` with its lists and guard built; slots in cell order, as World keeps
/// them (the guard's slot groups are then compact), unless `inCellOrder` is false.
std::unique_ptr<Bed> makeBed(const std::vector<ParticleSpec>& specs, bool inCellOrder = true) {
  auto bed = std::make_unique<Bed>();
  for (std::size_t i = 0; i < specs.size(); ++i) bed->particles.append(specs[i], 2500.0, i);
  if (inCellOrder) {
    CellGrid grid;
    grid.build(bed->particles.position, bed->particles.radius, kSkin);
    bed->particles.permute(grid.spatialOrder(bed->particles.position));
  }
  bed->list.build(bed->particles, {});
  for (const Vec3& normal : {Vec3(0, 0, 1), Vec3(1, 0, 0)}) {
    PlaneWall wall;
    wall.spec.normal = normal;
    wall.buildNearList(bed->particles, kSkin, {});
    bed->planes.push_back(wall);
  }
  const auto built = bed->list.builtPositions();
  bed->guard.arm(built, bed->particles.radius, kSkin);
  for (const PlaneWall& wall : bed->planes) {
    bed->guard.addPlane(wall.spec.point, wall.spec.normal, wall.near_slots, built, bed->particles.radius);
  }
  return bed;
}

/// n spheres of radius 0.5-1.5 mm at random in a cube of side `box` (particle i's cube
/// moved by offset(i)) above the floor z = 0 and right of the wall x = 0.
std::unique_ptr<Bed> randomBed(std::size_t n, double box, std::mt19937_64& rng,
                               Vec3 (*offset)(std::size_t) = [](std::size_t) { return Vec3::Zero().eval(); },
                               bool inCellOrder = true) {
  std::uniform_real_distribution<double> u(0.0, 1.0);
  std::vector<ParticleSpec> specs(n);
  for (std::size_t i = 0; i < n; ++i) {
    specs[i].radius = 0.001 * (0.5 + u(rng));
    specs[i].position = Vec3(u(rng), u(rng), u(rng)) * box + offset(i);
  }
  return makeBed(specs, inCellOrder);
}

/// Where the lists miss a contact at positions `now`: "" if nowhere.
std::string missedContact(const Bed& bed, const std::vector<Vec3>& now) {
  const ParticleArrays& p = bed.particles;
  const auto offsets = bed.list.offsets();
  const auto partners = bed.list.partners();
  for (std::size_t i = 0; i < p.size(); ++i) {
    for (std::size_t j = i + 1; j < p.size(); ++j) {
      if ((now[j] - now[i]).norm() >= p.radius[i] + p.radius[j]) continue;
      if (std::find(partners.begin() + offsets[i], partners.begin() + offsets[i + 1], j) ==
          partners.begin() + offsets[i + 1]) {
        return "pair " + std::to_string(i) + "-" + std::to_string(j) + " touches but is not listed";
      }
    }
  }
  for (const PlaneWall& wall : bed.planes) {
    for (std::size_t i = 0; i < p.size(); ++i) {
      if ((now[i] - wall.spec.point).dot(wall.spec.normal) >= p.radius[i]) continue;
      if (std::find(wall.near_slots.begin(), wall.near_slots.end(), i) == wall.near_slots.end()) {
        return "particle " + std::to_string(i) + " touches a plane but is not in its near list";
      }
    }
  }
  return "";
}

enum class Motion { kCarried, kTwoHalves, kJiggle, kThrown, kOneGroupJiggles };

/// The bed's build positions displaced by one of the motions, at a random scale.
std::vector<Vec3> displaced(const Bed& bed, Motion motion, std::mt19937_64& rng) {
  std::uniform_real_distribution<double> u(0.0, 1.0);
  std::normal_distribution<double> gauss(0.0, 1.0);
  const auto built = bed.list.builtPositions();
  std::vector<Vec3> now(built.begin(), built.end());
  const auto direction = [&] { return Vec3(gauss(rng), gauss(rng), gauss(rng)).normalized(); };
  switch (motion) {
    case Motion::kCarried: {
      // Towards or away from the planes, up to 20 skins, with a jiggle of up to a skin.
      const Vec3 shift = direction() * (20.0 * kSkin * u(rng));
      const double jiggle = kSkin * u(rng);
      for (Vec3& x : now) x += shift + direction() * (jiggle * u(rng));
      break;
    }
    case Motion::kTwoHalves: {
      const Vec3 a = direction() * (10.0 * kSkin * u(rng));
      const Vec3 slip = direction() * (3.0 * kSkin * u(rng));
      // Split at a group boundary: the halves meet only across near group pairs.
      const std::size_t half = now.size() / 2 / RebuildGuard::kGroupSlots * RebuildGuard::kGroupSlots;
      for (std::size_t i = 0; i < now.size(); ++i) now[i] += i < half ? a : Vec3(a + slip);
      break;
    }
    case Motion::kJiggle: {
      const double amplitude = 1.5 * kSkin * u(rng);
      for (Vec3& x : now) x += direction() * (amplitude * u(rng));
      break;
    }
    case Motion::kThrown: {
      const std::size_t i = static_cast<std::size_t>(u(rng) * static_cast<double>(now.size()));
      const std::size_t j = (i + 1 + static_cast<std::size_t>(u(rng) * static_cast<double>(now.size() - 1))) %
                            now.size();
      now[i] += (now[j] - now[i]).normalized() * (2.0 * kSkin * u(rng));  // towards another, up to 2 skins
      break;
    }
    case Motion::kOneGroupJiggles: {
      // Relative motion inside one slot group only.
      const std::size_t groups = (now.size() + RebuildGuard::kGroupSlots - 1) / RebuildGuard::kGroupSlots;
      const std::size_t first = static_cast<std::size_t>(u(rng) * static_cast<double>(groups)) *
                                RebuildGuard::kGroupSlots;
      const double amplitude = 1.5 * kSkin * u(rng);
      for (std::size_t i = first; i < std::min(now.size(), first + RebuildGuard::kGroupSlots); ++i) {
        now[i] += direction() * (amplitude * u(rng));
      }
      break;
    }
  }
  return now;
}

TEST(RebuildGuard, FreshListsHoldEveryContactUnderAnyMotion) {
  std::mt19937_64 rng(2024);
  std::array<int, 5> fresh{};
  std::array<int, 5> trials{};
  for (int bedIndex = 0; bedIndex < 6; ++bedIndex) {
    // Dense (deep overlaps, many pairs per group) to sparse.
    const double box = 0.006 + 0.004 * bedIndex;
    const auto bed = randomBed(300, box, rng);
    EXPECT_GT(bed->guard.nearPairCount(), 0u);
    for (int t = 0; t < 500; ++t) {
      const auto motion = static_cast<Motion>(t % 5);
      const std::vector<Vec3> now = displaced(*bed, motion, rng);
      ++trials[t % 5];
      if (bed->guard.stale(bed->list.builtPositions(), now)) continue;
      ++fresh[t % 5];
      const std::string missed = missedContact(*bed, now);
      ASSERT_EQ(missed, "") << "bed " << bedIndex << ", motion " << static_cast<int>(motion) << ", trial " << t;
    }
  }
  // Not vacuous: every kind of motion must have been judged fresh often.
  for (std::size_t m = 0; m < fresh.size(); ++m) {
    EXPECT_GT(fresh[m], trials[m] / 10) << "motion " << m << ": " << fresh[m] << " of " << trials[m];
  }
}

TEST(RebuildGuard, ChunkedTestsSeeMotionOnlyOneChunkCanSee) {
  // Enough groups that the pair and plane tests are cut into several chunks, and motions
  // only one chunk's tests can see: the answer must not depend on which thread ran it.
  std::mt19937_64 rng(77);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  const auto bed = randomBed(20000, 0.04, rng);
  const auto built = bed->list.builtPositions();
  const std::size_t groups = (built.size() + RebuildGuard::kGroupSlots - 1) / RebuildGuard::kGroupSlots;
  ThreadPool pool(2);
  for (int t = 0; t < 40; ++t) {
    // Slots from a random group boundary on slip 3 skins against the others: only the near
    // group pairs across that boundary see it.
    const std::size_t split = (1 + static_cast<std::size_t>(u(rng) * static_cast<double>(groups - 1))) *
                              RebuildGuard::kGroupSlots;
    std::vector<Vec3> now(built.begin(), built.end());
    for (std::size_t i = split; i < now.size(); ++i) now[i] += Vec3(3.0 * kSkin, 0.0, 0.0);
    EXPECT_TRUE(bed->guard.stale(built, now)) << "split at " << split;
    EXPECT_TRUE(bed->guard.stale(built, now, &pool)) << "split at " << split;
    // The whole bed 0.2 skins away from both planes: fresh.
    now.assign(built.begin(), built.end());
    for (Vec3& x : now) x += Vec3(0.14 * kSkin, 0.0, 0.14 * kSkin);
    EXPECT_FALSE(bed->guard.stale(built, now));
    EXPECT_FALSE(bed->guard.stale(built, now, &pool));
    // The whole bed carried 1-3 skins towards the floor: only the floor's tests see it
    // (no relative motion), and not those of the x = 0 wall, which come last.
    const double down = (1.0 + 2.0 * u(rng)) * kSkin;
    now.assign(built.begin(), built.end());
    for (Vec3& x : now) x.z() -= down;
    EXPECT_TRUE(bed->guard.stale(built, now)) << "down " << down;
    EXPECT_TRUE(bed->guard.stale(built, now, &pool)) << "down " << down;
  }
}

TEST(RebuildGuard, ABedCarriedAsOneBodyNeedsNoRebuildWhereTheHalfSkinRuleWould) {
  std::mt19937_64 rng(7);
  const auto bed = randomBed(500, 0.01, rng);
  const auto built = bed->list.builtPositions();
  // Up, away from the floor, and along the wall: 30 skins.
  std::vector<Vec3> now(built.begin(), built.end());
  for (Vec3& x : now) x += Vec3(0.0, 30.0 * kSkin, 30.0 * kSkin);
  EXPECT_TRUE(bed->list.needsRebuild(now)) << "the skin/2 rule rebuilds";
  EXPECT_FALSE(bed->guard.stale(built, now));
  // Carried down onto the floor by 2 skins: the lowest particles may now touch it.
  for (Vec3& x : now) x += Vec3(0.0, 0.0, -32.0 * kSkin);
  EXPECT_TRUE(bed->guard.stale(built, now));
}

TEST(RebuildGuard, FarGroupsCarriedOntoEachOtherAreStale) {
  // Two slot groups 40 mm apart along y, far beyond each other's reach, so no near pair joins
  // them; the second, carried rigidly onto the first, touches it: the bound on the spread
  // of all displacements must catch it.
  std::mt19937_64 rng(11);
  constexpr std::size_t kGroup = RebuildGuard::kGroupSlots;
  const auto bed = randomBed(2 * kGroup, 0.004, rng, [](std::size_t i) {
    return Vec3(0.01, i < RebuildGuard::kGroupSlots ? 0.0 : 0.04, 0.01);
  }, false);
  ASSERT_EQ(bed->guard.nearPairCount(), 0u);
  const auto built = bed->list.builtPositions();
  std::vector<Vec3> now(built.begin(), built.end());
  EXPECT_FALSE(bed->guard.stale(built, now));
  for (std::size_t i = kGroup; i < now.size(); ++i) now[i].y() -= 0.04;  // along both planes
  ASSERT_NE(missedContact(*bed, now), "") << "the test needs a missed contact";
  EXPECT_TRUE(bed->guard.stale(built, now));
}

TEST(RebuildGuard, GroupsJustBeyondContactRangeCarriedTogetherAreStale) {
  // Two 8 x 8 sheets of 1 mm spheres, 3 mm apart within a sheet, the sheets 2.3 mm
  // apart: no pair within 2 r + skin = 2.2 mm, so none is listed. Closing the sheets by
  // 0.4 mm (twice the skin) makes every facing pair touch; the two groups' build boxes
  // must count as near (within 2 (2 r_max + skin)), or only the spread bound would see
  // the motion, and it allows 2 r_max + 2 skin.
  std::vector<ParticleSpec> specs(2 * RebuildGuard::kGroupSlots);
  for (std::size_t i = 0; i < specs.size(); ++i) {
    const std::size_t k = i % RebuildGuard::kGroupSlots;
    specs[i].radius = 0.001;
    specs[i].position = Vec3(0.01 + 0.003 * static_cast<double>(k % 8), i < RebuildGuard::kGroupSlots ? 0.0 : 0.0023,
                             0.01 + 0.003 * static_cast<double>(k / 8));
  }
  const auto bed = makeBed(specs, false);
  ASSERT_EQ(bed->list.pairCount(), 0u);
  const auto built = bed->list.builtPositions();
  std::vector<Vec3> now(built.begin(), built.end());
  for (std::size_t i = RebuildGuard::kGroupSlots; i < now.size(); ++i) now[i].y() -= 2.0 * kSkin;
  ASSERT_NE(missedContact(*bed, now), "") << "the test needs a missed contact";
  EXPECT_TRUE(bed->guard.stale(built, now));
}

TEST(RebuildGuard, PairsClosingInsideOneGroupAreStale) {
  // One group: a row of 1 mm spheres 1.2 skins further apart than touching (so none is
  // listed), every second one moved 0.65 skin towards its right neighbour, which moves
  // as far towards it: pairs close by 1.3 skins. Only the group's own spread shows it.
  std::vector<ParticleSpec> specs(RebuildGuard::kGroupSlots);
  const double spacing = 0.002 + 1.2 * kSkin;
  for (std::size_t i = 0; i < specs.size(); ++i) {
    specs[i].radius = 0.001;
    specs[i].position = Vec3(0.01 + spacing * static_cast<double>(i), 0.01, 0.01);
  }
  const auto bed = makeBed(specs, false);
  ASSERT_EQ(bed->list.pairCount(), 0u);
  const auto built = bed->list.builtPositions();
  std::vector<Vec3> now(built.begin(), built.end());
  for (std::size_t i = 0; i < now.size(); ++i) now[i].x() += (i % 2 == 0 ? 0.65 : -0.65) * kSkin;
  ASSERT_NE(missedContact(*bed, now), "") << "the test needs a missed contact";
  EXPECT_TRUE(bed->guard.stale(built, now));
}

TEST(RebuildGuard, NonFiniteParticlesTouchNothingAndDoNotForceRebuilds) {
  std::mt19937_64 rng(3);
  const auto bed = randomBed(200, 0.01, rng);
  const auto built = bed->list.builtPositions();
  std::vector<Vec3> now(built.begin(), built.end());
  now[17] = Vec3::Constant(std::numeric_limits<double>::quiet_NaN());
  EXPECT_FALSE(bed->guard.stale(built, now));
  EXPECT_TRUE(bed->guard.stale(built, std::vector<Vec3>(now.begin(), now.end() - 1))) << "count changed";
}

TEST(RebuildGuard, AWorldCarriesALatticeOntoTheFloorWithTwoBuilds) {
  // A 4 x 4 x 4 lattice of 1 mm spheres (gaps of 0.3 mm, within the 0.5 mm skin) moving
  // down at 1 m/s without gravity: 19 mm, 38 skins, to the floor. The skin/2 rule would
  // rebuild every 25 steps; relative to each other the spheres do not move, so the
  // world rebuilds once more, when the lowest layer may reach the floor, and the floor
  // then stops them.
  SimulationSettings s = test::fineSettings(1e-5, 2.0);
  s.neighbour_skin = 5e-4;
  World world(s);
  const std::uint32_t material = world.addMaterial(test::testMaterial(0.5));
  world.addPlane({"floor", Vec3::Zero(), Vec3::UnitZ(), material});
  for (int k = 0; k < 64; ++k) {
    ParticleSpec p;
    p.radius = 1e-3;
    p.position = Vec3(0.01 + 0.0023 * (k % 4), 0.01 + 0.0023 * (k / 4 % 4), 0.02 + 0.0023 * (k / 16));
    p.velocity = Vec3(0.0, 0.0, -1.0);
    p.material = material;
    world.addParticle(p);
  }
  world.initialize();
  ASSERT_GT(world.neighbourList().pairCount(), 0u);
  const std::uint64_t before = world.neighbourList().buildCount();
  const auto lowestSpeed = [&] {
    double v = 1e9;
    for (const Vec3& u : world.particles().velocity) v = std::min(v, u.z());
    return v;
  };
  // Until the first sphere turns back: ~1,900 steps to the floor, then the contact.
  const std::uint64_t steps = test::stepUntil(world, [&] {
    double highest = -1e9;
    for (const Vec3& u : world.particles().velocity) highest = std::max(highest, u.z());
    return highest > 0.0;
  }, 5000);
  ASSERT_LT(steps, 5000u) << "the floor must stop the lattice";
  EXPECT_GT(steps, 1800u);
  EXPECT_LE(world.neighbourList().buildCount() - before, 2u) << "builds while carried";
  EXPECT_GT(lowestSpeed(), -1.0 - 1e-12) << "nothing sped up: no pair met unseen";
}

}  // namespace
}  // namespace demlink::core
