// Mass balance of a run with a source, a sink and domain bounds all acting: at every
// step, particles inserted - removed by the sink - removed over the bounds equals the
// particles in the world exactly (integers), and the same for mass to 1e-12 relative
// (the masses are sums of the same doubles in different orders). A sink that forgets
// one particle in its tally is caught by the same check.
#include <cmath>
#include <cstdint>
#include <string>

#include <gtest/gtest.h>

#include "component_scene.hpp"

namespace demlink::core {
namespace {

constexpr int kSteps = 2000;  // 0.1 s: insertion, sink removals and bounds removals all happen
constexpr double kMassTolerance = 1.0e-12;  // relative to the inserted mass

/// Inserted minus removed, against what the world holds.
struct Balance {
  std::int64_t count_error = 0;  ///< inserted - removed - in world [-]
  double mass_error = 0.0;       ///< same in mass, relative to the inserted mass [-]
};

Balance balance(const World& world, const SourceReport& inserted, const std::vector<RemovalTally>& removed) {
  std::int64_t count = static_cast<std::int64_t>(inserted.inserted_count) -
                       static_cast<std::int64_t>(world.particles().size());
  double mass = inserted.inserted_mass - world.totalMass();  // [kg]
  for (const RemovalTally& tally : removed) {
    count -= static_cast<std::int64_t>(tally.count);
    mass -= tally.mass;
  }
  Balance b;
  b.count_error = count;
  b.mass_error = inserted.inserted_mass > 0.0 ? std::abs(mass) / inserted.inserted_mass : std::abs(mass);
  return b;
}

TEST(MassBalance, SourceSinkAndBoundsBalanceAtEveryStep) {
  test::ComponentScene scene = test::buildComponentScene();
  World& world = *scene.world;
  std::uint64_t stepsWithAllThree = 0;
  double worst = 0.0;
  for (int n = 0; n < kSteps; ++n) {
    world.step();
    const Balance b = balance(world, scene.source->report(), {scene.sink->total(), world.removedAtBounds()});
    ASSERT_EQ(b.count_error, 0) << "step " << world.stepCount();
    ASSERT_LE(b.mass_error, kMassTolerance) << "step " << world.stepCount();
    worst = std::max(worst, b.mass_error);
    if (scene.sink->total().count > 0 && world.removedAtBounds().count > 0) ++stepsWithAllThree;
  }
  // All three must have acted, and for a good part of the run together.
  EXPECT_GT(scene.source->report().inserted_count, 100u);
  EXPECT_GT(scene.sink->total().count, 5u);
  EXPECT_GT(world.removedAtBounds().count, 5u);
  EXPECT_GT(world.particles().size(), 10u);
  EXPECT_GT(stepsWithAllThree, 100u);
  EXPECT_EQ(scene.source->report().shortfall_count, 0u);
  RecordProperty("worst_relative_mass_error", std::to_string(worst));
}

/// A sink that removes what is inside its sphere but leaves the first particle it
/// removes out of its tally: the bug the balance must catch.
class ForgetfulSink final : public WorldComponent {
 public:
  ForgetfulSink(Vec3 centre, double radius) : WorldComponent("forgetful"), centre_(centre), radius_(radius) {}
  [[nodiscard]] std::string_view kind() const override { return "forgetful_sink"; }
  [[nodiscard]] StageSet stages() const override { return stageBit(Stage::kInsertRemove); }
  void insertAndRemove(ComponentWorld& world) override {
    const ParticleArrays& p = world.particles();
    double forgottenMass = 0.0;  // [kg]
    RemovalTally removed;
    world.removeParticles(
        [&](std::size_t i) {
          const bool inside = (p.position[i] - centre_).norm() <= radius_;
          if (inside && !forgot_) {
            forgot_ = true;
            forgottenMass = p.mass[i];
          }
          return inside;
        },
        removed);
    if (forgottenMass > 0.0) {
      --removed.count;
      removed.mass -= forgottenMass;
    }
    tally_.count += removed.count;
    tally_.mass += removed.mass;
  }
  [[nodiscard]] const RemovalTally& tally() const { return tally_; }

 private:
  Vec3 centre_;
  double radius_;
  bool forgot_ = false;
  RemovalTally tally_;
};

TEST(MassBalance, CatchesASinkThatForgetsAParticle) {
  ForgetfulSink* forgetful = nullptr;
  test::ComponentScene scene = test::buildComponentScene(7, 1, [&](World& world) {
    forgetful = static_cast<ForgetfulSink*>(
        &world.addComponent(std::make_unique<ForgetfulSink>(Vec3(0.02, 0.0, 0.012), 0.01)));
  });
  World& world = *scene.world;
  bool countCaught = false;
  bool massCaught = false;
  for (int n = 0; n < kSteps; ++n) {
    world.step();
    const Balance b =
        balance(world, scene.source->report(), {scene.sink->total(), world.removedAtBounds(), forgetful->tally()});
    countCaught = countCaught || b.count_error != 0;
    massCaught = massCaught || b.mass_error > kMassTolerance;
  }
  EXPECT_TRUE(countCaught) << "the forgotten particle went unnoticed in the count";
  EXPECT_TRUE(massCaught) << "the forgotten particle went unnoticed in the mass";
  EXPECT_GT(forgetful->tally().count, 0u) << "the forgetful sink removed only one particle";
}

}  // namespace
}  // namespace demlink::core
