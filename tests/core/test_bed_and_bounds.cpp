// Macroscopic checks.
//  - A settled bed in a box of planes: the floor carries the bed's weight
//    (side walls with mu = 0 take no vertical load) within 1 %.
//  - Particles leaving the domain bounds are removed and counted, with mass.
//  - Integrators: for an elastic bounce, velocity Verlet's energy error falls as
//    dt^2, explicit Euler's (paper eqs. 14-17) only as dt and with a gain.
#include <random>

#include <gtest/gtest.h>

#include "test_scenes.hpp"

namespace demlink::core {
namespace {

TEST(Bed, FloorCarriesTheWeightOfASettledBed) {
  SimulationSettings s;
  s.time_step = 1e-5;
  s.max_impact_velocity = 1.0;
  // These scenes test bookkeeping, not restitution: a loose restitution tolerance keeps
  // the step they were written for inside the limit (docs/physics.md "Critical time step").
  s.restitution_tolerance = 0.2;
  World world(s);
  const auto grains = test::addBoxedLattice(world);
  const auto floor = world.addPlane({"floor", Vec3::Zero(), Vec3::UnitZ(), grains});
  world.initialize();
  for (int n = 0; n < 60000; ++n) world.step();  // 0.6 s: falls, bounces, settles
  const double weight = world.totalMass() * 9.81;
  EXPECT_LT(world.kineticEnergy(), 1e-6 * weight * 0.03) << "bed has not settled";
  EXPECT_NEAR(world.planes()[floor].force.z() / -weight, 1.0, 0.01)
      << "floor force " << world.planes()[floor].force.transpose() << ", weight " << weight;
}

TEST(Bounds, ParticlesLeavingAreRemovedAndCounted) {
  SimulationSettings s = test::fineSettings(1e-5, 1.0);
  s.bounds = DomainBounds{Vec3::Constant(-0.1), Vec3::Constant(0.1)};
  World world(s);
  world.addMaterial(test::testMaterial(0.5));
  double leavingMass = 0.0;
  for (int i = 0; i < 10; ++i) {
    ParticleSpec p;
    p.radius = 0.001 * (1 + i % 3);
    p.position = Vec3(0.01 * i - 0.05, 0.0, 0.0);
    p.velocity = i % 2 == 0 ? Vec3(0.0, 0.0, 2.0) : Vec3::Zero();  // evens fly out in 0.05 s
    world.addParticle(p);
    if (i % 2 == 0) leavingMass += test::sphereMass(p.radius, 2500.0);
  }
  world.initialize();
  const double massBefore = world.totalMass();
  for (int n = 0; n < 10000; ++n) world.step();
  EXPECT_EQ(world.removedAtBounds().count, 5u);
  EXPECT_NEAR(world.removedAtBounds().mass, leavingMass, 1e-15);
  EXPECT_EQ(world.particles().size(), 5u);
  EXPECT_NEAR(world.totalMass() + world.removedAtBounds().mass, massBefore, 1e-15);
  for (std::uint64_t id : world.particles().id) EXPECT_EQ(id % 2, 0u) << "odd ids (i even) must have left";
}

/// Relative kinetic-energy error after one elastic bounce off a plane.
double bounceEnergyError(IntegratorKind integrator, double dt) {
  SimulationSettings s = test::fineSettings(dt, 1.0);
  s.integrator = integrator;
  s.allow_unsafe_time_step = true;
  World world(s);
  const auto mat = world.addMaterial(test::testMaterial(1.0));
  test::addFloorAndSphere(world, mat, 0.01, Vec3(0.0, 0.0, -1.0), 1e-4);
  world.initialize();
  const double e0 = world.kineticEnergy();
  test::stepUntil(world, [&] { return world.particles().position[0].z() > 0.0102; }, 10'000'000);
  return world.kineticEnergy() / e0 - 1.0;
}

TEST(Integrators, VerletSecondOrderEulerFirstOrderAndGaining) {
  // Hertz contact here lasts ~1.3e-4 s: dt of 1e-6 and 5e-7 give ~130 and ~260 steps.
  const double verletCoarse = std::abs(bounceEnergyError(IntegratorKind::VelocityVerlet, 1e-6));
  const double verletFine = std::abs(bounceEnergyError(IntegratorKind::VelocityVerlet, 5e-7));
  const double eulerCoarse = bounceEnergyError(IntegratorKind::ExplicitEuler, 1e-6);
  const double eulerFine = bounceEnergyError(IntegratorKind::ExplicitEuler, 5e-7);
  EXPECT_GT(eulerCoarse, 0.0) << "explicit Euler adds energy to an oscillator";
  EXPECT_NEAR(eulerCoarse / eulerFine, 2.0, 0.3) << "first order: halving dt halves the error";
  EXPECT_LT(verletCoarse, 0.1 * eulerCoarse);
  EXPECT_GT(verletCoarse / verletFine, 3.0) << "second order: halving dt quarters the error";
}

}  // namespace
}  // namespace demlink::core
