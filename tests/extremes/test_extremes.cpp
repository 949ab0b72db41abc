// The extremes suite: radii 10 um to 1 m, E 1e5 to 1e12 Pa, impacts to 100 m/s,
// mass ratios to 1e6, a 1:10 polydisperse bed, every e at 0.99 of the accepted
// limit with random onset phases, a clump and a moving mesh at the limit, an
// empty world. Each case runs at the accepted time step with the watchdog
// stopping on any fault, and asserts: no NaN, no energy gain beyond 1e-3 for
// e = 1, restitution within 1 % of e, no tunnelling through the plane or mesh.
#include <cmath>
#include <random>
#include <string>

#include <gtest/gtest.h>

#include "test_scenes.hpp"

namespace demlink::core {
namespace {

struct Impact {
  double radius = 0.01;       // [m]
  double youngs = 1e7;        // [Pa]
  double speed = 1.0;         // [m/s]
  double e = 0.5;
  double phase = 0.5;         // onset phase in [0, 1)
  double radius_ratio = 0.0;  // > 0: head-on with a sphere radius_ratio x as large; 0: on a rigid plane
};

Material materialOf(const Impact& c) {
  Material m = test::testMaterial(c.e);
  m.youngs_modulus = c.youngs;
  return m;
}

/// Builds the impact at `dt` (0: probe for the limit), returns the world.
World impactWorld(const Impact& c, double dt) {
  SimulationSettings s = test::fineSettings(dt > 0.0 ? dt : 1e-15, c.speed);
  s.restitution_tolerance = SimulationSettings{}.restitution_tolerance;  // the promise under test
  s.watchdog.every_steps = 1;
  World world(s);
  world.addMaterial(materialOf(c));
  const double gap = (3.0 + c.phase) * c.speed * dt;
  ParticleSpec a;
  a.radius = c.radius;
  if (c.radius_ratio <= 0.0) {
    world.addPlane({"floor", Vec3::Zero(), Vec3::UnitZ(), 0, true});
    a.position = Vec3(0.0, 0.0, c.radius + gap);
    a.velocity = Vec3(0.0, 0.0, -c.speed);
    world.addParticle(a);
  } else {
    ParticleSpec b;
    b.radius = c.radius * c.radius_ratio;
    a.position = Vec3(-c.radius - gap, 0.0, 0.0);
    a.velocity = Vec3(c.speed, 0.0, 0.0);  // b at rest: the relative speed is c.speed
    b.position = Vec3(b.radius, 0.0, 0.0);
    world.addParticle(a);
    world.addParticle(b);
  }
  world.initialize();
  return world;
}

struct Outcome {
  double restitution = 0.0;
  double energy_ratio = 0.0;  // final / initial kinetic energy
  bool tunnelled = false;
};

Outcome run(const Impact& c) {
  const double dt = 0.99 * impactWorld(c, 0.0).timeStepReport().limit;
  World world = impactWorld(c, dt);
  const ParticleArrays& p = world.particles();
  const double before = world.kineticEnergy();
  Outcome out;
  const bool plane = c.radius_ratio <= 0.0;
  const double gap = (3.0 + c.phase) * c.speed * dt;
  for (int n = 0; n < 2'000'000; ++n) {
    world.step();
    if (plane) {
      out.tunnelled = out.tunnelled || p.position[0].z() < 0.0;
      if (p.position[0].z() > c.radius + gap) {
        out.restitution = p.velocity[0].z() / c.speed;
        break;
      }
    } else {
      const double distance = (p.position[1] - p.position[0]).norm();
      out.tunnelled = out.tunnelled || p.position[0].x() > p.position[1].x();
      if (distance > c.radius * (1.0 + c.radius_ratio) + gap) {
        out.restitution = (p.velocity[1].x() - p.velocity[0].x()) / c.speed;
        break;
      }
    }
  }
  out.energy_ratio = world.kineticEnergy() / before;
  EXPECT_TRUE(std::isfinite(out.energy_ratio));
  return out;
}

void expectGood(const Impact& c, const std::string& what) {
  const Outcome o = run(c);
  EXPECT_FALSE(o.tunnelled) << what;
  EXPECT_NEAR(o.restitution / c.e, 1.0, 0.01) << what;
  if (c.e == 1.0) {
    EXPECT_LE(o.energy_ratio, 1.0 + 1e-3) << what;
  }
}

TEST(Extremes, RadiiFromTenMicronsToOneMetre) {
  for (const double r : {1e-5, 1e-3, 1.0}) {
    for (const double e : {0.5, 1.0}) expectGood({.radius = r, .e = e}, "R=" + std::to_string(r));
  }
}

TEST(Extremes, StiffnessFrom1e5To1e12Pa) {
  for (const double youngs : {1e5, 1e9, 1e12}) {
    for (const double e : {0.2, 1.0}) expectGood({.youngs = youngs, .e = e}, "E=" + std::to_string(youngs));
  }
}

TEST(Extremes, ImpactsUpTo100MetresPerSecond) {
  // Stiff enough that 100 m/s does not squash the sphere (E = 10 MPa would: delta/R > 0.5).
  for (const double v : {10.0, 100.0}) {
    for (const double e : {0.5, 1.0}) expectGood({.youngs = 1e10, .speed = v, .e = e}, "v=" + std::to_string(v));
  }
}

TEST(Extremes, MassRatiosUpTo1e6) {
  for (const double ratio : {10.0, 100.0}) {  // radius ratio 100: mass ratio 1e6
    for (const double e : {0.5, 1.0}) {
      expectGood({.e = e, .radius_ratio = ratio}, "radius ratio " + std::to_string(ratio));
    }
  }
}

TEST(Extremes, EveryRestitutionAtTheLimitWithRandomOnsetPhase) {
  std::mt19937_64 rng(6);
  std::uniform_real_distribution<double> uniform(0.0, 1.0);
  for (const double e : {0.1, 0.2, 0.3, 0.5, 0.7, 0.9, 1.0}) {
    for (int k = 0; k < 3; ++k) {
      expectGood({.e = e, .phase = uniform(rng)}, "e=" + std::to_string(e));
      expectGood({.e = e, .phase = uniform(rng), .radius_ratio = 1.0}, "pair e=" + std::to_string(e));
    }
  }
}

TEST(Extremes, PolydisperseBedOneToTenSettlesWithoutFault) {
  SimulationSettings probe = test::fineSettings(1e-15, 2.0);
  probe.gravity = Vec3(0.0, 0.0, -9.81);
  probe.restitution_tolerance = SimulationSettings{}.restitution_tolerance;
  auto build = [&](double dt) {
    SimulationSettings s = probe;
    s.time_step = dt;
    s.watchdog.every_steps = 10;
    World world(s);
    // E = 1 GPa: a 10 mm sphere landing on a 1 mm one pinned to the floor squashes a
    // 10 MPa one by more than its radius (physics, not the step).
    Material grains = test::testMaterial(0.3, 0.5);
    grains.youngs_modulus = 1e9;
    world.addMaterial(grains);
    world.addPlane({"floor", Vec3::Zero(), Vec3::UnitZ(), 0, true});
    std::mt19937_64 rng(10);
    std::uniform_real_distribution<double> radius(0.001, 0.01);
    for (int k = 0; k < 40; ++k) {
      ParticleSpec p;
      p.radius = k < 2 ? (k == 0 ? 0.001 : 0.01) : radius(rng);
      p.position = Vec3(0.025 * (k % 5), 0.025 * ((k / 5) % 2), 0.015 + 0.025 * (k / 10));
      world.addParticle(p);
    }
    world.initialize();
    return world;
  };
  World world = build(0.99 * build(1e-15).timeStepReport().limit);
  const std::uint64_t steps = static_cast<std::uint64_t>(0.15 / world.settings().time_step);
  for (std::uint64_t n = 0; n < steps; ++n) world.step();  // the watchdog throws on any fault
  for (std::size_t i = 0; i < world.particles().size(); ++i) {
    EXPECT_GT(world.particles().position[i].z(), 0.0) << "particle below the floor";
  }
}

TEST(Extremes, ClumpDroppedAtTheLimit) {
  auto build = [&](double dt) {
    SimulationSettings s = test::fineSettings(dt, 2.0);
    s.gravity = Vec3(0.0, 0.0, -9.81);
    s.restitution_tolerance = SimulationSettings{}.restitution_tolerance;
    s.watchdog.every_steps = 1;
    World world(s);
    world.addMaterial(test::testMaterial(0.5, 0.5));
    world.addPlane({"floor", Vec3::Zero(), Vec3::UnitZ(), 0, true});
    const auto shape = world.addClumpTemplate(
        ClumpTemplate("pair", {{Vec3(-0.004, 0, 0), 0.005}, {Vec3(0.004, 0, 0), 0.004}}));
    world.addClump({shape, 0, Vec3(0, 0, 0.05), Quat(Eigen::AngleAxisd(0.3, Vec3::UnitY())), Vec3(0, 0, -1.5)});
    world.initialize();
    return world;
  };
  World world = build(0.99 * build(1e-15).timeStepReport().limit);
  const std::uint64_t steps = static_cast<std::uint64_t>(0.1 / world.settings().time_step);
  for (std::uint64_t n = 0; n < steps; ++n) {
    world.step();
    for (const Vec3& x : world.particles().position) ASSERT_GT(x.z(), 0.0) << "member through the floor";
  }
}

TEST(Extremes, MovingMeshHitsASphereAtTheLimitWithoutTunnelling) {
  // A plate rising at 5 m/s meets a sphere at rest: the speed is seen from the
  // mesh's motion alone (max_impact_velocity left at 0.1).
  auto build = [&](double dt) {
    SimulationSettings s = test::fineSettings(dt, 0.1);
    s.restitution_tolerance = SimulationSettings{}.restitution_tolerance;
    s.watchdog.every_steps = 1;
    World world(s);
    world.addMaterial(test::testMaterial(0.5));
    MeshBody plate("plate", {Vec3(-1, -1, 0), Vec3(1, -1, 0), Vec3(1, 1, 0), Vec3(-1, 1, 0)}, {{0, 1, 2}, {0, 2, 3}},
                   0);
    plate.setVelocity(Vec3(0, 0, 5.0), Vec3::Zero());
    plate.setRigid(true);
    world.addMesh(std::move(plate));
    ParticleSpec p;
    p.radius = 0.01;
    p.position = Vec3(0.1, 0.1, 0.011);
    world.addParticle(p);
    world.initialize();
    return world;
  };
  World probe = build(1e-15);
  EXPECT_DOUBLE_EQ(probe.validatedImpactSpeed(), 5.0);
  World world = build(0.99 * probe.timeStepReport().limit);
  for (int n = 0; n < 5000; ++n) {
    world.step();
    ASSERT_GT(world.particles().position[0].z(), world.meshes()[0].position().z()) << "through the plate";
  }
  // Rebound of a sphere at rest from a rigid plate at 5 m/s: (1 + e) x 5 m/s.
  EXPECT_NEAR(world.particles().velocity[0].z() / (1.5 * 5.0), 1.0, 0.01);
}

TEST(Extremes, EmptyWorldSteps) {
  World world(test::fineSettings(1e-3, 1.0));
  world.addMaterial(test::testMaterial(0.5));
  world.initialize();
  for (int n = 0; n < 100; ++n) world.step();
  EXPECT_EQ(world.stepCount(), 100u);
  EXPECT_EQ(world.kineticEnergy(), 0.0);
}

}  // namespace
}  // namespace demlink::core
