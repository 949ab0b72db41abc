/// Clods in a pit generator's bed (bonds/clods.hpp, pit_generator.hpp): a settled bed of
/// a few hundred spheres, 40 % of them grouped into clods of radius 45 mm and joined by
/// a bond rule limited to the clods. Checked against the definition: the bonded fraction
/// within 0.03 of clod_fraction, every clod (a connected set of bonds) within one of the
/// pit's clods and within clod_radius + r of one of its spheres, no bond across clods,
/// the bed itself unchanged by the clods, and the same clods for the same seed.
#include <gtest/gtest.h>

#include <algorithm>
#include <map>
#include <numeric>
#include <unordered_map>
#include <vector>

#include "demlink/core/setup/pit_generator.hpp"
#include "demlink/core/base/input_error.hpp"
#include "demlink/core/world.hpp"
#include "test_scenes.hpp"

namespace demlink::core {
namespace {

constexpr double kRMin = 0.016;        // [m]
constexpr double kRMax = 0.02;         // [m]
constexpr double kClodRadius = 0.045;  // [m]
constexpr double kClodFraction = 0.4;  // [-]
constexpr double kGap = 0.1 * kRMin;   // touching: surface gap at most this [m]

PitSpec clodPit(std::uint64_t seed, double clodFraction) {
  PitSpec spec;
  spec.lower = Vec3(-0.2, -0.1, 0.0);
  spec.upper = Vec3(0.2, 0.1, 0.3);
  spec.target_height = 0.12;
  spec.sizes = SizeDistribution::uniform(kRMin, kRMax);
  spec.seed = seed;
  spec.clod_fraction = clodFraction;
  spec.clod_radius = clodFraction > 0.0 ? kClodRadius : 0.0;
  spec.clod_gap = kGap;
  return spec;
}

struct Bed {
  World world{SimulationSettings{}};
  PitReport report;
};

std::unique_ptr<Bed> makeBed(std::uint64_t seed, double clodFraction) {
  auto bed = std::make_unique<Bed>();
  bed->world.addMaterial(test::testMaterial(0.5, 0.5));
  bed->report = generatePit(bed->world, clodPit(seed, clodFraction), "pit", "components[1].pit_generator");
  return bed;
}

/// The clods' bond rule: strong, stiff enough to hold, limited to the pit's clods.
BondRule clodRule(const PitReport& report) {
  BondRule rule;
  rule.name = "clay";
  rule.properties.normal_stiffness_per_area = 1.0e8;
  rule.properties.shear_stiffness_per_area = 1.0e8;
  rule.properties.tensile_strength = 1.0e6;
  rule.properties.shear_strength = 1.0e6;
  rule.properties.gap_tolerance = kGap;
  rule.groups.emplace(report.clod_members.begin(), report.clod_members.end());
  return rule;
}

/// Connected sets of particles (slots) joined by intact bonds.
std::vector<std::vector<std::uint32_t>> bondedSets(const World& world) {
  const std::size_t n = world.particles().size();
  std::vector<std::uint32_t> parent(n);
  std::iota(parent.begin(), parent.end(), 0u);
  const auto root = [&](std::uint32_t i) {
    while (parent[i] != i) i = parent[i] = parent[parent[i]];
    return i;
  };
  std::vector<char> bonded(n, 0);
  for (const ParallelBond& bond : world.bonds().bonds()) {
    if (bond.broken) continue;
    bonded[bond.slot_a] = bonded[bond.slot_b] = 1;
    parent[root(bond.slot_a)] = root(bond.slot_b);
  }
  std::map<std::uint32_t, std::vector<std::uint32_t>> sets;
  for (std::uint32_t i = 0; i < n; ++i) {
    if (bonded[i] != 0) sets[root(i)].push_back(i);
  }
  std::vector<std::vector<std::uint32_t>> out;
  for (auto& [r, members] : sets) out.push_back(std::move(members));
  return out;
}

TEST(PitClods, BondedFractionAndClodSizeFollowTheSpecAndTheBedIsUnchanged) {
  const auto bed = makeBed(5, kClodFraction);
  const auto plain = makeBed(5, 0.0);
  World& world = bed->world;
  const ParticleArrays& p = world.particles();
  ASSERT_GT(p.size(), 150u);
  // The clods leave the bed as it is.
  ASSERT_EQ(p.size(), plain->world.particles().size());
  for (std::size_t i = 0; i < p.size(); ++i) {
    ASSERT_EQ(p.position[i], plain->world.particles().position[i]);
    ASSERT_EQ(p.radius[i], plain->world.particles().radius[i]);
  }
  EXPECT_TRUE(plain->report.clod_members.empty());
  ASSERT_GT(bed->report.clods, 3u);

  world.addBondRule(clodRule(bed->report), "clods");
  world.initialize();
  world.step();  // the bonds are made at the end of the first step
  const std::vector<std::vector<std::uint32_t>> sets = bondedSets(world);
  std::size_t bondedParticles = 0;
  for (const auto& members : sets) bondedParticles += members.size();
  const double fraction = static_cast<double>(bondedParticles) / static_cast<double>(p.size());
  EXPECT_NEAR(fraction, kClodFraction, 0.03) << bondedParticles << " of " << p.size() << " spheres bonded";

  std::unordered_map<std::uint64_t, std::uint32_t> clodOf(bed->report.clod_members.begin(),
                                                          bed->report.clod_members.end());
  for (const ParallelBond& bond : world.bonds().bonds()) {
    ASSERT_EQ(clodOf.at(bond.id_a), clodOf.at(bond.id_b)) << "a bond joins two clods";
  }
  double largestExtent = 0.0;
  for (const auto& members : sets) {
    // Its centre: the member whose farthest fellow (centre distance + radius) is nearest.
    double extent = std::numeric_limits<double>::infinity();
    for (const std::uint32_t m : members) {
      double farthest = 0.0;
      for (const std::uint32_t j : members) farthest = std::max(farthest, (p.position[j] - p.position[m]).norm() + p.radius[j]);
      extent = std::min(extent, farthest);
    }
    EXPECT_LE(extent, kClodRadius + kRMax + 1.0e-6) << "a clod of " << members.size() << " spheres";
    largestExtent = std::max(largestExtent, extent);
  }
  EXPECT_GT(largestExtent, 0.5 * (kClodRadius + kRMax)) << "clods of about clod_radius, not pairs";
  std::printf("clods: %u clods, %zu bonded sets, %zu of %zu spheres bonded (%.4f, asked %.2f), largest extent %.4g m\n",
              bed->report.clods, sets.size(), bondedParticles, p.size(), fraction, kClodFraction, largestExtent);
}

TEST(PitClods, SameSeedSameClods) {
  const auto a = makeBed(7, 0.3);
  const auto b = makeBed(7, 0.3);
  ASSERT_FALSE(a->report.clod_members.empty());
  EXPECT_EQ(a->report.clod_members, b->report.clod_members);
}

TEST(PitClods, BadClodFieldsNameTheField) {
  const auto fieldOf = [](double fraction, double radius) {
    PitSpec spec = clodPit(1, 0.0);
    spec.clod_fraction = fraction;
    spec.clod_radius = radius;
    try {
      spec.validate("pit");
    } catch (const InputError& e) {
      return e.field() + " = " + e.value();
    }
    return std::string("(accepted)");
  };
  EXPECT_EQ(fieldOf(0.5, 0.05), "(accepted)");
  EXPECT_EQ(fieldOf(1.5, 0.05), "pit.clod_fraction = 1.5");
  EXPECT_EQ(fieldOf(-0.1, 0.05), "pit.clod_fraction = -0.1");
  EXPECT_EQ(fieldOf(0.5, 0.0), "pit.clod_radius = 0");
  EXPECT_EQ(fieldOf(0.0, 0.05), "pit.clod_radius = 0.05");
}

}  // namespace
}  // namespace demlink::core
