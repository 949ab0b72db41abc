/// Restitution on both engines, on however many MPI ranks the test was started with: a
/// sphere shot at a plane, at a FIXED facet floor, and two spheres shot at each other,
/// without gravity, so the speed after the contact is the rebound speed itself. Our engine
/// calibrates its damping so that a contact delivers the material's restitution; LIGGGHTS
/// is given a restitution that makes its damping ours (liggghtsRestitution), and its normal
/// force must not pull either (limitForce on), or it delivers 0.436 for 0.5.
#include <gtest/gtest.h>

#include <cstdint>
#include <cstdio>
#include <string>

#include "demlink/server/backend/liggghts_backend.hpp"
#include "demlink/server/backend/liggghts_script.hpp"
#include "scene_test_support.hpp"
#include "test_support.hpp"

namespace demlink::server {
namespace {

constexpr double kRestitution = 0.5;
constexpr double kImpactSpeed = 0.3;  // [m/s], of the sphere on a wall and of each sphere of the pair
constexpr std::uint64_t kSteps = 500;  // 5 ms: every contact below is over by 2.5 ms

const std::string kBox = R"({"name": "box", "simulation_box": {"time_step": 1e-5, "end_time": 0.005,
    "gravity": {"x": 0, "y": 0, "z": 0}, "max_impact_velocity": 1.0,
    "bounds": {"lower": {"x": 0, "y": 0, "z": -0.005}, "upper": {"x": 0.03, "y": 0.02, "z": 0.02}}}})";
const std::string kBeads = R"({"name": "beads", "material": {"density": 2500, "youngs_modulus": 5e6,
    "poisson_ratio": 0.3, "restitution": 0.5, "sliding_friction": 0.5}})";
/// A 4 mm sphere 0.5 mm above z = 0, moving down at the impact speed.
const std::string kFalling = R"({"name": "bead", "single_particle": {"material": "beads",
    "position": {"x": 0.012, "y": 0.009, "z": 0.0025}, "velocity": {"z": -0.3}, "diameter": 0.004}})";

struct Rebound {
  double ours;      ///< [m/s]
  double liggghts;  ///< [m/s]
};

/// The speed of the first particle after the contact, on both engines; the particles of
/// `scene` move along the x or z axis only.
Rebound reboundSpeeds(const v1::Scene& scene) {
  TranslatedScene native = translateScene(scene, {});
  NativeBackend ours(native.world);
  ours.advanceTo(kSteps);
  TranslatedScene translated = translateScene(scene, {});
  requireLiggghtsCompatible(scene, translated.world);
  LiggghtsBackend backend(translated.world);
  backend.advanceTo(kSteps);
  backend.syncParticles();
  return {ours.world().particles().velocity[0].norm(), backend.world().particles().velocity[0].norm()};
}

/// Both engines deliver the material's restitution (to 1 %: the calibration is exact, the
/// 70 steps of a contact are not), and LIGGGHTS ours to 2 %.
void expectSameRestitution(const Rebound& rebound, const char* contact) {
  const double expected = kRestitution * kImpactSpeed;
  EXPECT_NEAR(rebound.ours, expected, 0.01 * expected) << contact;
  EXPECT_NEAR(rebound.liggghts, expected, 0.01 * expected) << contact << ", ranks " << mpiRanks();
  EXPECT_NEAR(rebound.liggghts, rebound.ours, 0.02 * rebound.ours) << contact << ", ranks " << mpiRanks();
  std::printf("%s, %d rank(s): rebound %.9g m/s on LIGGGHTS, %.9g m/s on ours (e %.6g and %.6g; ratio %.9g)\n",
              contact, mpiRanks(), rebound.liggghts, rebound.ours, rebound.liggghts / kImpactSpeed,
              rebound.ours / kImpactSpeed, rebound.liggghts / rebound.ours);
}

TEST(LiggghtsRestitution, SphereOnPlaneReboundsAsOnOurs) {
  const v1::Scene scene = test::sceneOf({
      kBox,
      kBeads,
      R"({"name": "floor", "plane": {"point": {"z": 0}, "normal": {"z": 1}, "material": "beads"}})",
      kFalling,
  });
  expectSameRestitution(reboundSpeeds(scene), "sphere on a plane");
}

TEST(LiggghtsRestitution, SphereOnFixedFacetFloorReboundsAsOnOurs) {
  const v1::Scene scene = test::sceneOf({
      kBox,
      kBeads,
      R"({"name": "floor", "facet_body": {"role": "FIXED", "material": "beads", "triangles": {"triangles": [
          {"a": {"x": 0, "y": 0, "z": 0}, "b": {"x": 0.02, "y": 0, "z": 0}, "c": {"x": 0.02, "y": 0.02, "z": 0}},
          {"a": {"x": 0, "y": 0, "z": 0}, "b": {"x": 0.02, "y": 0.02, "z": 0}, "c": {"x": 0, "y": 0.02, "z": 0}}]}}})",
      kFalling,
  });
  expectSameRestitution(reboundSpeeds(scene), "sphere on a FIXED facet floor");
}

TEST(LiggghtsRestitution, SpherePairReboundsAsOnOurs) {
  // Head on, 0.5 mm apart, each at the impact speed: the pair's relative speed is twice it,
  // and so is its rebound, shared equally.
  const v1::Scene scene = test::sceneOf({
      kBox,
      kBeads,
      R"({"name": "a", "single_particle": {"material": "beads", "position": {"x": 0.01275, "y": 0.01, "z": 0.01},
          "velocity": {"x": 0.3}, "diameter": 0.004}})",
      R"({"name": "b", "single_particle": {"material": "beads", "position": {"x": 0.01725, "y": 0.01, "z": 0.01},
          "velocity": {"x": -0.3}, "diameter": 0.004}})",
  });
  expectSameRestitution(reboundSpeeds(scene), "two spheres head on");
}

}  // namespace
}  // namespace demlink::server
