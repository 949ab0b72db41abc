// Conservation laws.
//  - Elastic (e = 1), frictionless gas of spheres in a closed box of planes:
//    total energy (kinetic + Hertz elastic energy of open contacts,
//    U = 8/15 E* sqrt(R*) delta^(5/2)) stays within 1e-4 relative over more
//    than 10^4 collisions with velocity Verlet.
//  - Linear momentum of a free cluster (no walls, no gravity) with dissipative,
//    frictional contacts is conserved to round-off.
#include <random>
#include <set>

#include <gtest/gtest.h>

#include "test_scenes.hpp"

namespace demlink::core {
namespace {

/// Kinetic energy plus the elastic energy stored in open Hertz contacts.
double totalEnergy(const World& world) {
  const ParticleArrays& p = world.particles();
  double energy = world.kineticEnergy();
  const double eStar = world.pairTable()(0, 0).effective_youngs;
  auto hertzEnergy = [&](double rStar, double overlap) {
    return overlap > 0.0 ? 8.0 / 15.0 * eStar * std::sqrt(rStar) * std::pow(overlap, 2.5) : 0.0;
  };
  for (std::size_t i = 0; i < p.size(); ++i) {
    for (std::size_t j = i + 1; j < p.size(); ++j) {
      const double overlap = p.radius[i] + p.radius[j] - (p.position[j] - p.position[i]).norm();
      energy += hertzEnergy(p.radius[i] * p.radius[j] / (p.radius[i] + p.radius[j]), overlap);
    }
    for (const PlaneWall& wall : world.planes()) {
      energy += hertzEnergy(p.radius[i], p.radius[i] - (p.position[i] - wall.spec.point).dot(wall.spec.normal));
    }
  }
  return energy;
}

TEST(Conservation, ElasticGasKeepsEnergyOver10kCollisions) {
  constexpr double kRadius = 0.001;
  constexpr double kBox = 0.02;
  SimulationSettings settings = test::fineSettings(4e-6, 2.0);
  World world(settings);
  const auto mat = world.addMaterial(test::testMaterial(1.0, 0.0));
  const Vec3 lo = Vec3::Zero();
  const Vec3 hi = Vec3::Constant(kBox);
  for (int d = 0; d < 3; ++d) {
    world.addPlane({"lo", lo, Vec3::Unit(d), mat});
    world.addPlane({"hi", hi, -Vec3::Unit(d), mat});
  }
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  // 6 x 6 x 6 lattice (spacing 3.3 mm) with random velocities up to 1 m/s.
  for (int ix = 0; ix < 6; ++ix) {
    for (int iy = 0; iy < 6; ++iy) {
      for (int iz = 0; iz < 6; ++iz) {
        ParticleSpec s;
        s.radius = kRadius;
        s.position = Vec3(ix + 0.5, iy + 0.5, iz + 0.5) * (kBox / 6.0);
        s.velocity = Vec3(unit(rng), unit(rng), unit(rng)) / std::sqrt(3.0);
        world.addParticle(s);
      }
    }
  }
  world.initialize();
  const double e0 = totalEnergy(world);
  std::uint64_t collisions = 0;
  auto previous = test::listedContacts(world);
  double worstDrift = 0.0;
  while (collisions < 10'000) {
    world.step();
    const auto current = test::listedContacts(world);
    for (const auto& pair : current) collisions += previous.count(pair) == 0 ? 1 : 0;
    previous = current;
    if (world.stepCount() % 2000 == 0) worstDrift = std::max(worstDrift, std::abs(totalEnergy(world) / e0 - 1.0));
    ASSERT_LT(world.stepCount(), 2'000'000u) << "too few collisions: " << collisions;
  }
  worstDrift = std::max(worstDrift, std::abs(totalEnergy(world) / e0 - 1.0));
  EXPECT_LT(worstDrift, 1e-4) << "after " << collisions << " particle-particle collisions";
  RecordProperty("collisions", static_cast<int>(collisions));
}

TEST(Conservation, MomentumConservedToRoundOffInDissipativeCollisions) {
  World world(test::fineSettings(2e-6, 2.0));
  world.addMaterial(test::testMaterial(0.3, 0.5, 0.1));
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  for (int i = 0; i < 4; ++i) {
    for (int j = 0; j < 4; ++j) {
      for (int k = 0; k < 4; ++k) {
        ParticleSpec s;
        s.radius = 0.001 * (1.0 + 0.2 * unit(rng));
        s.position = Vec3(i, j, k) * 0.0021;
        s.velocity = Vec3(unit(rng), unit(rng), unit(rng)) * 0.5 - Vec3(i - 1.5, j - 1.5, k - 1.5) * 0.3;
        s.angular_velocity = Vec3(unit(rng), unit(rng), unit(rng)) * 100.0;
        world.addParticle(s);
      }
    }
  }
  world.initialize();
  auto momentum = [&] {
    Vec3 sum = Vec3::Zero();
    const auto& p = world.particles();
    for (std::size_t i = 0; i < p.size(); ++i) sum += p.mass[i] * p.velocity[i];
    return sum;
  };
  const Vec3 p0 = momentum();
  double scale = 0.0;  // sum of |m v|: the round-off yardstick
  for (std::size_t i = 0; i < world.particles().size(); ++i) {
    scale += world.particles().mass[i] * world.particles().velocity[i].norm();
  }
  const double e0 = world.kineticEnergy();
  for (int n = 0; n < 20000; ++n) world.step();
  EXPECT_LT(world.kineticEnergy(), 0.9 * e0) << "collisions must have happened and dissipated";
  EXPECT_LT((momentum() - p0).norm(), 1e-13 * scale);
}

}  // namespace
}  // namespace demlink::core
