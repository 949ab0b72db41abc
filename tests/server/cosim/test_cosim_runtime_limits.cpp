// Every run-time input field against the limit the same field obeys in a declaration:
// NaN, +-inf, +-1e300 and one step past the documented bound are refused with
// INVALID_INPUT naming the field (never INTERNAL); the bound itself is accepted.
#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <limits>
#include <string>
#include <vector>

#include "cosim_test_support.hpp"
#include "demlink/core/base/input_bounds.hpp"

namespace demlink::server::test {
namespace {

constexpr double kDt = 1e-5;  // [s]; every component is exchanged every 10 steps

/// Declares a scene with one component of every kind that takes a run-time input.
void declareScene(CosimHarness& h) {
  h.hello(1);
  h.declare(1, boxJson(kDt, 0.0, R"("coupling": {"expected_count": 8})", 1e-4));
  for (const std::string& c : smallBedJson(2)) h.declare(1, c);
  h.declare(1, R"({"name": "plate", "communication_interval": 1e-4, "rigid_body": {"material": "glass",
      "box": {"size": {"x": 0.02, "y": 0.02, "z": 0.002}}, "position": {"z": 0.05}, "motion": "LAGGED"}})");
  h.declare(1, R"({"name": "sheet", "communication_interval": 1e-4, "mass_spring_body": {
      "box": {"lo": {"x": 0, "y": 0, "z": 0.1}, "hi": {"x": 0.04, "y": 0.04, "z": 0.101}, "node_spacing": 0.02},
      "material": "glass", "total_mass": 0.1, "stiffness": 100, "damping": 0.1,
      "driven": {"regions": [{"lo": {"x": -0.01, "y": -1, "z": -1}, "hi": {"x": 0.001, "y": 1, "z": 1}}]}}})");
  h.declare(1, R"({"name": "pour", "communication_interval": 1e-4, "particle_source": {"material": "glass",
      "sizes": {"uniform": {"r_min": 0.0015, "r_max": 0.002}}, "box": {"lower": {"x": 0.03, "y": -0.01, "z": 0.01},
      "upper": {"x": 0.05, "y": 0.01, "z": 0.02}}, "rate_particles_per_s": 100, "max_attempts": 1, "seed": 7}})");
  h.declare(1, R"({"name": "zone", "communication_interval": 1e-4, "region_sensor": {"region": {"sphere":
      {"radius": 0.1}}}})");
}

/// One run-time input field: which component sends it, how the value is set, the field
/// an Error must name, and the documented bound (0: finite only).
struct Field {
  std::string component;
  std::string field;
  std::function<void(v1::DataPackage&, double)> set;
  double bound = 0.0;
};

v1::DataPackage restingInput(const std::string& component) {
  v1::DataPackage p;
  if (component == "plate") *p.mutable_rigid_body_input() = bodyInput(core::Vec3(0, 0, 0.05), core::Quat::Identity());
  if (component == "sheet") {
    v1::DeformableBodyInput& in = *p.mutable_deformable_body_input();
    in.mutable_orientation()->set_w(1.0);
    in.mutable_position();
  }
  return p;
}

std::vector<Field> fields() {
  std::vector<Field> out;
  const auto vec = [](v1::Vector3& v, int axis, double x) {
    if (axis == 0) v.set_x(x);
    if (axis == 1) v.set_y(x);
    if (axis == 2) v.set_z(x);
  };
  out.push_back({"box", "simulation_box_input.gravity[2]",
                 [=](v1::DataPackage& p, double x) { vec(*p.mutable_simulation_box_input()->mutable_gravity(), 2, x); },
                 core::kMaxAcceleration});
  out.push_back({"box", "simulation_box_input.frame.linear_acceleration[0]",
                 [=](v1::DataPackage& p, double x) {
                   vec(*p.mutable_simulation_box_input()->mutable_frame()->mutable_linear_acceleration(), 0, x);
                 },
                 core::kMaxAcceleration});
  out.push_back({"box", "simulation_box_input.frame.angular_velocity[2]",
                 [=](v1::DataPackage& p, double x) {
                   vec(*p.mutable_simulation_box_input()->mutable_frame()->mutable_angular_velocity(), 2, x);
                 },
                 core::kMaxAngularVelocity});
  out.push_back({"box", "simulation_box_input.frame.angular_acceleration[2]",
                 [=](v1::DataPackage& p, double x) {
                   vec(*p.mutable_simulation_box_input()->mutable_frame()->mutable_angular_acceleration(), 2, x);
                 },
                 core::kMaxAngularAcceleration});
  out.push_back({"box", "simulation_box_input.frame.origin[0]",
                 [=](v1::DataPackage& p, double x) {
                   vec(*p.mutable_simulation_box_input()->mutable_frame()->mutable_origin(), 0, x);
                 },
                 core::kMaxCoordinate});
  for (const char* kindName : {"rigid_body_input", "deformable_body_input"}) {
    const std::string kind = kindName;
    const std::string component = kind == "rigid_body_input" ? "plate" : "sheet";
    const auto body = [kind](v1::DataPackage& p) -> v1::RigidBodyInput* {
      return kind == "rigid_body_input" ? p.mutable_rigid_body_input() : nullptr;
    };
    const auto motion = [body](v1::DataPackage& p, const std::string& which) -> v1::Vector3& {
      if (v1::RigidBodyInput* r = body(p)) {
        if (which == "position") return *r->mutable_position();
        if (which == "linear_velocity") return *r->mutable_linear_velocity();
        return *r->mutable_angular_velocity();
      }
      v1::DeformableBodyInput& d = *p.mutable_deformable_body_input();
      if (which == "position") return *d.mutable_position();
      if (which == "linear_velocity") return *d.mutable_linear_velocity();
      return *d.mutable_angular_velocity();
    };
    for (const auto& [which, bound] : {std::pair<std::string, double>{"position", core::kMaxCoordinate},
                                       {"linear_velocity", core::kMaxSpeed},
                                       {"angular_velocity", core::kMaxAngularVelocity}}) {
      out.push_back({component, kind + "." + which + "[0]",
                     [=](v1::DataPackage& p, double x) { vec(motion(p, which), 0, x); }, bound});
    }
    out.push_back({component, kind + ".orientation.x",
                   [=](v1::DataPackage& p, double x) {
                     if (v1::RigidBodyInput* r = body(p)) {
                       r->mutable_orientation()->set_x(x);
                     } else {
                       p.mutable_deformable_body_input()->mutable_orientation()->set_x(x);
                     }
                   },
                   0.0});
  }
  out.push_back({"pour", "particle_source_input.rate_particles_per_s",
                 [](v1::DataPackage& p, double x) { p.mutable_particle_source_input()->set_rate_particles_per_s(x); },
                 core::kMaxSourceParticleRate});
  out.push_back({"zone", "region_sensor_input.centre",
                 [=](v1::DataPackage& p, double x) { vec(*p.mutable_region_sensor_input()->mutable_centre(), 0, x); },
                 0.0});
  return out;
}

/// The first Error connection 1 got, if any.
std::optional<v1::Error> firstError(CosimHarness& h) {
  const std::vector<v1::Error> errors = h.errors(1);
  if (errors.empty()) return std::nullopt;
  return errors.front();
}

/// Sends `value` in `f` at step 0 (the other components' packages after it).
std::optional<v1::Error> sendAt(const Field& f, double value) {
  ScratchDir dir;
  CosimHarness h(dir.path());
  declareScene(h);
  EXPECT_TRUE(h.compiled(1).has_value()) << (h.errors(1).empty() ? "" : h.errors(1).front().message());
  if (!h.compiled(1)) return std::nullopt;
  v1::DataPackage package = restingInput(f.component);
  package.set_component_id(h.idOf(1, f.component));
  package.set_step(0);
  f.set(package, value);
  h.send(1, package);
  for (const char* other : {"box", "plate", "sheet", "pour", "zone"}) {
    if (other == f.component || h.closed(1)) continue;
    v1::DataPackage p = restingInput(other);
    p.set_component_id(h.idOf(1, other));
    p.set_step(0);
    h.send(1, p);
  }
  return firstError(h);
}

TEST(CosimRuntimeLimits, EveryRunTimeInputObeysTheDeclarationsBound) {
  const double inf = std::numeric_limits<double>::infinity();
  for (const Field& f : fields()) {
    // A region's centre is bounded only by being finite, in a declaration as at run time.
    std::vector<double> refused = {std::nan(""), inf, -inf};
    if (f.component != "zone") refused.insert(refused.end(), {1e300, -1e300});
    if (f.bound > 0.0) {
      refused.push_back(std::nextafter(f.bound, inf));
      if (f.field.find("rate") == std::string::npos) refused.push_back(-std::nextafter(f.bound, inf));
    }
    for (const double value : refused) {
      const std::optional<v1::Error> error = sendAt(f, value);
      ASSERT_TRUE(error.has_value()) << f.field << " = " << value << " was accepted";
      EXPECT_EQ(error->code(), v1::Error::INVALID_INPUT) << f.field << " = " << value << ": " << error->message();
      // The frame's spin and turn are also bounded at the farthest particle; either rule names
      // the field. A quaternion that is not a unit one is named as a whole.
      const std::string named = f.field.substr(0, f.field.find('['));
      const std::string last = named.substr(named.rfind('.') + 1);
      EXPECT_NE(error->field().find(last == "x" ? "orientation" : last), std::string::npos)
          << f.field << " = " << value << ": field " << error->field() << ": " << error->message();
    }
    if (f.bound > 0.0 && f.field.find("frame.angular") == std::string::npos) {
      // At the bound: not refused by the bound (the world may still stop on its watchdog, and
      // this scene's deformable bodies refuse any moving room; never INTERNAL).
      for (const double value : {f.bound, f.field.find("rate") == std::string::npos ? -f.bound : 0.0}) {
        const std::optional<v1::Error> error = sendAt(f, value);
        if (!error) continue;
        EXPECT_NE(error->code(), v1::Error::INTERNAL) << f.field << " = " << value << ": " << error->message();
        if (error->code() == v1::Error::INVALID_INPUT) {
          EXPECT_EQ(error->message().find("must be at most"), std::string::npos)
              << f.field << " = " << value << ": " << error->message();
        } else {
          EXPECT_EQ(error->code(), v1::Error::SIMULATION_FAULT) << f.field << " = " << value << ": " << error->message();
        }
      }
    }
  }
}

}  // namespace
}  // namespace demlink::server::test
