/// Parallel bonds (Potyondy and Cundall 2004) against closed forms: the axial vibration
/// of a bonded pair, a bonded cantilever against Euler-Bernoulli, breaking at the tensile
/// and shear strength, energy conservation, the time-step limit, and bit-identical
/// checkpoint round trips.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numbers>
#include <random>
#include <sstream>
#include <vector>

#include "bonds/bond_test_scenes.hpp"
#include "demlink/core/base/input_error.hpp"

namespace demlink::core {
namespace {

using test::addSphere;
using test::bondProperties;
using test::bondSettings;
using test::kBondGap;
using test::kBondRadius;

constexpr double kSpacing = 2.0 * kBondRadius + kBondGap;  // centre distance of bonded neighbours [m]

double axialStiffness(const ParallelBondProperties& p) {
  return p.normal_stiffness_per_area * std::numbers::pi * kBondRadius * kBondRadius;  // kn A [N/m]
}

/// Drives the particle in `slot` for the next step: sets its velocity and spin so that after
/// the step's first half kick (which adds (F / m + g) dt / 2, and T / I dt / 2) they are
/// `velocity` and `spin`, the values its drift and the bonds see.
void driveNextStep(World& world, std::size_t slot, const Vec3& velocity, const Vec3& spin) {
  ParticleArrays& p = world.particles();
  const double h = 0.5 * world.settings().time_step;
  p.velocity[slot] = velocity - (p.force[slot] * p.inv_mass[slot] + world.gravity()) * h;
  p.angular_velocity[slot] = spin - p.torque[slot] * p.inv_inertia[slot] * h;
}

TEST(ParallelBond, PairVibratesAxiallyAtSqrtOfKOverReducedMass) {
  const ParallelBondProperties props = bondProperties();
  const double m = test::sphereMassOf(kBondRadius);
  const double omega = std::sqrt(axialStiffness(props) / (0.5 * m));  // reduced mass m/2
  const double period = 2.0 * std::numbers::pi / omega;
  World world(bondSettings(period / 200.0));
  world.addMaterial(test::bondedMaterial());
  const double v0 = 1.0e-3;  // amplitude 2 v0 / omega = 8 nm: the gap never closes
  addSphere(world, Vec3::Zero(), Vec3(-v0, 0.0, 0.0));
  addSphere(world, Vec3(kSpacing, 0.0, 0.0), Vec3(v0, 0.0, 0.0));
  world.addBondRule(test::everywhere(props));
  world.step();  // the bond is made at the end of the first step, carrying nothing
  ASSERT_EQ(world.bonds().counts().intact, 1u);
  const auto distance = [&] { return (world.particles().position[1] - world.particles().position[0]).norm(); };
  const double rest = distance();
  std::vector<double> crossings;  // upward zero crossings of the stretch, interpolated
  double previous = 0.0;
  for (int n = 1; n <= 2000; ++n) {  // 10 periods
    world.step();
    const double stretch = distance() - rest;
    if (previous < 0.0 && stretch >= 0.0) crossings.push_back(world.time() - world.settings().time_step * stretch / (stretch - previous));
    previous = stretch;
  }
  ASSERT_GE(crossings.size(), 9u);
  const double measured = (crossings.back() - crossings.front()) / static_cast<double>(crossings.size() - 1);
  // Velocity Verlet at 200 steps a period shifts the period by (omega dt)^2 / 24 = 4e-5.
  EXPECT_NEAR(measured / period, 1.0, 1.0e-3) << "measured " << measured << " s, 2 pi sqrt(mu / k) = " << period;
  std::printf("axial period %.9g s, closed form %.9g s, ratio %.6f\n", measured, period, measured / period);
}

TEST(ParallelBond, CantileverUnderNodeLoadsDeflectsAsEulerBernoulli) {
  // A row of N + 1 bonded spheres along x, the first clamped (held in place, no spin),
  // each free sphere loaded by its weight m g (gravity along -y). Euler-Bernoulli with
  // E = kn L (L the bond length) and I = pi Rb^4 / 4, superposed point loads P at x_i:
  //   tip deflection = sum_i P x_i^2 (3 l - x_i) / (6 E I),  l = N L.
  // The bonded row is a beam discretised with one bond per element: its bending follows
  // exactly (the moment is linear along an element), while the shear compliance of the
  // bonds and the trapezoidal integration of the slope add O(1/N^2): below 0.5 % at N = 10
  // ((1/4 + 3 kn / (16 ks)) / N^2). Tolerance 1 %. The load is applied at once and the
  // swing is damped by a velocity drag added by the test (the bonds are undamped); the
  // clamp holds the root's half-step velocity and spin at zero (driveNextStep).
  const int bonds = 10;
  const ParallelBondProperties props = bondProperties();
  const double m = test::sphereMassOf(kBondRadius);
  const double g = 9.81;
  SimulationSettings settings = bondSettings(1.0e-6);
  settings.gravity = Vec3(0.0, -g, 0.0);
  settings.watchdog.every_steps = 0;  // the test's clamp and drag take energy out
  World world(settings);
  world.addMaterial(test::bondedMaterial());
  std::vector<std::uint64_t> ids;
  for (int i = 0; i <= bonds; ++i) ids.push_back(addSphere(world, Vec3(kSpacing * i, 0.0, 0.0)));
  world.addBondRule(test::everywhere(props));
  const double length = kSpacing;
  const double youngs = props.normal_stiffness_per_area * length;
  const double inertia = std::numbers::pi * std::pow(kBondRadius, 4) / 4.0;
  const double ei = youngs * inertia;
  const double span = bonds * length;
  double expected = 0.0;
  for (int i = 1; i <= bonds; ++i) {
    const double x = i * length;
    expected += m * g * x * x * (3.0 * span - x) / (6.0 * ei);
  }
  const double mu = m / length;  // mass per length
  const double omega1 = 1.875104 * 1.875104 * std::sqrt(ei / (mu * std::pow(span, 4)));
  const double drag = 2.0 * 0.7 * omega1;  // damping ratio 0.7 in the first mode [1/s]
  const double dt = settings.time_step;
  ParticleArrays& p = world.particles();
  const Vec3 root = Vec3::Zero();
  const int steps = static_cast<int>(30.0 * 2.0 * std::numbers::pi / omega1 / dt);
  for (int n = 0; n < steps; ++n) {
    driveNextStep(world, test::slotOf(world, ids.front()), Vec3::Zero(), Vec3::Zero());
    world.step();
    for (std::size_t i = 0; i < p.size(); ++i) {
      if (p.id[i] == ids.front()) {
        ASSERT_EQ(p.position[i], root) << "the root is held";
      } else {
        p.velocity[i] *= 1.0 - drag * dt;
        p.angular_velocity[i] *= 1.0 - drag * dt;
      }
    }
  }
  ASSERT_EQ(world.bonds().counts().intact, static_cast<std::uint64_t>(bonds));
  const double tip = -p.position[test::slotOf(world, ids.back())].y();
  EXPECT_NEAR(tip / expected, 1.0, 0.01) << "tip " << tip << " m, Euler-Bernoulli " << expected << " m";
  std::printf("cantilever tip %.6g m, Euler-Bernoulli %.6g m, ratio %.5f\n", tip, expected, tip / expected);
}

/// Pulls (or shears) a bonded pair apart at a constant relative speed `speed` along
/// `direction` (driveNextStep) until the bond breaks;
/// returns the largest force the particles felt.
double largestForceUntilBreak(const ParallelBondProperties& props, const Vec3& direction, double speed, double dt) {
  SimulationSettings settings = bondSettings(dt);
  settings.watchdog.every_steps = 0;  // the test drives the pair
  World world(settings);
  world.addMaterial(test::bondedMaterial());
  const std::uint64_t first = addSphere(world, Vec3::Zero());
  const std::uint64_t second = addSphere(world, Vec3(kSpacing, 0.0, 0.0));
  world.addBondRule(test::everywhere(props));
  world.step();
  double largest = 0.0;
  ParticleArrays& p = world.particles();
  for (int n = 0; n < 1000000 && world.bonds().counts().broken == 0; ++n) {
    for (std::size_t i = 0; i < 2; ++i) {
      driveNextStep(world, i, (p.id[i] == first ? -0.5 : 0.5) * speed * direction, Vec3::Zero());
    }
    world.step();
    largest = std::max(largest, p.force[test::slotOf(world, second)].norm());
  }
  EXPECT_EQ(world.bonds().counts().broken, 1u);
  EXPECT_EQ(world.bonds().counts().intact, 0u);
  EXPECT_EQ(p.force[0].norm(), 0.0) << "a broken bond loads nothing";
  return largest;
}

TEST(ParallelBond, PulledApartBreaksAtItsTensileStrength) {
  ParallelBondProperties props = bondProperties();
  props.tensile_strength = 5.0e6;  // [Pa]
  const double area = std::numbers::pi * kBondRadius * kBondRadius;
  const double load = props.tensile_strength * area;
  // 1e5 steps to the break: each step adds 1e-5 of the load.
  const double dt = 1.0e-7;
  const double speed = load / axialStiffness(props) / (1.0e5 * dt);
  const double largest = largestForceUntilBreak(props, Vec3::UnitX(), speed, dt);
  EXPECT_NEAR(largest / load, 1.0, 1.0e-3) << "largest " << largest << " N, sigma_t A = " << load << " N";
  std::printf("tensile break at %.9g N, sigma_t A = %.9g N, ratio %.7f\n", largest, load, largest / load);
}

TEST(ParallelBond, ShearedBreaksAtItsShearStrength) {
  ParallelBondProperties props = bondProperties();
  props.shear_strength = 5.0e6;  // [Pa]
  const double area = std::numbers::pi * kBondRadius * kBondRadius;
  const double load = props.shear_strength * area;
  const double dt = 1.0e-7;
  const double speed = load / axialStiffness(props) / (1.0e5 * dt);
  // Sheared along y with the spheres' spin held at zero, the shear force also bends the
  // bond (|Mb| R / I grows with it) but the tensile strength is out of reach.
  const double largest = largestForceUntilBreak(props, Vec3::UnitY(), speed, dt);
  EXPECT_NEAR(largest / load, 1.0, 1.0e-3) << "largest " << largest << " N, tau_c A = " << load << " N";
}

/// Four spheres on a tetrahedron, bonded on its six edges, with random velocities and
/// spins: every mode of the bond (axial, shear, twist, bending) is excited.
World tetrahedron(double dt, const ParallelBondProperties& props, double speed) {
  SimulationSettings settings = bondSettings(dt);
  settings.max_impact_velocity = 10.0 * speed;
  World world(settings);
  world.addMaterial(test::bondedMaterial());
  const double a = kSpacing;
  const std::vector<Vec3> corners{Vec3::Zero(), Vec3(a, 0.0, 0.0), Vec3(0.5 * a, std::sqrt(3.0) / 2.0 * a, 0.0),
                                  Vec3(0.5 * a, std::sqrt(3.0) / 6.0 * a, std::sqrt(2.0 / 3.0) * a)};
  std::mt19937_64 random(7);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  const auto draw = [&](double scale) -> Vec3 {
    const Vec3 direction(unit(random), unit(random), unit(random));
    return scale * direction;
  };
  for (const Vec3& x : corners) addSphere(world, x, draw(speed), draw(speed / kBondRadius));
  world.addBondRule(test::everywhere(props));
  return world;
}

TEST(ParallelBond, UndampedBondsConserveKineticPlusStrainEnergy) {
  const ParallelBondProperties props = bondProperties();
  const double m = test::sphereMassOf(kBondRadius);
  const double period = 2.0 * std::numbers::pi / std::sqrt(axialStiffness(props) / (0.5 * m));
  World world = tetrahedron(period / 200.0, props, 1.0e-3);
  world.step();
  ASSERT_EQ(world.bonds().counts().intact, 6u);
  const auto energy = [&] { return world.kineticEnergy() + world.bonds().strainEnergy(world.particles()); };
  const double start = energy();
  double largestStrain = 0.0;
  double worst = 0.0;
  for (int n = 0; n < 20000; ++n) {  // 100 axial periods
    world.step();
    worst = std::max(worst, std::abs(energy() - start) / start);
    largestStrain = std::max(largestStrain, world.bonds().strainEnergy(world.particles()) / start);
  }
  ASSERT_GT(largestStrain, 0.1) << "the bonds must store a fair share of the energy";
  // Velocity Verlet keeps the energy within O((omega dt)^2) = 1e-3 of its start.
  EXPECT_LT(worst, 2.0e-3) << "energy drifted by " << worst << " of its start";
  std::printf("tetrahedron: energy within %.3g of its start over 100 periods\n", worst);
}

TEST(ParallelBond, BreakingReleasesNoEnergy) {
  ParallelBondProperties props = bondProperties();
  props.tensile_strength = 2.0e5;
  props.shear_strength = 2.0e5;
  const double m = test::sphereMassOf(kBondRadius);
  const double period = 2.0 * std::numbers::pi / std::sqrt(axialStiffness(props) / (0.5 * m));
  World world = tetrahedron(period / 200.0, props, 0.5);
  world.step();
  ASSERT_EQ(world.bonds().counts().intact, 6u);
  const auto energy = [&] { return world.kineticEnergy() + world.bonds().strainEnergy(world.particles()); };
  const double start = energy();
  double largest = start;
  for (int n = 0; n < 20000; ++n) {
    world.step();
    largest = std::max(largest, energy());
  }
  ASSERT_GT(world.bonds().counts().broken, 0u) << "the test needs bonds that break";
  // Within the integrator's O((omega dt)^2) energy error.
  EXPECT_LT(largest, start * (1.0 + 2.0e-3)) << "energy grew from " << start << " J to " << largest << " J";
  std::printf("breaking: %llu bonds broke, energy %.6g J -> largest %.6g J, final %.6g J\n",
              static_cast<unsigned long long>(world.bonds().counts().broken), start, largest, energy());
}

TEST(ParallelBond, CriticalTimeStepNamesTheBondsAndBoundsAPairsStability) {
  const ParallelBondProperties props = bondProperties();
  const double m = test::sphereMassOf(kBondRadius);
  const double k = axialStiffness(props);
  const auto build = [&](double dt) {
    SimulationSettings settings = bondSettings(dt);
    settings.watchdog.every_steps = 0;
    auto world = std::make_unique<World>(settings);
    world->addMaterial(test::bondedMaterial());
    addSphere(*world, Vec3::Zero(), Vec3(-0.01, 0.0, 0.0));
    addSphere(*world, Vec3(kSpacing, 0.0, 0.0), Vec3(0.01, 0.0, 0.0));
    world->addBondRule(test::everywhere(props));
    return world;
  };
  // The limits in the report, named after the rule.
  auto probe = build(1.0e-9);
  probe->initialize();
  double axial = 0.0;
  double rotational = 0.0;
  for (const TimeStepConstraint& c : probe->timeStepReport().constraints) {
    if (c.name == "parallel_bonds cement axial") axial = c.limit;
    if (c.name == "parallel_bonds cement rotational") rotational = c.limit;
  }
  ASSERT_GT(axial, 0.0);
  ASSERT_GT(rotational, 0.0);
  EXPECT_EQ(probe->timeStepReport().limited_by, "parallel_bonds cement rotational");
  // A bonded pair alone is stable up to dt = 2 / omega = sqrt(2 m / k): the limit lies below.
  const double pairLimit = std::sqrt(2.0 * m / k);
  EXPECT_LT(axial, pairLimit);
  // A step above the limit is refused, naming the bond constraint.
  try {
    build(1.01 * rotational)->initialize();
    ADD_FAILURE() << "a step above the bond limit was accepted";
  } catch (const InputError& error) {
    EXPECT_NE(std::string(error.what()).find("parallel_bonds cement rotational"), std::string::npos) << error.what();
  }
  // The pair's axial vibration: bounded at the limit, unstable just beyond the pair's own limit.
  const auto growth = [&](double dt) {
    SimulationSettings settings = bondSettings(dt);
    settings.allow_unsafe_time_step = true;
    settings.watchdog.every_steps = 0;
    World world(settings);
    world.addMaterial(test::bondedMaterial());
    addSphere(world, Vec3::Zero(), Vec3(-0.01, 0.0, 0.0));
    addSphere(world, Vec3(kSpacing, 0.0, 0.0), Vec3(0.01, 0.0, 0.0));
    world.addBondRule(test::everywhere(props));
    world.step();
    const double start = world.kineticEnergy() + world.bonds().strainEnergy(world.particles());
    double largest = start;
    for (int n = 0; n < 200; ++n) {
      world.step();
      largest = std::max(largest, world.kineticEnergy() + world.bonds().strainEnergy(world.particles()));
    }
    return largest / start;
  };
  EXPECT_LT(growth(axial), 1.1);
  EXPECT_GT(growth(1.05 * pairLimit), 1.0e3);
}

/// A bonded 3 x 3 x 3 block thrown at a floor, its spheres rattling: some bonds break;
/// slots are re-sorted at every neighbour build.
World thrownBlock() {
  SimulationSettings settings = bondSettings(2.0e-7);
  settings.max_impact_velocity = 2.0;
  settings.sort_every_builds = 1;
  settings.neighbour_skin = 2.0e-5;  // [m]: rebuilt (and re-sorted) every few tens of steps
  World world(settings);
  const std::uint32_t rock = world.addMaterial(test::bondedMaterial());
  world.addPlane({"floor", Vec3::Zero(), Vec3::UnitZ(), rock});
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 3; ++j) {
      for (int k = 0; k < 3; ++k) {
        // The block's motion plus a rattle of its spheres that breaks some of its bonds.
        const double phase = i + 2.0 * j + 3.0 * k;
        const Vec3 rattle(std::sin(phase), std::cos(1.7 * phase), std::sin(2.3 * phase));
        addSphere(world, Vec3(kSpacing * i, kSpacing * j, kBondRadius + 2.0e-5 + kSpacing * k),
                  Vec3(0.3, 0.0, -1.0) + 0.2 * rattle);
      }
    }
  }
  ParallelBondProperties props = bondProperties(1.0e10, 1.0e10);
  props.tensile_strength = 6.0e4;
  props.shear_strength = 6.0e4;
  world.addBondRule(test::everywhere(props));
  return world;
}

/// A bonded n x n x n block of spheres on `threads` DEM threads, its spheres rattling
/// apart so that some of its bonds break (no floor, no gravity).
World rattledBlock(int n, std::uint32_t threads) {
  SimulationSettings settings = bondSettings(2.0e-7);
  settings.max_impact_velocity = 2.0;
  settings.threads = threads;
  World world(settings);
  world.addMaterial(test::bondedMaterial());
  for (int i = 0; i < n; ++i) {
    for (int j = 0; j < n; ++j) {
      for (int k = 0; k < n; ++k) {
        const double phase = i + 2.0 * j + 3.0 * k;
        const Vec3 rattle(std::sin(phase), std::cos(1.7 * phase), std::sin(2.3 * phase));
        addSphere(world, Vec3(kSpacing * i, kSpacing * j, kSpacing * k), 0.3 * rattle, 50.0 * rattle);
      }
    }
  }
  ParallelBondProperties props = bondProperties(1.0e10, 1.0e10);
  props.tensile_strength = 6.0e4;
  props.shear_strength = 6.0e4;
  world.addBondRule(test::everywhere(props));
  return world;
}

TEST(ParallelBond, BondStageGivesTheSameBitsOnAnyThreadCount) {
  // The bonds advance in chunks over the pool and their loads are added in bond order
  // afterwards: 1, 2 and 3 threads end in the same bits, particles and bonds.
  // 8^3 spheres carry 1,344 bonds: several chunks of the stage's loop.
  ASSERT_GE(maxThreads(), 2u);
  std::vector<World> worlds;
  for (std::uint32_t threads = 1; threads <= 3; ++threads) {
    worlds.push_back(rattledBlock(8, std::min(threads, maxThreads())));
    worlds.back().advance(400);
  }
  const World& one = worlds[0];
  ASSERT_GT(one.bonds().bonds().size(), 1024u) << "the test needs several chunks of bonds";
  ASSERT_GT(one.bonds().counts().broken, 0u) << "the test needs bonds that break";
  ASSERT_GT(one.bonds().counts().intact, 0u) << "and bonds that hold";
  std::printf("rattled block: %llu intact, %llu broken bonds\n",
              static_cast<unsigned long long>(one.bonds().counts().intact),
              static_cast<unsigned long long>(one.bonds().counts().broken));
  for (std::size_t t = 1; t < worlds.size(); ++t) {
    const World& other = worlds[t];
    EXPECT_EQ(other.bonds().counts().broken, one.bonds().counts().broken) << t + 1 << " threads";
    const ParticleArrays& p = one.particles();
    const ParticleArrays& q = other.particles();
    ASSERT_EQ(p.size(), q.size());
    std::size_t differing = 0;
    for (std::size_t i = 0; i < p.size(); ++i) {
      differing += p.position[i] != q.position[i] || p.angular_velocity[i] != q.angular_velocity[i] ||
                   p.force[i] != q.force[i] || p.torque[i] != q.torque[i];
    }
    EXPECT_EQ(differing, 0u) << t + 1 << " threads: particles in other bits than on one";
    for (std::size_t k = 0; k < one.bonds().bonds().size(); ++k) {
      const ParallelBond& a = one.bonds().bonds()[k];
      const ParallelBond& b = other.bonds().bonds()[k];
      ASSERT_TRUE(a.broken == b.broken && a.normal_force == b.normal_force && a.shear_force == b.shear_force &&
                  a.bending_moment == b.bending_moment && a.twisting_moment == b.twisting_moment)
          << t + 1 << " threads: bond " << k;
    }
  }
}

TEST(ParallelBond, CheckpointRoundTripContinuesBitIdentically) {
  World uninterrupted = thrownBlock();
  uninterrupted.advance(600);
  std::ostringstream middle;
  uninterrupted.saveCheckpoint(middle);
  uninterrupted.advance(1400);
  ASSERT_GT(uninterrupted.bonds().counts().broken, 0u) << "the test needs broken bonds";
  ASSERT_GT(uninterrupted.bonds().counts().intact, 0u) << "and intact ones";
  ASSERT_GT(uninterrupted.neighbourList().buildCount(), 2u) << "and re-sorted slots";
  std::printf("thrown block: %llu intact, %llu broken bonds, %llu neighbour builds\n",
              static_cast<unsigned long long>(uninterrupted.bonds().counts().intact),
              static_cast<unsigned long long>(uninterrupted.bonds().counts().broken),
              static_cast<unsigned long long>(uninterrupted.neighbourList().buildCount()));

  World restored = thrownBlock();
  restored.restoreCheckpoint(middle.str(), "middle");
  restored.advance(1400);
  std::ostringstream a;
  std::ostringstream b;
  uninterrupted.saveCheckpoint(a);
  restored.saveCheckpoint(b);
  EXPECT_TRUE(a.str() == b.str()) << "the continued run differs from the uninterrupted one";
  const ParticleArrays& p = uninterrupted.particles();
  const ParticleArrays& q = restored.particles();
  ASSERT_EQ(p.size(), q.size());
  for (std::size_t i = 0; i < p.size(); ++i) EXPECT_EQ(p.position[i], q.position[i]) << "slot " << i;
}

TEST(ParallelBond, BondsFollowTheirParticlesThroughReSorting) {
  // Bonds are kept by particle ids: after re-sorting the slots every build, each bond's
  // slots still hold its particles.
  World world = thrownBlock();
  world.advance(2000);
  const ParticleArrays& p = world.particles();
  for (const ParallelBond& bond : world.bonds().bonds()) {
    EXPECT_EQ(p.id[bond.slot_a], bond.id_a);
    EXPECT_EQ(p.id[bond.slot_b], bond.id_b);
  }
  EXPECT_GT(world.bonds().bonds().size(), 0u);
}

TEST(ParallelBond, RestoreRefusesAFileWithoutTheScenesBonds) {
  World plain(bondSettings(2.0e-7));
  plain.addMaterial(test::bondedMaterial());
  addSphere(plain, Vec3::Zero());
  plain.step();
  std::ostringstream file;
  plain.saveCheckpoint(file);
  World bonded(bondSettings(2.0e-7));
  bonded.addMaterial(test::bondedMaterial());
  addSphere(bonded, Vec3::Zero());
  bonded.addBondRule(test::everywhere(bondProperties()));
  EXPECT_THROW(bonded.restoreCheckpoint(file.str(), "plain"), InputError);
}

TEST(ParallelBond, RuleFieldsAreValidatedByName) {
  const auto refused = [](const std::function<void(BondRule&)>& spoil) {
    World world(bondSettings(1.0e-7));
    world.addMaterial(test::bondedMaterial());
    BondRule rule = test::everywhere(bondProperties());
    spoil(rule);
    try {
      world.addBondRule(rule, "bonds");
    } catch (const InputError& error) {
      return error.field();
    }
    return std::string("(accepted)");
  };
  EXPECT_EQ(refused([](BondRule& r) { r.properties.radius_multiplier = 0.0; }), "bonds.radius_multiplier");
  EXPECT_EQ(refused([](BondRule& r) { r.properties.radius_multiplier = 1.5; }), "bonds.radius_multiplier");
  EXPECT_EQ(refused([](BondRule& r) { r.properties.normal_stiffness_per_area = -1.0; }),
            "bonds.normal_stiffness_per_area");
  EXPECT_EQ(refused([](BondRule& r) { r.properties.shear_stiffness_per_area = 0.0; }), "bonds.shear_stiffness_per_area");
  EXPECT_EQ(refused([](BondRule& r) { r.properties.tensile_strength = NAN; }), "bonds.tensile_strength");
  EXPECT_EQ(refused([](BondRule& r) { r.properties.shear_strength = 0.0; }), "bonds.shear_strength");
  EXPECT_EQ(refused([](BondRule& r) { r.properties.gap_tolerance = -1.0e-6; }), "bonds.gap_tolerance");
  EXPECT_EQ(refused([](BondRule& r) { r.fraction = 0.0; }), "bonds.fraction");
  EXPECT_EQ(refused([](BondRule& r) { r.materials = {3}; }), "bonds.materials[0]");
  EXPECT_EQ(refused([](BondRule&) {}), "(accepted)");
}

TEST(ParallelBond, RegionMaterialsAndFractionChooseThePairs) {
  // A row of 11 spheres: 10 candidate pairs.
  const auto made = [](const std::function<void(BondRule&)>& choose) {
    World world(bondSettings(1.0e-7));
    world.addMaterial(test::bondedMaterial());
    Material other = test::bondedMaterial();
    other.name = "other";
    world.addMaterial(other);
    for (int i = 0; i <= 10; ++i) {
      ParticleSpec s;
      s.radius = kBondRadius;
      s.position = Vec3(kSpacing * i, 0.0, 0.0);
      s.material = i < 6 ? 0 : 1;  // spheres 0-5 of rock, 6-10 of other
      world.addParticle(s);
    }
    BondRule rule = test::everywhere(bondProperties());
    choose(rule);
    world.addBondRule(rule);
    world.step();
    return world.bonds().counts().intact;
  };
  EXPECT_EQ(made([](BondRule&) {}), 10u);
  EXPECT_EQ(made([](BondRule& r) { r.materials = {0}; }), 5u);  // pairs 0-1 ... 4-5
  EXPECT_EQ(made([](BondRule& r) { r.materials = {1}; }), 4u);  // pairs 6-7 ... 9-10
  EXPECT_EQ(made([](BondRule& r) {
              r.region = VolumeShape::box(Vec3(3.5 * kSpacing, 1.0, 1.0), "region");  // centres 0 .. 1.75 spacings
              r.placement.centre = Vec3::Zero();
            }),
            1u);
  EXPECT_EQ(made([](BondRule& r) { r.properties.gap_tolerance = 0.5 * kBondGap; }), 0u);
  const std::uint64_t some = made([](BondRule& r) { r.fraction = 0.5; });
  EXPECT_GT(some, 0u);
  EXPECT_LT(some, 10u);
}

TEST(ParallelBond, BondStageRunsOnlyInScenesWithBonds) {
  World plain(bondSettings(1.0e-7));
  plain.addMaterial(test::bondedMaterial());
  addSphere(plain, Vec3::Zero());
  plain.initialize();
  const std::vector<std::string> without = plain.activeStages();
  EXPECT_EQ(std::find(without.begin(), without.end(), "parallel_bonds"), without.end());
  World bonded(bondSettings(1.0e-7));
  bonded.addMaterial(test::bondedMaterial());
  addSphere(bonded, Vec3::Zero());
  bonded.addBondRule(test::everywhere(bondProperties()));
  bonded.initialize();
  const std::vector<std::string> with = bonded.activeStages();
  EXPECT_NE(std::find(with.begin(), with.end(), "parallel_bonds"), with.end());
}

}  // namespace
}  // namespace demlink::core
