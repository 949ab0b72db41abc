/// PitGenerator: the settled bed reaches the target height (within one diameter),
/// stays in the box, has only small overlaps, and depends only on the seed.
#include <gtest/gtest.h>

#include <cmath>

#include "demlink/core/base/input_error.hpp"
#include "demlink/core/setup/pit_generator.hpp"
#include "demlink/core/world.hpp"
#include "test_scenes.hpp"

namespace demlink::core {
namespace {

/// A 0.4 x 0.2 m box, bed 0.12 m deep, spheres r in [16, 20] mm (a few hundred).
PitSpec smallPit(std::uint64_t seed, double targetHeight = 0.12) {
  PitSpec spec;
  spec.lower = Vec3(-0.2, -0.1, 0.0);
  spec.upper = Vec3(0.2, 0.1, 0.3);
  spec.target_height = targetHeight;
  spec.sizes = SizeDistribution::uniform(0.016, 0.02);
  spec.seed = seed;
  return spec;
}

struct Bed {
  World world{SimulationSettings{}};
  PitReport report;
};

std::unique_ptr<Bed> makeBed(std::uint64_t seed, double targetHeight = 0.12) {
  auto bed = std::make_unique<Bed>();
  bed->world.addMaterial(test::testMaterial(0.5, 0.5));
  bed->report = generatePit(bed->world, smallPit(seed, targetHeight), "pit", "components[1].pit_generator");
  return bed;
}

TEST(PitGenerator, BedReachesTheTargetInsideTheBoxWithSmallOverlaps) {
  const auto bed = makeBed(1);
  const PitSpec spec = smallPit(1);
  const ParticleArrays& p = bed->world.particles();
  ASSERT_GT(p.size(), 50u);
  EXPECT_TRUE(bed->report.settled);
  EXPECT_LT(bed->report.final_mean_kinetic_energy, bed->report.threshold);
  EXPECT_EQ(bed->report.kept, p.size());
  EXPECT_NEAR(bed->report.kept_mass, bed->world.totalMass(), 1e-12 * bed->world.totalMass());
  double top = 0.0;
  const double rMax = spec.sizes.maxRadius();
  for (std::size_t i = 0; i < p.size(); ++i) {
    const double r = p.radius[i];
    top = std::max(top, p.position[i].z() + r);
    // Inside the box: a sphere may press into a wall by a small fraction of its radius.
    for (int k = 0; k < 3; ++k) EXPECT_GE(p.position[i][k] - r, spec.lower[k] - 0.05 * r);
    for (int k = 0; k < 2; ++k) EXPECT_LE(p.position[i][k] + r, spec.upper[k] + 0.05 * r);
    EXPECT_EQ(p.velocity[i], Vec3::Zero());
    for (std::size_t j = i + 1; j < p.size(); ++j) {
      const double overlap = r + p.radius[j] - (p.position[i] - p.position[j]).norm();
      EXPECT_LT(overlap, 0.05 * std::min(r, p.radius[j]));
    }
  }
  EXPECT_LE(top, spec.lower.z() + spec.target_height + 1e-12);
  EXPECT_GE(top, spec.lower.z() + spec.target_height - 2.0 * rMax);
  // Solid fraction of the kept bed up to its top: a plausible loose packing for a
  // narrow box (5-6 diameters wide, wall effects) with a trimmed, rough surface.
  const double volume = bed->report.kept_mass / 2500.0;
  const double fraction = volume / (0.4 * 0.2 * top);
  EXPECT_GT(fraction, 0.35);
  EXPECT_LT(fraction, 0.68);
  // The report's packing fraction is the same solid volume over the target height.
  EXPECT_NEAR(bed->report.packing_fraction, volume / (0.4 * 0.2 * spec.target_height), 1e-12);
  EXPECT_GT(bed->report.settle_wall_seconds, 0.0);
}

TEST(PitGenerator, SameSeedSameBedOtherSeedOtherBed) {
  const auto a = makeBed(3, 0.06);
  const auto b = makeBed(3, 0.06);
  const auto c = makeBed(4, 0.06);
  const ParticleArrays& pa = a->world.particles();
  ASSERT_EQ(pa.size(), b->world.particles().size());
  for (std::size_t i = 0; i < pa.size(); ++i) {
    EXPECT_EQ(pa.position[i], b->world.particles().position[i]);
    EXPECT_EQ(pa.radius[i], b->world.particles().radius[i]);
  }
  bool differs = pa.size() != c->world.particles().size();
  for (std::size_t i = 0; !differs && i < pa.size(); ++i) differs = pa.position[i] != c->world.particles().position[i];
  EXPECT_TRUE(differs);
}

TEST(PitGenerator, BadInputNamesTheField) {
  auto fieldOf = [](const std::function<void(PitSpec&)>& edit) {
    World world{SimulationSettings{}};
    world.addMaterial(test::testMaterial(0.5));
    PitSpec spec = smallPit(1);
    edit(spec);
    try {
      spec.validate("pit");
      if (spec.material >= world.materials().size()) (void)generatePit(world, spec, "pit", "pit");
    } catch (const InputError& e) {
      return e.field();
    }
    return std::string("(accepted)");
  };
  EXPECT_EQ(fieldOf([](PitSpec&) {}), "(accepted)");
  EXPECT_EQ(fieldOf([](PitSpec& s) { s.upper.x() = -0.3; }), "pit.upper[0]");
  EXPECT_EQ(fieldOf([](PitSpec& s) { s.upper.z() = 0.0; }), "pit.upper[2]");
  EXPECT_EQ(fieldOf([](PitSpec& s) { s.target_height = 0.5; }), "pit.target_height");
  EXPECT_EQ(fieldOf([](PitSpec& s) { s.target_height = -0.1; }), "pit.target_height");
  EXPECT_EQ(fieldOf([](PitSpec& s) { s.sizes = SizeDistribution::uniform(0.02, 0.01); }), "pit.sizes.r_max");
  EXPECT_EQ(fieldOf([](PitSpec& s) { s.packing_fraction = 0.9; }), "pit.packing_fraction");
  EXPECT_EQ(fieldOf([](PitSpec& s) { s.overfill = 0.5; }), "pit.overfill");
  EXPECT_EQ(fieldOf([](PitSpec& s) { s.material = 2; }), "pit.material");
  EXPECT_EQ(fieldOf([](PitSpec& s) { s.sizes = SizeDistribution::fixed(0.1); }), "pit.upper[1]");
}

}  // namespace
}  // namespace demlink::core
