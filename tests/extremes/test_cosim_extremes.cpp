// Co-simulation at the extremes of the communication interval: one step, and 10^4
// steps. A client holds a plate still while a sphere hits it at the accepted time step
// (0.99 of the limit, the default 1 % restitution tolerance); every package the client
// receives is finite, the sphere rebounds at e within 1 %, and the plate's impulse
// (the sum of mean_force × interval) is the sphere's momentum change m·v·(1 + e). A
// client that drives the plate far beyond its declared speed over a 10^4-step interval
// stops the run with a named watchdog Error and never receives a NaN.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <string>

#include "cosim_test_support.hpp"
#include "demlink/server/cosim/cosim_simulation.hpp"

namespace demlink::server::test {
namespace {

constexpr double kRadius = 0.002;     // [m]
constexpr double kDensity = 2500.0;   // [kg/m^3]
constexpr double kSpeed = 1.0;        // impact speed [m/s]
constexpr double kRestitution = 0.5;  // [-]

std::string number(double x) {
  char text[64];
  std::snprintf(text, sizeof text, "%.17g", x);
  return text;
}

/// Box (no gravity, the default restitution tolerance), material, the client's plate
/// (top face at z = 0) and a sphere `gap` above it moving down at kSpeed.
void declareImpact(CosimHarness& h, double dt, std::uint64_t intervalSteps, double gap) {
  const double interval = static_cast<double>(intervalSteps) * dt;
  h.hello(1, "press");
  h.declare(1, R"({"name": "box", "simulation_box": {"time_step": )" + number(dt) +
                   R"(, "end_time": 0, "gravity": {}, "max_impact_velocity": )" + number(kSpeed) +
                   R"(, "coupling": {"expected_count": 4}, "output": {"vtk_interval": 0}}})");
  h.declare(1, R"({"name": "glass", "material": {"density": )" + number(kDensity) +
                   R"(, "youngs_modulus": 5e6, "sliding_friction": 0, "restitution": )" + number(kRestitution) + "}}");
  h.declare(1, R"({"name": "ball", "single_particle": {"material": "glass", "diameter": )" + number(2 * kRadius) +
                   R"(, "position": {"z": )" + number(kRadius + gap) + R"(}, "velocity": {"z": )" + number(-kSpeed) +
                   "}}}");
  h.declare(1, R"({"name": "plate", "communication_interval": )" + number(interval) +
                   R"(, "rigid_body": {"material": "glass", "box": {"size": {"x": 0.05, "y": 0.05, "z": 0.01}},
                   "position": {"z": -0.005}, "max_speed": 1, "motion": "PREDICTED"}})");
}

/// The accepted limit of the impact scene [s], from a compile at a tiny step.
double acceptedLimit() {
  ScratchDir dir;
  CosimHarness h(dir.path());
  declareImpact(h, 1e-8, 1, 1e-3);
  const std::optional<v1::Compiled> compiled = h.compiled(1);
  EXPECT_TRUE(compiled) << (h.errors(1).empty() ? "" : h.errors(1)[0].message());
  return compiled ? compiled->report().critical_time_step() : 0.0;
}

bool finite(const v1::Vector3& v) { return std::isfinite(v.x()) && std::isfinite(v.y()) && std::isfinite(v.z()); }

bool finite(const v1::RigidBodyOutput& o) {
  const v1::Quaternion& q = o.orientation();
  return finite(o.mean_force()) && finite(o.mean_torque()) && finite(o.force()) && finite(o.torque()) &&
         finite(o.position()) && std::isfinite(q.w()) && std::isfinite(q.x()) && std::isfinite(q.y()) &&
         std::isfinite(q.z());
}

/// Holds the plate still for `intervals` exchanges of `intervalSteps` steps each and
/// checks the rebound and the plate's impulse.
void impactAtInterval(std::uint64_t intervalSteps, std::uint64_t intervals) {
  const double limit = acceptedLimit();
  ASSERT_GT(limit, 0.0);
  const double dt = 0.99 * limit;
  ScratchDir dir;
  CosimHarness h(dir.path());
  declareImpact(h, dt, intervalSteps, 5.37 * kSpeed * dt);  // contact starts 0.37 of a step after step 5
  ASSERT_TRUE(h.compiled(1)) << (h.errors(1).empty() ? "" : h.errors(1)[0].message());
  const std::uint32_t plate = h.idOf(1, "plate");
  const double interval = static_cast<double>(intervalSteps) * dt;
  double impulse = 0.0;  // on the plate, z [N s]
  for (std::uint64_t k = 0; k < intervals; ++k) {
    h.sampleBody(1, plate, k * intervalSteps, bodyInput({0, 0, -0.005}, core::Quat::Identity()));
    ASSERT_TRUE(h.errors(1).empty()) << h.errors(1)[0].message();
    const std::optional<v1::DataPackage> answer = h.lastData(1, plate);
    ASSERT_TRUE(answer);
    ASSERT_EQ(answer->step(), (k + 1) * intervalSteps);
    ASSERT_TRUE(finite(answer->rigid_body())) << "interval " << k << ": " << answer->ShortDebugString();
    impulse += answer->rigid_body().mean_force().z() * interval;
  }
  const core::ParticleArrays& p = h.host().simulation()->compiled().scene->world.particles();
  ASSERT_EQ(p.size(), 1u);
  EXPECT_NEAR(p.velocity[0].z() / kSpeed / kRestitution, 1.0, 0.01) << "rebound at " << intervalSteps << " steps";
  const double mass = kDensity * 4.0 / 3.0 * std::numbers::pi * kRadius * kRadius * kRadius;
  // The sphere pushes the plate down: impulse −m·v·(1 + e); 1 % of e is 1/3 % of it.
  EXPECT_NEAR(-impulse / (mass * kSpeed * (1.0 + kRestitution)), 1.0, 0.01 * kRestitution / (1.0 + kRestitution));
  h.bye(1);
  ASSERT_TRUE(h.finished(1));
  EXPECT_TRUE(h.errors(1).empty());
  // The compile report ends with the measured per-stage seconds and shares.
  const std::string report = readText(dir.path() / "sim_001" / "compile_report.txt");
  EXPECT_NE(report.find("stage timing (sampled, " + std::to_string(intervals * intervalSteps) + " steps): "),
            std::string::npos)
      << report;
  EXPECT_NE(report.find(" %)"), std::string::npos) << report;
}

TEST(CosimExtremes, IntervalOfOneStep) { impactAtInterval(1, 400); }

TEST(CosimExtremes, IntervalOfTenThousandSteps) { impactAtInterval(10'000, 2); }

// Driven at 1000 m/s for an interval of 10^4 steps while declaring max_speed 1 m/s: the
// watchdog's speed bound (10 × the validated speed) stops the run inside the interval;
// the client gets Error{SIMULATION_FAULT, watchdog.speed_bound} and Finished, no package
// with a non-finite value.
TEST(CosimExtremes, ADrivenBodyFarBeyondItsSpeedStopsTheRunByName) {
  const double dt = 0.99 * acceptedLimit();
  ScratchDir dir;
  CosimHarness h(dir.path());
  declareImpact(h, dt, 10'000, 0.01);
  ASSERT_TRUE(h.compiled(1));
  h.sampleBody(1, h.idOf(1, "plate"), 0, bodyInput({0, 0, -0.005}, core::Quat::Identity(), {1000, 0, 0}));
  const std::vector<v1::Error> errors = h.errors(1);
  ASSERT_FALSE(errors.empty());
  EXPECT_EQ(errors.back().code(), v1::Error::SIMULATION_FAULT) << errors.back().message();
  EXPECT_EQ(errors.back().field(), "watchdog.speed_bound") << errors.back().message();
  EXPECT_NE(errors.back().message().find("plate"), std::string::npos) << errors.back().message();
  EXPECT_TRUE(h.finished(1));
  for (const v1::DataPackage& d : h.data(1)) {
    if (d.has_rigid_body()) {
      EXPECT_TRUE(finite(d.rigid_body())) << d.ShortDebugString();
    }
  }
}

}  // namespace
}  // namespace demlink::server::test
