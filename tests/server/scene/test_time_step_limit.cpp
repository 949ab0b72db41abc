// The accepted time-step limit keeps its promise, checked as a user would
// through scene files: for e in {0.1, 0.2, 0.5, 0.9}, a sphere on a plane and
// two spheres head-on, at 0.99 of the accepted limit and random contact-onset
// phases, the rebound ratio is within 1 % of e. The compile report names what
// set the limit and prints the calibrated damping.
#include <cmath>
#include <random>
#include <string>

#include <gtest/gtest.h>

#include "scene_test_support.hpp"

namespace demlink::server {
namespace {

constexpr double kRadius = 0.01;  // [m]
constexpr double kSpeed = 1.0;    // [m/s]

std::string number(double x) {
  char text[64];
  std::snprintf(text, sizeof text, "%.17g", x);
  return text;
}

/// Sphere on a plane (onPlane) or two spheres head-on; the contact starts
/// `phase` of a step after the last step without overlap.
v1::Scene impactScene(double e, double dt, double phase, bool onPlane) {
  const double gap = (3.0 + phase) * kSpeed * dt;
  std::vector<std::string> c{
      R"({"name": "box", "simulation_box": {"time_step": )" + number(dt) +
          R"(, "end_time": 1, "gravity": {}, "restitution_tolerance": 0.01, "max_impact_velocity": )" + number(kSpeed) + "}}",
      R"({"name": "glass", "material": {"youngs_modulus": 1e7, "sliding_friction": 0, "restitution": )" +
          number(e) + "}}"};
  auto lattice = [&](const std::string& name, double x, double z, double vx, double vz) {
    return R"({"name": ")" + name + R"(", "particle_lattice": {"material": "glass", "radius": )" + number(kRadius) +
           R"(, "spacing": 1, "counts": {"nx": 1, "ny": 1, "nz": 1}, "origin": {"x": )" + number(x) +
           R"(, "z": )" + number(z) + R"(}, "velocity": {"x": )" + number(vx) + R"(, "z": )" + number(vz) + "}}}";
  };
  if (onPlane) {
    c.push_back(R"({"name": "floor", "plane": {"normal": {"z": 1}, "material": "glass"}})");
    c.push_back(lattice("ball", 0.0, kRadius + gap, 0.0, -kSpeed));
  } else {
    c.push_back(lattice("left", -kRadius - 0.5 * gap, 0.0, 0.5 * kSpeed, 0.0));
    c.push_back(lattice("right", kRadius + 0.5 * gap, 0.0, -0.5 * kSpeed, 0.0));
  }
  return test::sceneOf(c);
}

double acceptedLimit(double e, bool onPlane) {
  TranslatedScene t = translateScene(impactScene(e, 1e-12, 0.0, onPlane), {});
  t.world.initialize();
  return t.world.timeStepReport().limit;
}

double rebound(double e, double dt, double phase, bool onPlane) {
  TranslatedScene t = translateScene(impactScene(e, dt, phase, onPlane), {});
  core::World& w = t.world;
  w.initialize();
  const core::ParticleArrays& p = w.particles();
  const double gap = (3.0 + phase) * kSpeed * dt;
  for (int n = 0; n < 1'000'000; ++n) {
    w.step();
    if (onPlane && p.position[0].z() > kRadius + gap) return p.velocity[0].z() / kSpeed;
    if (!onPlane && (p.position[1] - p.position[0]).norm() > 2.0 * kRadius + gap) {
      return std::abs(p.velocity[1].x() - p.velocity[0].x()) / kSpeed;
    }
  }
  return 0.0;
}

TEST(TimeStepLimit, RestitutionWithinOnePercentAtTheLimitForAnyOnsetPhase) {
  std::mt19937_64 rng(13);
  std::uniform_real_distribution<double> uniform(0.0, 1.0);
  for (const bool onPlane : {true, false}) {
    for (const double e : {0.1, 0.2, 0.5, 0.9}) {
      const double dt = 0.99 * acceptedLimit(e, onPlane);
      double worst = 0.0;
      for (int k = 0; k < 6; ++k) {
        const double got = rebound(e, dt, uniform(rng), onPlane);
        worst = std::max(worst, std::abs(got - e) / e);
      }
      EXPECT_LE(worst, 0.01) << (onPlane ? "sphere on plane" : "sphere pair") << " e=" << e << " dt=" << dt;
    }
  }
}

TEST(TimeStepLimit, ReportNamesTheLimitAndTheDamping) {
  TranslatedScene t = translateScene(impactScene(0.2, 1e-12, 0.0, true), {});
  t.world.initialize();
  const core::TimeStepReport& r = t.world.timeStepReport();
  EXPECT_EQ(r.limited_by, "restitution glass/glass (e = 0.2)");
  ASSERT_EQ(r.damping.size(), 1u);
  EXPECT_NEAR(r.damping[0].beta, -r.damping[0].damping_coefficient / std::sqrt(5.0), 1e-15);
  std::string text;
  for (const std::string& line : r.describe()) text += line + "\n";
  EXPECT_NE(text.find("limited by restitution glass/glass"), std::string::npos) << text;
  EXPECT_NE(text.find("beta = "), std::string::npos) << text;
  EXPECT_NE(text.find("rayleigh"), std::string::npos) << text;
}

TEST(TimeStepLimit, ToleranceIsValidatedAndLoosensTheLimit) {
  v1::Scene scene = impactScene(0.2, 1e-12, 0.0, true);
  scene.mutable_components(0)->mutable_simulation_box()->set_restitution_tolerance(0.0);
  EXPECT_EQ(test::errorFieldAfterInitialize(scene), "components[0].simulation_box.restitution_tolerance");
  scene.mutable_components(0)->mutable_simulation_box()->set_restitution_tolerance(0.05);
  TranslatedScene t = translateScene(scene, {});
  t.world.initialize();
  EXPECT_GT(t.world.timeStepReport().limit, 2.0 * acceptedLimit(0.2, true));
}

// One default everywhere: a scene file or client that omits the tolerance gets the
// engine's 1 %, and the limit it computes is the one the accuracy test above checks.
TEST(TimeStepLimit, ASceneThatOmitsTheToleranceGetsOnePercent) {
  v1::Scene scene = impactScene(0.2, 1e-12, 0.0, true);
  scene.mutable_components(0)->mutable_simulation_box()->clear_restitution_tolerance();
  TranslatedScene t = translateScene(scene, {});
  EXPECT_EQ(t.world.settings().restitution_tolerance, 0.01);
  t.world.initialize();
  EXPECT_NEAR(t.world.timeStepReport().limit / acceptedLimit(0.2, true), 1.0, 1e-12);
}

// The strict policy from a scene file: a sphere falling past the declared impact speed
// stops the run by name at the first watchdog check beyond it (0.1 m/s after ~1.03e-2 s).
TEST(TimeStepLimit, StrictSpeedPolicyStopsAFasterParticleNamingIt) {
  const v1::Scene scene = test::sceneOf(
      {R"({"name": "box", "simulation_box": {"time_step": 1e-5, "end_time": 1, "max_impact_velocity": 0.1,
           "watchdog": {"every_steps": 10, "speed_policy": "STOP"}}})",
       R"({"name": "glass", "material": {"youngs_modulus": 1e7}})",
       R"({"name": "ball", "particle_lattice": {"material": "glass", "radius": 0.01, "spacing": 1,
           "counts": {"nx": 1, "ny": 1, "nz": 1}}})"});
  TranslatedScene t = translateScene(scene, {});
  t.world.initialize();
  try {
    for (int k = 0; k < 2000; ++k) t.world.step();
    FAIL() << "no stop; speed " << t.world.particles().velocity[0].norm() << " m/s";
  } catch (const core::SimulationFault& fault) {
    EXPECT_EQ(fault.check(), "speed");
    EXPECT_NE(std::string(fault.what()).find("particle 1 moves at"), std::string::npos) << fault.what();
    EXPECT_NEAR(t.world.time(), 0.0103, 2e-4);
  }
}

}  // namespace
}  // namespace demlink::server
