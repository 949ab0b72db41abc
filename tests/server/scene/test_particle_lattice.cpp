/// Lattice generation: layout, deterministic randomness, validation.
#include <gtest/gtest.h>

#include <random>

#include "demlink/core/base/input_error.hpp"
#include "demlink/server/scene/particle_lattice.hpp"

namespace demlink::server {
namespace {

LatticeSpec depositionLattice(std::uint64_t seed) {
  LatticeSpec spec;
  spec.radius = 0.002;
  spec.radius_max = 0.003;
  spec.origin = core::Vec3(0.0045, 0.0045, 0.0035);
  spec.spacing = 0.0065;
  spec.counts = {15, 15, 4};
  spec.jitter = 0.0002;
  spec.seed = seed;
  spec.material = 2;
  return spec;
}

TEST(ParticleLattice, SameSeedGivesIdenticalSpheres) {
  const std::vector<core::ParticleSpec> a = generateLattice(depositionLattice(12345));
  const std::vector<core::ParticleSpec> b = generateLattice(depositionLattice(12345));
  ASSERT_EQ(a.size(), 900u);
  ASSERT_EQ(a.size(), b.size());
  for (std::size_t i = 0; i < a.size(); ++i) {
    EXPECT_EQ(a[i].position, b[i].position) << i;  // bit-identical, not just close
    EXPECT_EQ(a[i].radius, b[i].radius) << i;
  }
}

TEST(ParticleLattice, DifferentSeedGivesDifferentSpheres) {
  const std::vector<core::ParticleSpec> a = generateLattice(depositionLattice(12345));
  const std::vector<core::ParticleSpec> b = generateLattice(depositionLattice(12346));
  ASSERT_EQ(a.size(), b.size());
  std::size_t differentPositions = 0;
  std::size_t differentRadii = 0;
  for (std::size_t i = 0; i < a.size(); ++i) {
    differentPositions += a[i].position != b[i].position ? 1 : 0;
    differentRadii += a[i].radius != b[i].radius ? 1 : 0;
  }
  EXPECT_EQ(differentPositions, a.size());
  EXPECT_EQ(differentRadii, a.size());
}

TEST(ParticleLattice, LayoutRadiiAndJitterStayInTheirRanges) {
  const LatticeSpec spec = depositionLattice(7);
  const std::vector<core::ParticleSpec> spheres = generateLattice(spec);
  double smallest = 1.0;
  double largest = 0.0;
  for (std::size_t i = 0; i < spheres.size(); ++i) {
    const std::size_t ix = i % 15;
    const std::size_t iy = (i / 15) % 15;
    const std::size_t iz = i / 225;
    const core::Vec3 site = spec.origin + spec.spacing * core::Vec3(static_cast<double>(ix), static_cast<double>(iy),
                                                                    static_cast<double>(iz));
    EXPECT_LE((spheres[i].position - site).cwiseAbs().maxCoeff(), spec.jitter) << "x fastest, then y, then z: " << i;
    EXPECT_GE(spheres[i].radius, spec.radius);
    EXPECT_LE(spheres[i].radius, *spec.radius_max);
    EXPECT_EQ(spheres[i].material, 2u);
    smallest = std::min(smallest, spheres[i].radius);
    largest = std::max(largest, spheres[i].radius);
  }
  EXPECT_LT(smallest, 0.0021) << "radii should spread over [radius, radius_max]";
  EXPECT_GT(largest, 0.0029);
}

TEST(ParticleLattice, UsesItsOwnUniformMappingOfMt19937_64) {
  // The documented contract: u = (top 53 bits of mt19937_64) * 2^-53, radius drawn first.
  // radius = 0, radius_max = 1 (not a valid scene, but generateLattice does not
  // validate) makes the radius u itself, so even a last-bit difference shows,
  // e.g. from std::uniform_real_distribution (which rounds 64 bits instead).
  LatticeSpec spec = depositionLattice(99);
  spec.radius = 0.0;
  spec.radius_max = 1.0;
  spec.jitter = 0.0;
  const std::vector<core::ParticleSpec> spheres = generateLattice(spec);
  std::mt19937_64 rng(99);
  for (std::size_t i = 0; i < 64; ++i) {
    const double u = static_cast<double>(rng() >> 11) * 0x1.0p-53;
    ASSERT_EQ(spheres[i].radius, u) << i;
  }
}

TEST(ParticleLattice, WithoutSpreadOrJitterItIsAnExactLattice) {
  LatticeSpec spec;
  spec.radius = 0.5;
  spec.spacing = 1.25;
  spec.counts = {2, 1, 3};
  spec.origin = core::Vec3(1, 2, 3);
  spec.velocity = core::Vec3(0, 0, -2);
  const std::vector<core::ParticleSpec> spheres = generateLattice(spec);
  ASSERT_EQ(spheres.size(), 6u);
  EXPECT_EQ(spheres[1].position, core::Vec3(2.25, 2, 3));
  EXPECT_EQ(spheres[5].position, core::Vec3(2.25, 2, 5.5));
  EXPECT_EQ(spheres[5].radius, 0.5);
  EXPECT_EQ(spheres[5].velocity, core::Vec3(0, 0, -2));
}

TEST(ParticleLattice, ValidationNamesTheField) {
  auto fieldOf = [](const LatticeSpec& spec) {
    try {
      spec.validate("lattice");
    } catch (const core::InputError& error) {
      return error.field();
    }
    return std::string("(valid)");
  };
  EXPECT_EQ(fieldOf(depositionLattice(1)), "(valid)");
  LatticeSpec overlap = depositionLattice(1);
  overlap.jitter = 0.0003;  // 2 (3 + 0.3) mm = 6.6 mm > 6.5 mm spacing
  EXPECT_EQ(fieldOf(overlap), "lattice.spacing");
  LatticeSpec inverted = depositionLattice(1);
  inverted.radius_max = 0.001;
  EXPECT_EQ(fieldOf(inverted), "lattice.radius_max");
  LatticeSpec empty = depositionLattice(1);
  empty.counts[1] = 0;
  EXPECT_EQ(fieldOf(empty), "lattice.counts.ny");
  LatticeSpec huge = depositionLattice(1);
  huge.counts = {4'000'000'000u, 4'000'000'000u, 4'000'000'000u};
  EXPECT_EQ(fieldOf(huge), "lattice.counts");
  LatticeSpec nan = depositionLattice(1);
  nan.origin.x() = std::nan("");
  EXPECT_EQ(fieldOf(nan), "lattice.origin[0]");
  LatticeSpec negativeJitter = depositionLattice(1);
  negativeJitter.jitter = -1e-4;
  EXPECT_EQ(fieldOf(negativeJitter), "lattice.jitter");
}

}  // namespace
}  // namespace demlink::server
