// The contact-law registry: every ContactModel value has one entry with a unique
// name that round-trips; each law's calibration delivers the requested
// restitution in a two-sphere impact through the engine; each law's critical
// time step is positive and finite. Iterating the registry means a new law is
// covered here without editing this file.
#include <cmath>
#include <set>
#include <string>

#include <gtest/gtest.h>

#include "demlink/core/contact/contact_law_registry.hpp"
#include "demlink/core/contact/critical_time_step.hpp"
#include "demlink/core/base/input_error.hpp"
#include "test_scenes.hpp"

namespace demlink::core {
namespace {

constexpr double kRadius = 0.01;  // [m]
constexpr double kSpeed = 1.0;    // [m/s]
constexpr double kDt = 5.0e-7;    // [s]

TEST(ContactLawRegistry, OneEntryPerEnumValueWithUniqueNames) {
  ASSERT_EQ(contactLaws().size(), kContactModelCount);
  std::set<std::string_view> names;
  for (std::size_t k = 0; k < kContactModelCount; ++k) {
    const auto model = static_cast<ContactModel>(k);
    const ContactLawEntry& law = contactLaw(model);
    EXPECT_EQ(law.model, model);
    EXPECT_FALSE(law.name.empty());
    EXPECT_TRUE(names.insert(law.name).second) << "duplicate name " << law.name;
    EXPECT_EQ(toString(model), law.name);
    EXPECT_EQ(contactModelNamed(law.name), model) << law.name;
  }
  EXPECT_EQ(contactModelNamed("hertz"), std::nullopt);
  EXPECT_THROW((void)contactLaw(static_cast<ContactModel>(kContactModelCount)), InputError);
}

TEST(ContactLawRegistry, NamesUsedInReports) {
  EXPECT_EQ(toString(ContactModel::HertzMindlin), "hertz_mindlin");
  EXPECT_EQ(toString(ContactModel::LinearSpringDashpot), "linear_spring_dashpot");
}

TEST(ContactLawRegistry, VisitPicksTheLawOfTheModel) {
  for (const ContactLawEntry& law : contactLaws()) {
    const ContactModel visited = visitContactLaw(law.model, []<class Law>() { return Law::kModel; });
    EXPECT_EQ(visited, law.model) << law.name;
  }
}

class ContactLawCalibration : public ::testing::TestWithParam<std::size_t> {};

TEST_P(ContactLawCalibration, TwoSphereImpactDeliversTheRequestedRestitution) {
  const ContactLawEntry& law = contactLaws()[GetParam()];
  for (double e : {0.2, 0.6, 0.95}) {
    World world(test::fineSettings(kDt, kSpeed, law.model));
    world.addMaterial(test::testMaterial(e));
    const std::optional<double> rebound = test::headOnRebound(world, kRadius, kSpeed, 4'000'000);
    ASSERT_TRUE(rebound) << law.name << ": spheres never separated";
    EXPECT_NEAR(*rebound / e, 1.0, test::kRestitutionTolerance) << law.name << " e=" << e;
  }
}

TEST_P(ContactLawCalibration, CriticalTimeStepIsPositiveAndFinite) {
  const ContactLawEntry& law = contactLaws()[GetParam()];
  const std::vector<Material> materials{test::testMaterial(0.5)};
  const ContactPairTable table(materials, law.model, {kRadius, kSpeed, 0.0});
  const TimeStepReport report = criticalTimeStep(materials, table, law.model, IntegratorKind::VelocityVerlet, {kRadius},
                                                 kSpeed, 0.01);
  for (double t : {report.contact_duration, report.limit}) {
    EXPECT_GT(t, 0.0) << law.name;
    EXPECT_TRUE(std::isfinite(t)) << law.name;
  }
  const double mass = test::sphereMass(kRadius, materials[0].density);
  const double duration = law.contact_duration(table(0, 0), 0.5 * kRadius, 0.5 * mass, kSpeed);
  EXPECT_GT(duration, 0.0) << law.name;
  EXPECT_TRUE(std::isfinite(duration)) << law.name;
}

INSTANTIATE_TEST_SUITE_P(EveryLaw, ContactLawCalibration, ::testing::Range<std::size_t>(0, kContactModelCount),
                         [](const ::testing::TestParamInfo<std::size_t>& param) {
                           return std::string(contactLaws()[param.param].name);
                         });

}  // namespace
}  // namespace demlink::core
