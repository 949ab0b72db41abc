// Delivered coefficient of restitution: the rebound-to-impact speed ratio must
// be within 1 % of the requested e, for both contact laws, against a plane and
// between two spheres. (Normal force clamped at zero: see docs/physics.md.)
#include <gtest/gtest.h>

#include "test_scenes.hpp"

namespace demlink::core {
namespace {

constexpr double kRadius = 0.01;
constexpr double kSpeed = 1.0;
constexpr double kDt = 5.0e-7;

struct Case {
  ContactModel model;
  double e;
};

class Restitution : public ::testing::TestWithParam<Case> {};

TEST_P(Restitution, SphereOnPlane) {
  const Case c = GetParam();
  World world(test::fineSettings(kDt, kSpeed, c.model));
  const auto mat = world.addMaterial(test::testMaterial(c.e));
  test::addFloorAndSphere(world, mat, kRadius, Vec3(0.0, 0.0, -kSpeed), 1e-6);
  world.initialize();
  auto& p = world.particles();
  const auto steps = test::stepUntil(world, [&] { return p.position[0].z() > kRadius + 2e-6; }, 4'000'000);
  ASSERT_LT(steps, 4'000'000u) << "sphere never left the plane";
  EXPECT_NEAR(p.velocity[0].z() / kSpeed / c.e, 1.0, test::kRestitutionTolerance);
}

TEST_P(Restitution, SphereOnSphere) {
  const Case c = GetParam();
  World world(test::fineSettings(kDt, kSpeed, c.model));
  world.addMaterial(test::testMaterial(c.e));
  const std::optional<double> rebound = test::headOnRebound(world, kRadius, kSpeed, 4'000'000);
  ASSERT_TRUE(rebound) << "spheres never separated";
  EXPECT_NEAR(*rebound / c.e, 1.0, test::kRestitutionTolerance);
}

std::vector<Case> allCases() {
  std::vector<Case> cases;
  for (ContactModel m : {ContactModel::HertzMindlin, ContactModel::LinearSpringDashpot}) {
    for (double e : {0.1, 0.3, 0.5, 0.7, 0.9}) cases.push_back({m, e});
  }
  return cases;
}

INSTANTIATE_TEST_SUITE_P(BothLaws, Restitution, ::testing::ValuesIn(allCases()), [](const ::testing::TestParamInfo<Case>& param) {
  return std::string(toString(param.param.model)) + "_e" + std::to_string(static_cast<int>(param.param.e * 10 + 0.5));
});

}  // namespace
}  // namespace demlink::core
