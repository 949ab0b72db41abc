// A scene computes only what it needs: for a set of scenes the compile
// report's active stages are exactly the ones each needs, so a stage that runs
// without being needed (or a needed one that is missing) fails here.
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "scene_test_support.hpp"

namespace demlink::server {
namespace {

using Stages = std::vector<std::string>;

Stages stagesOf(const std::string& boxExtra, const std::vector<std::string>& more,
                const std::string& material = R"({"name": "glass", "material": {}})") {
  std::vector<std::string> c{R"({"name": "box", "simulation_box": {"time_step": 1e-7, "end_time": 1)" +
                                 (boxExtra.empty() ? "" : ", " + boxExtra) + "}}",
                             material,
                             R"({"name": "ball", "particle_lattice": {"material": "glass", "radius": 0.01,
                                 "spacing": 1, "counts": {"nx": 1, "ny": 1, "nz": 1}, "origin": {"z": 0.5}}})"};
  c.insert(c.end(), more.begin(), more.end());
  TranslatedScene t = translateScene(test::sceneOf(c), {});
  t.world.initialize();
  return t.world.activeStages();
}

const std::string kPlane = R"({"name": "floor", "plane": {"normal": {"z": 1}, "material": "glass"}})";

TEST(SceneStages, EachSceneRunsExactlyTheStagesItNeeds) {
  const Stages core{"velocity_verlet", "neighbour_list", "forces", "particle_contacts:hertz_mindlin"};
  auto with = [&](Stages middle, Stages tail) {
    Stages s = std::move(middle);
    s.insert(s.end(), tail.begin(), tail.end());
    return s;
  };
  const Stages end{"second_half_kick", "advance_clock", "watchdog"};
  EXPECT_EQ(stagesOf("", {}), with(core, end)) << "one sphere, nothing else";
  EXPECT_EQ(stagesOf("", {kPlane}), with(with(core, {"plane_contacts"}), end)) << "a plane";
  EXPECT_EQ(stagesOf(R"("watchdog": {"every_steps": 0})", {}),
            with(core, {"second_half_kick", "advance_clock"}))
      << "watchdog off";
  EXPECT_EQ(stagesOf(R"("integrator": "EXPLICIT_EULER")", {}),
            (Stages{"explicit_euler", "neighbour_list", "forces", "particle_contacts:hertz_mindlin", "advance_clock",
                    "watchdog"}))
      << "explicit Euler: no second half kick";
  EXPECT_EQ(stagesOf("", {kPlane}, R"({"name": "glass", "material": {"rolling_friction": 0.1}})"),
            with(with(core, {"plane_contacts", "rolling_resistance"}), end))
      << "rolling friction";
  EXPECT_EQ(stagesOf(R"("frame": {"angular_velocity": {"z": 1}})", {}),
            with(Stages{"velocity_verlet", "moving_frame", "neighbour_list", "forces",
                        "particle_contacts:hertz_mindlin"},
                 end))
      << "a rotating frame";
  EXPECT_EQ(stagesOf(R"("bounds": {"lower": {"x": -1, "y": -1, "z": -1}, "upper": {"x": 1, "y": 1, "z": 1}})", {}),
            with(with(Stages{"bounds_removal"}, core), end))
      << "fixed bounds";
}

}  // namespace
}  // namespace demlink::server
