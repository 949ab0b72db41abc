// Per-pair contact overrides (World::setPairOverride, scene component
// material_pair): the overridden pair delivers the overriding restitution
// (damping recalibrated), to 1 %, under both contact laws; like-material pairs
// keep their own values; friction overrides reach the pair table; bad
// overrides are refused naming the field.
#include <gtest/gtest.h>

#include "demlink/core/base/input_error.hpp"
#include "test_scenes.hpp"

namespace demlink::core {
namespace {

constexpr double kRadius = 0.01;  // [m]
constexpr double kSpeed = 1.0;    // [m/s]
constexpr double kDt = 5.0e-7;    // [s]

/// Two unlike materials: the mean restitution of the pair is 0.6.
Material stiffDense() {
  Material m = test::testMaterial(0.3, 0.4);
  m.name = "dense";
  return m;
}
Material softLight() {
  Material m = test::testMaterial(0.9, 0.2);
  m.name = "light";
  m.density = 1200.0;
  m.youngs_modulus = 5.0e6;
  m.poisson_ratio = 0.4;
  return m;
}

/// Rebound-to-impact speed ratio of a head-on impact between spheres of
/// materials a and b (indices 0 = dense, 1 = light), with an optional override.
double measuredRestitution(ContactModel model, std::uint32_t a, std::uint32_t b,
                           const std::optional<PairOverrideEntry>& override) {
  World world(test::fineSettings(kDt, kSpeed, model));
  world.addMaterial(stiffDense());
  world.addMaterial(softLight());
  if (override) world.setPairOverride(override->material_a, override->material_b, override->values);
  const std::optional<double> rebound = test::headOnRebound(world, kRadius, kSpeed, 2'000'000, a, b);
  EXPECT_TRUE(rebound) << "spheres never separated";
  return rebound.value_or(0.0);
}

PairOverrideEntry restitutionOverride(std::uint32_t a, std::uint32_t b, double e) {
  PairOverrideEntry entry{a, b, {}};
  entry.values.restitution = e;
  return entry;
}

class PairOverrideImpact : public ::testing::TestWithParam<ContactModel> {};

TEST_P(PairOverrideImpact, UnlikePairWithoutOverrideTakesTheMean) {
  EXPECT_NEAR(measuredRestitution(GetParam(), 0, 1, std::nullopt) / 0.6, 1.0, test::kRestitutionTolerance);
}

TEST_P(PairOverrideImpact, UnlikePairTakesTheOverride) {
  // Given as (light, dense): the order of the two materials must not matter.
  EXPECT_NEAR(measuredRestitution(GetParam(), 0, 1, restitutionOverride(1, 0, 0.8)) / 0.8, 1.0,
              test::kRestitutionTolerance);
  EXPECT_NEAR(measuredRestitution(GetParam(), 0, 1, restitutionOverride(0, 1, 0.15)) / 0.15, 1.0,
              test::kRestitutionTolerance);
}

TEST_P(PairOverrideImpact, LikePairsKeepTheirOwnRestitution) {
  const auto override = restitutionOverride(0, 1, 0.8);
  EXPECT_NEAR(measuredRestitution(GetParam(), 0, 0, override) / 0.3, 1.0, test::kRestitutionTolerance);
  EXPECT_NEAR(measuredRestitution(GetParam(), 1, 1, override) / 0.9, 1.0, test::kRestitutionTolerance);
}

TEST_P(PairOverrideImpact, LikePairCanBeOverridden) {
  EXPECT_NEAR(measuredRestitution(GetParam(), 0, 0, restitutionOverride(0, 0, 0.7)) / 0.7, 1.0,
              test::kRestitutionTolerance);
}

INSTANTIATE_TEST_SUITE_P(BothLaws, PairOverrideImpact,
                         ::testing::Values(ContactModel::HertzMindlin, ContactModel::LinearSpringDashpot),
                         [](const ::testing::TestParamInfo<ContactModel>& param) {
                           return std::string(toString(param.param));
                         });

/// A world with the two materials and one sphere of each, initialised.
World initialisedWorld(const std::vector<PairOverrideEntry>& overrides) {
  World world(test::fineSettings(kDt, kSpeed));
  world.addMaterial(stiffDense());
  world.addMaterial(softLight());
  for (const auto& o : overrides) world.setPairOverride(o.material_a, o.material_b, o.values);
  test::addHeadOnPair(world, kRadius, kSpeed, 0.01, 0, 1);
  world.initialize();
  return world;
}

TEST(PairOverride, OnlyTheGivenValuesChange) {
  PairOverrideEntry friction{0, 1, {}};
  friction.values.sliding_friction = 0.05;
  friction.values.rolling_friction = 0.02;
  const World plain = initialisedWorld({});
  const World overridden = initialisedWorld({friction});
  const ContactPairParams& p = plain.pairTable()(0, 1);
  const ContactPairParams& o = overridden.pairTable()(1, 0);
  EXPECT_EQ(o.sliding_friction, 0.05);
  EXPECT_EQ(o.rolling_friction, 0.02);
  EXPECT_EQ(o.restitution, p.restitution) << "restitution not overridden: stays the mean";
  EXPECT_EQ(o.normal_damping, p.normal_damping);
  EXPECT_EQ(o.effective_youngs, p.effective_youngs);
  // Neither material rolls, so only the override switches the rolling kernel on.
  EXPECT_FALSE(plain.pairTable().anyRollingFriction());
  EXPECT_TRUE(overridden.pairTable().anyRollingFriction());
  for (std::uint32_t m : {0u, 1u}) {
    EXPECT_EQ(overridden.pairTable()(m, m).sliding_friction, plain.pairTable()(m, m).sliding_friction);
    EXPECT_EQ(overridden.pairTable()(m, m).normal_damping, plain.pairTable()(m, m).normal_damping);
  }
}

/// Calls setPairOverride and returns the InputError's field (fails if none).
std::string overrideErrorField(World& world, std::uint32_t a, std::uint32_t b, const PairOverride& values) {
  try {
    world.setPairOverride(a, b, values, "pair");
  } catch (const InputError& e) {
    return e.field();
  }
  ADD_FAILURE() << "expected an InputError";
  return {};
}

TEST(PairOverride, BadOverridesNameTheField) {
  World world(test::fineSettings(kDt, kSpeed));
  world.addMaterial(stiffDense());
  world.addMaterial(softLight());
  PairOverride zeroE;
  zeroE.restitution = 0.0;
  EXPECT_EQ(overrideErrorField(world, 0, 1, zeroE), "pair.restitution");
  PairOverride bigE;
  bigE.restitution = 1.2;
  EXPECT_EQ(overrideErrorField(world, 0, 1, bigE), "pair.restitution");
  PairOverride negativeMu;
  negativeMu.sliding_friction = -0.1;
  EXPECT_EQ(overrideErrorField(world, 0, 1, negativeMu), "pair.sliding_friction");
  PairOverride nanRolling;
  nanRolling.rolling_friction = std::nan("");
  EXPECT_EQ(overrideErrorField(world, 0, 1, nanRolling), "pair.rolling_friction");
  PairOverride ok;
  ok.restitution = 0.5;
  EXPECT_EQ(overrideErrorField(world, 0, 2, ok), "pair.material");
  world.setPairOverride(0, 1, ok, "pair");
  EXPECT_EQ(overrideErrorField(world, 1, 0, ok), "pair") << "the same unordered pair twice";
  test::addHeadOnPair(world, kRadius, kSpeed, 0.01, 0, 1);
  world.initialize();
  EXPECT_EQ(overrideErrorField(world, 0, 0, ok), "pair") << "after initialize()";
}

}  // namespace
}  // namespace demlink::core
