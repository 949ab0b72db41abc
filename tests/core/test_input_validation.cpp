// Bad input is refused with an InputError that names the field and the value.
#include <limits>

#include <gtest/gtest.h>

#include "demlink/core/base/input_error.hpp"
#include "test_scenes.hpp"

namespace demlink::core {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr double kInf = std::numeric_limits<double>::infinity();

/// Runs f, expects InputError whose field ends with `field` and whose message
/// contains `value`.
template <class F>
void expectInputError(F&& f, const std::string& field, const std::string& value) {
  try {
    f();
    ADD_FAILURE() << "no error for " << field << " = " << value;
  } catch (const InputError& e) {
    EXPECT_TRUE(e.field().ends_with(field)) << "field was " << e.field() << ", expected " << field;
    EXPECT_EQ(e.value(), value) << e.what();
    EXPECT_NE(std::string(e.what()).find(field), std::string::npos) << e.what();
  }
}

struct MaterialCase {
  std::string field;
  double value;
  std::string text;
};

TEST(InputValidation, MaterialFieldsOutOfRange) {
  const std::vector<MaterialCase> cases = {
      {"density", 0.0, "0"},           {"density", -1.0, "-1"},           {"density", kNaN, "nan"},
      {"youngs_modulus", 0.0, "0"},    {"youngs_modulus", kInf, "inf"},   {"poisson_ratio", 0.5, "0.5"},
      {"poisson_ratio", -1.0, "-1"},   {"restitution", 0.0, "0"},         {"restitution", 1.01, "1.01"},
      {"sliding_friction", -0.1, "-0.1"}, {"rolling_friction", -1.0, "-1"}, {"rolling_friction", kNaN, "nan"},
  };
  for (const auto& c : cases) {
    Material m = test::testMaterial(0.5);
    if (c.field == "density") m.density = c.value;
    if (c.field == "youngs_modulus") m.youngs_modulus = c.value;
    if (c.field == "poisson_ratio") m.poisson_ratio = c.value;
    if (c.field == "restitution") m.restitution = c.value;
    if (c.field == "sliding_friction") m.sliding_friction = c.value;
    if (c.field == "rolling_friction") m.rolling_friction = c.value;
    World world(test::fineSettings(1e-6, 1.0));
    expectInputError([&] { world.addMaterial(m); }, "test." + c.field, c.text);
  }
}

TEST(InputValidation, ParticleFields) {
  World world(test::fineSettings(1e-6, 1.0));
  world.addMaterial(test::testMaterial(0.5));
  ParticleSpec s;
  s.radius = 0.0;
  expectInputError([&] { world.addParticle(s, "p"); }, "p.radius", "0");
  s.radius = -0.001;
  expectInputError([&] { world.addParticle(s, "p"); }, "p.radius", "-0.001");
  s.radius = 0.001;
  s.position.y() = kNaN;
  expectInputError([&] { world.addParticle(s, "p"); }, "p.position[1]", "nan");
  s.position.y() = 0.0;
  s.velocity.z() = kInf;
  expectInputError([&] { world.addParticle(s, "p"); }, "p.velocity[2]", "inf");
  s.velocity.z() = 0.0;
  s.material = 5;
  expectInputError([&] { world.addParticle(s, "p"); }, "p.material", "5");
}

TEST(InputValidation, PlaneFields) {
  World world(test::fineSettings(1e-6, 1.0));
  world.addMaterial(test::testMaterial(0.5));
  expectInputError([&] { world.addPlane({"w", Vec3::Zero(), Vec3::Zero(), 0}, "floor"); }, "floor.normal",
                   "(0, 0, 0)");
  expectInputError([&] { world.addPlane({"w", Vec3(kNaN, 0, 0), Vec3::UnitZ(), 0}, "floor"); }, "floor.point[0]",
                   "nan");
}

TEST(InputValidation, TimeStepNonPositiveOrAboveCriticalLimit) {
  SimulationSettings s = test::fineSettings(0.0, 1.0);
  expectInputError([&] { World w(s); }, "settings.time_step", "0");
  s.time_step = -1e-6;
  expectInputError([&] { World w(s); }, "settings.time_step", "-1e-06");
  s.time_step = kNaN;
  expectInputError([&] { World w(s); }, "settings.time_step", "nan");

  // r = 1 mm, E = 1e7: Rayleigh T_R ~ 1.6e-4 s, so 1e-4 s is far above 20 % of it.
  s.time_step = 1e-4;
  World world(s);
  world.addMaterial(test::testMaterial(0.5));
  ParticleSpec p;
  p.radius = 0.001;
  world.addParticle(p);
  try {
    world.initialize();
    ADD_FAILURE() << "time step above the critical limit accepted";
  } catch (const InputError& e) {
    EXPECT_EQ(e.field(), "settings.time_step");
    EXPECT_NE(std::string(e.what()).find("critical limit"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find(formatValue(world.timeStepReport().limit)), std::string::npos)
        << "message must name the limit: " << e.what();
  }
  // The explicit override accepts it.
  s.allow_unsafe_time_step = true;
  World unsafe(s);
  unsafe.addMaterial(test::testMaterial(0.5));
  unsafe.addParticle(p);
  EXPECT_NO_THROW(unsafe.initialize());
}

TEST(InputValidation, CriticalTimeStepMatchesRayleighFormula) {
  // T_R = pi R sqrt(rho/G) / (0.1631 nu + 0.8766), G = E / (2 (1 + nu)).
  const Material m = test::testMaterial(0.5);
  const double g = m.youngs_modulus / (2.0 * (1.0 + m.poisson_ratio));
  const double expected = std::numbers::pi * 0.002 * std::sqrt(m.density / g) / (0.1631 * 0.3 + 0.8766);
  EXPECT_NEAR(rayleighTimeStep(m, 0.002) / expected, 1.0, 1e-12);
}

TEST(InputValidation, BoundsMustNotBeInverted) {
  SimulationSettings s = test::fineSettings(1e-6, 1.0);
  s.bounds = DomainBounds{Vec3::Zero(), Vec3(1.0, -1.0, 1.0)};
  expectInputError([&] { World w(s); }, "settings.bounds.upper[1]", "-1");
}

}  // namespace
}  // namespace demlink::core
