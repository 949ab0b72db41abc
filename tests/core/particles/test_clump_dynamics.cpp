/// Clump rigid-body dynamics: torque-free tumbling against an independent
/// integration of Euler's equations (plus angular momentum and energy), a clump
/// dropped on a plane (no energy gain, comes to rest, members rigid), removal by
/// the domain bounds (whole clump, tally mass = clump mass), the neighbour list
/// (no pairs inside a clump, the clump's mass in contacts) and explicit Euler.
#include <gtest/gtest.h>

#include <cmath>

#include "demlink/core/base/input_error.hpp"
#include "demlink/core/world.hpp"
#include "test_scenes.hpp"

namespace demlink::core {
namespace {

/// Three spheres [m] with three distinct principal moments.
ClumpTemplate asymmetricTemplate() {
  return ClumpTemplate("tri", {{Vec3(0.0, 0.0, 0.0), 0.002},
                               {Vec3(0.0024, 0.0002, 0.0), 0.0014},
                               {Vec3(0.0002, 0.0018, 0.0006), 0.001}});
}

std::vector<double> memberDistances(const World& world, const ClumpBody& body) {
  std::vector<double> d;
  const auto& x = world.particles().position;
  for (std::size_t a = 0; a < body.member_slots.size(); ++a) {
    for (std::size_t b = a + 1; b < body.member_slots.size(); ++b) {
      d.push_back((x[body.member_slots[a]] - x[body.member_slots[b]]).norm());
    }
  }
  return d;
}

/// Euler's equations in the body frame, I w' = (I w) x w, by RK4 with `substeps`.
Vec3 eulerEquations(const Vec3& inertia, Vec3 w, double duration, int substeps) {
  auto rate = [&](const Vec3& v) { return Vec3(inertia.cwiseProduct(v).cross(v).cwiseQuotient(inertia)); };
  const double h = duration / substeps;
  for (int s = 0; s < substeps; ++s) {
    const Vec3 k1 = rate(w);
    const Vec3 k2 = rate(w + 0.5 * h * k1);
    const Vec3 k3 = rate(w + 0.5 * h * k2);
    const Vec3 k4 = rate(w + h * k3);
    w += h / 6.0 * (k1 + 2.0 * k2 + 2.0 * k3 + k4);
  }
  return w;
}

TEST(ClumpDynamics, TorqueFreeTumblingConservesMomentumAndEnergy) {
  SimulationSettings settings = test::fineSettings(1.0e-5, 1.0);
  World world(settings);
  const auto material = world.addMaterial(test::testMaterial(0.5));
  const auto shape = world.addClumpTemplate(asymmetricTemplate());
  ClumpSpec spec;
  spec.template_index = shape;
  spec.material = material;
  spec.orientation = Quat(Eigen::AngleAxisd(0.7, Vec3(1.0, -2.0, 0.5).normalized()));
  spec.angular_velocity = Vec3(40.0, -150.0, 90.0);  // not along a principal axis [rad/s]
  world.addClump(spec);
  world.initialize();
  const ClumpBody& body = world.clumps().front();
  const Vec3 moments = body.inertia;
  ASSERT_GT(moments[1] - moments[0], 0.05 * moments[2]);
  ASSERT_GT(moments[2] - moments[1], 0.05 * moments[2]);

  auto worldMomentum = [&] {
    // From the members' angular velocity and the body pose: L = R I R^T w.
    const Mat3 r = body.orientation.toRotationMatrix();
    const Vec3 w = world.particles().angular_velocity[body.member_slots.front()];
    return Vec3(r * moments.asDiagonal() * r.transpose() * w);
  };
  const Vec3 l0 = worldMomentum();
  const double e0 = world.kineticEnergy();
  const Vec3 w0Body = body.orientation.conjugate() * body.angularVelocity();
  const std::vector<double> d0 = memberDistances(world, body);
  constexpr int kSteps = 20000;  // 0.2 s, about 6 turns
  double worstEnergy = 0.0;
  for (int s = 0; s < kSteps; ++s) {
    world.step();
    worstEnergy = std::max(worstEnergy, std::abs(world.kineticEnergy() - e0) / e0);
  }
  EXPECT_LT((worldMomentum() - l0).norm(), 1e-10 * l0.norm());
  EXPECT_LT(worstEnergy, 1e-9);  // measured 2.4e-13 (RK4 error, |w| dt = 1.8e-3)
  // The body-frame angular velocity follows Euler's equations (independent RK4, 10x finer).
  const Vec3 wBody = body.orientation.conjugate() * body.angularVelocity();
  const Vec3 reference = eulerEquations(moments, w0Body, kSteps * settings.time_step, 10 * kSteps);
  EXPECT_LT((wBody - reference).norm(), 1e-6 * reference.norm());
  EXPECT_GT((wBody - w0Body).norm(), 0.1 * w0Body.norm()) << "the test needs a tumbling body";
  const std::vector<double> d = memberDistances(world, body);
  for (std::size_t k = 0; k < d.size(); ++k) EXPECT_NEAR(d[k], d0[k], 1e-12 * d0[k]);
  // Member velocities are the rigid field v + w x r: central difference of positions.
  const auto& p = world.particles();
  const std::uint32_t slot = body.member_slots.back();
  const Vec3 x0 = p.position[slot];
  const Vec3 v0 = p.velocity[slot];
  world.step();
  const Vec3 x1 = p.position[slot];
  const Vec3 v1 = p.velocity[slot];
  EXPECT_LT(((x1 - x0) / settings.time_step - 0.5 * (v0 + v1)).norm(), 1e-5 * v0.norm());
}

TEST(ClumpDynamics, DroppedClumpComesToRestWithoutEnergyGain) {
  SimulationSettings settings = test::fineSettings(1.5e-5, 1.0);
  settings.gravity = Vec3(0.0, 0.0, -9.81);
  World world(settings);
  const auto material = world.addMaterial(test::testMaterial(0.5, 0.5));
  world.addPlane({"floor", Vec3::Zero(), Vec3::UnitZ(), material});
  ClumpSpec spec;
  spec.template_index = world.addClumpTemplate(asymmetricTemplate());
  spec.material = material;
  spec.position = Vec3(0.0, 0.0, 0.012);
  spec.orientation = Quat(Eigen::AngleAxisd(1.1, Vec3(0.3, 1.0, -0.4).normalized()));
  spec.angular_velocity = Vec3(5.0, -3.0, 8.0);
  world.addClump(spec);
  world.initialize();
  const ClumpBody& body = world.clumps().front();
  const double g = 9.81;
  auto energy = [&] { return world.kineticEnergy() + body.mass * g * body.position.z(); };
  const double e0 = energy();
  const std::vector<double> d0 = memberDistances(world, body);
  double worstGain = 0.0;
  double worstStretch = 0.0;
  for (int s = 0; s < 33000; ++s) {  // 0.5 s
    world.step();
    worstGain = std::max(worstGain, (energy() - e0) / e0);
    const std::vector<double> d = memberDistances(world, body);
    for (std::size_t k = 0; k < d.size(); ++k) worstStretch = std::max(worstStretch, std::abs(d[k] - d0[k]) / d0[k]);
  }
  EXPECT_LT(worstGain, 1e-9);
  EXPECT_LT(worstStretch, 1e-12);
  // At rest: kinetic energy below 1e-8 of the energy the drop released.
  const double released = e0 - energy();
  EXPECT_LT(world.kineticEnergy(), 1e-8 * released);
  // Resting on the floor: the lowest member touches it (overlap below 1% of its radius).
  double lowest = 1.0;
  for (const std::uint32_t slot : body.member_slots) {
    lowest = std::min(lowest, world.particles().position[slot].z() - world.particles().radius[slot]);
  }
  EXPECT_LT(lowest, 0.0);
  EXPECT_GT(lowest, -0.01 * 0.001);
  EXPECT_NEAR(body.force.z(), body.mass * g, 1e-6 * body.mass * g);
}

TEST(ClumpDynamics, BoundsRemoveWholeClumpWithItsMass) {
  SimulationSettings settings = test::fineSettings(1.0e-5, 1.0);
  settings.bounds = DomainBounds{Vec3::Constant(-0.02), Vec3::Constant(0.02)};
  World world(settings);
  const auto material = world.addMaterial(test::testMaterial(0.5));
  const auto shape = world.addClumpTemplate(asymmetricTemplate());
  ClumpSpec leaving;
  leaving.template_index = shape;
  leaving.material = material;
  leaving.position = Vec3(0.015, 0.0, 0.0);
  leaving.velocity = Vec3(1.0, 0.0, 0.0);
  ClumpSpec staying = leaving;
  staying.position = Vec3(-0.01, 0.0, 0.0);
  staying.velocity = Vec3::Zero();
  staying.angular_velocity = Vec3(0.0, 0.0, 30.0);
  world.addClump(staying);  // lower slots: compaction moves the staying clump's members too
  ParticleSpec free;
  free.radius = 0.001;
  free.position = Vec3(0.0, 0.01, 0.0);
  world.addParticle(free);
  const std::uint64_t leavingId = world.addClump(leaving);
  world.initialize();
  const double leavingMass = world.clumps().back().mass;
  const std::size_t members = asymmetricTemplate().spheres().size();
  const std::size_t total = world.particles().size();
  ASSERT_EQ(total, 2 * members + 1);
  const std::vector<double> d0 = memberDistances(world, world.clumps().front());
  // Step until the first member is out; the whole clump must go in that step.
  std::size_t steps = 0;
  while (world.particles().size() == total && steps < 2000) {
    world.step();
    ++steps;
  }
  ASSERT_LT(steps, 2000u);
  EXPECT_EQ(world.particles().size(), members + 1);
  EXPECT_EQ(world.removedAtBounds().count, 1u);
  EXPECT_NEAR(world.removedAtBounds().mass, leavingMass, 1e-14 * leavingMass);
  ASSERT_EQ(world.clumps().size(), 1u);
  EXPECT_NE(world.clumps().front().id, leavingId);
  for (std::size_t i = 0; i < world.particles().size(); ++i) EXPECT_NE(world.particles().clump_id[i], leavingId);
  // The COM of the removed clump was still inside: the rule is "any member out".
  const double comX = 0.015 + static_cast<double>(steps) * settings.time_step;
  EXPECT_LT(comX, 0.02);
  // The remaining clump keeps its shape and keeps spinning after compaction.
  for (int s = 0; s < 100; ++s) world.step();
  const std::vector<double> d = memberDistances(world, world.clumps().front());
  for (std::size_t k = 0; k < d.size(); ++k) EXPECT_NEAR(d[k], d0[k], 1e-12 * d0[k]);
  EXPECT_NEAR(world.totalMass(), world.clumps().front().mass + test::sphereMass(0.001, 2500.0), 1e-12);
}

TEST(ClumpDynamics, NeighbourListSkipsOwnMembersAndUsesClumpMass) {
  World world(test::fineSettings(1.0e-5, 1.0));
  const auto material = world.addMaterial(test::testMaterial(0.5));
  ClumpSpec spec;
  spec.template_index = world.addClumpTemplate(asymmetricTemplate());
  spec.material = material;
  world.addClump(spec);
  ParticleSpec free;
  free.radius = 0.001;
  // Below the first (2 mm) member, overlapping it slightly.
  free.position = world.particles().position[world.clumps().front().member_slots.front()] - Vec3(0.0, 0.0, 0.0029);
  world.addParticle(free);
  world.initialize();
  const auto& p = world.particles();
  const auto offsets = world.neighbourList().offsets();
  const auto partners = world.neighbourList().partners();
  const auto reduced = world.neighbourList().reduced();
  const double clumpMass = world.clumps().front().mass;
  const double sphereMass = test::sphereMass(0.001, 2500.0);
  std::size_t pairsWithFree = 0;
  for (std::size_t i = 0; i < p.size(); ++i) {
    for (std::uint32_t k = offsets[i]; k < offsets[i + 1]; ++k) {
      const std::uint32_t j = partners[k];
      EXPECT_FALSE(p.clump_id[i] != 0 && p.clump_id[i] == p.clump_id[j]) << "pair inside one clump";
      ++pairsWithFree;
      const double expected = clumpMass * sphereMass / (clumpMass + sphereMass);
      EXPECT_NEAR(reduced[k].mass, expected, 1e-12 * expected);
    }
  }
  EXPECT_GE(pairsWithFree, 1u);
  const double membersMass = [&] {
    double m = 0.0;
    for (std::size_t i = 0; i < p.size(); ++i) m += p.clump_id[i] != 0 ? p.mass[i] : 0.0;
    return m;
  }();
  EXPECT_NEAR(membersMass, clumpMass, 1e-12 * clumpMass);
  const auto stages = world.activeStages();
  EXPECT_NE(std::find(stages.begin(), stages.end(), "clump_rigid_bodies"), stages.end());
}

TEST(ClumpDynamics, ExplicitEulerMovesTheBodyLikeASphere) {
  SimulationSettings settings = test::fineSettings(1.0e-5, 1.0);
  settings.integrator = IntegratorKind::ExplicitEuler;
  settings.gravity = Vec3(0.0, 0.0, -9.81);
  settings.allow_unsafe_time_step = true;  // one clump in free flight: no contact to resolve
  World world(settings);
  const auto material = world.addMaterial(test::testMaterial(0.5));
  ClumpSpec spec;
  spec.template_index = world.addClumpTemplate(asymmetricTemplate());
  spec.material = material;
  spec.velocity = Vec3(0.3, 0.0, 1.0);
  spec.angular_velocity = Vec3(0.0, 20.0, 5.0);
  world.addClump(spec);
  world.initialize();
  const Vec3 l0 = world.clumps().front().angular_momentum;
  constexpr int kSteps = 500;
  for (int s = 0; s < kSteps; ++s) world.step();
  // Explicit Euler: x_n = x_0 + v_0 n dt + g dt^2 n (n - 1) / 2.
  const double dt = settings.time_step;
  const Vec3 expected = spec.velocity * (kSteps * dt) + settings.gravity * (dt * dt * kSteps * (kSteps - 1) / 2.0);
  EXPECT_LT((world.clumps().front().position - expected).norm(), 1e-12);
  EXPECT_LT((world.clumps().front().angular_momentum - l0).norm(), 1e-14 * l0.norm());
}

TEST(ClumpDynamics, RejectsBadClumpsNamingTheField) {
  World world(test::fineSettings(1.0e-5, 1.0));
  const auto material = world.addMaterial(test::testMaterial(0.5));
  const auto shape = world.addClumpTemplate(asymmetricTemplate());
  auto expectField = [&](const ClumpSpec& spec, const std::string& field) {
    try {
      world.addClump(spec, "components[4].particle_lattice");
      ADD_FAILURE() << "accepted; expected an error on " << field;
    } catch (const InputError& e) {
      EXPECT_EQ(e.field(), field) << e.what();
    }
  };
  ClumpSpec good;
  good.template_index = shape;
  good.material = material;
  ClumpSpec bad = good;
  bad.template_index = 7;
  expectField(bad, "components[4].particle_lattice.clump_template");
  bad = good;
  bad.material = 3;
  expectField(bad, "components[4].particle_lattice.material");
  bad = good;
  bad.orientation = Quat(0.0, 0.0, 0.0, 0.0);
  expectField(bad, "components[4].particle_lattice.orientation");
  bad = good;
  bad.position = Vec3(0.0, std::nan(""), 0.0);
  expectField(bad, "components[4].particle_lattice.position[1]");
  bad = good;
  bad.angular_velocity = Vec3(std::numeric_limits<double>::infinity(), 0.0, 0.0);
  expectField(bad, "components[4].particle_lattice.angular_velocity[0]");
  try {
    world.addClumpTemplate(asymmetricTemplate(), "components[1].clump_template");
    ADD_FAILURE() << "duplicate template name accepted";
  } catch (const InputError& e) {
    EXPECT_EQ(e.field(), "components[1].clump_template.name");
  }
  EXPECT_EQ(world.particles().size(), 0u);
}

}  // namespace
}  // namespace demlink::core
