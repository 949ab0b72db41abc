/// The LIGGGHTS input of a compiled scene: the restitution mapping, the commands of the
/// deposition box, and one refusal per feature LIGGGHTS-PUBLIC cannot run (the error
/// names the component and says why). No LIGGGHTS or MPI needed.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <numbers>
#include <string>
#include <vector>

#include "demlink/core/base/input_error.hpp"
#include "demlink/server/backend/liggghts_motion.hpp"
#include "demlink/server/backend/liggghts_script.hpp"
#include "demlink/server/backend/simulation_backend.hpp"
#include "scene_test_support.hpp"
#include "test_support.hpp"

namespace demlink::server {
namespace {

const std::string kBox = R"({"name": "box", "simulation_box": {"time_step": 1e-5, "end_time": 0.01,
    "bounds": {"lower": {"x": 0, "y": 0, "z": 0}, "upper": {"x": 0.1, "y": 0.1, "z": 0.1}}}})";
const std::string kBoxNoBounds = R"({"name": "box", "simulation_box": {"time_step": 1e-5, "end_time": 0.01}})";
const std::string kBeads = R"({"name": "beads", "material": {"density": 2500, "youngs_modulus": 5e6,
    "poisson_ratio": 0.3, "restitution": 0.5, "sliding_friction": 0.5}})";
const std::string kFloor = R"({"name": "floor", "plane": {"normal": {"z": 1}, "material": "beads"}})";
const std::string kBead = R"({"name": "bead", "single_particle": {"material": "beads",
    "position": {"x": 0.05, "y": 0.05, "z": 0.01}, "diameter": 0.004}})";

std::vector<std::string> base() { return {kBox, kBeads, kFloor, kBead}; }

/// The InputError requireLiggghtsCompatible throws for `scene` and the world compiled
/// from `compiled` (files in `files`), as "field = value: reason", or "(accepted)".
std::string refusalOf(const v1::Scene& scene, const v1::Scene& compiled, const std::filesystem::path& files = {}) {
  TranslatedScene translated = translateScene(compiled, files);
  translated.world.initialize();
  try {
    requireLiggghtsCompatible(scene, translated.world);
  } catch (const core::InputError& error) {
    return error.what();
  }
  return "(accepted)";
}

std::string refusal(const std::vector<std::string>& components) {
  return refusalOf(test::sceneOf(components), test::sceneOf(components));
}

/// As refusal(), for a component kind the backend does not map: the kind check needs no
/// valid component, so the world is the base scene's.
std::string kindRefusal(const std::string& component) {
  std::vector<std::string> components = base();
  components.push_back(component);
  return refusalOf(test::sceneOf(components), test::sceneOf(base()));
}

bool has(const std::string& text, const std::string& part) { return text.find(part) != std::string::npos; }

TEST(LiggghtsRestitution, InvertsLiggghtsDampingFormula) {
  // LIGGGHTS: gamma_n = -2 sqrt(5/6) beta sqrt(S_n m*), beta = ln e / sqrt(ln^2 e + pi^2).
  for (double e : {0.05, 0.3, 0.5, 0.9, 1.0}) {
    const double beta = std::log(e) / std::sqrt(std::log(e) * std::log(e) + std::numbers::pi * std::numbers::pi);
    const double damping = -2.0 * std::sqrt(5.0 / 6.0) * beta;
    EXPECT_NEAR(liggghtsRestitution(damping, "e"), e, 1e-12) << e;
  }
  EXPECT_THROW((void)liggghtsRestitution(2.0 * std::sqrt(5.0 / 6.0), "e"), core::InputError);
}

TEST(LiggghtsScript, DepositionBoxCommands) {
  TranslatedScene translated = translateScene(test::sceneOf(base()), {});
  translated.world.initialize();
  EXPECT_EQ(refusal(base()), "(accepted)");
  const std::vector<std::string> commands = liggghtsCommands(translated.world, "scene.data");
  auto line = [&](const std::string& start) {
    const auto found = std::find_if(commands.begin(), commands.end(),
                                    [&](const std::string& c) { return c.starts_with(start); });
    return found == commands.end() ? std::string("(missing)") : *found;
  };
  EXPECT_EQ(line("read_data"), "read_data scene.data");
  EXPECT_EQ(line("timestep"), "timestep 1.0000000000000001e-05");
  // limitForce on: our normal force never pulls, and the restitution mapping assumes so.
  EXPECT_EQ(line("pair_style"), "pair_style gran model hertz tangential history limitForce on");
  EXPECT_TRUE(line("fix demlink_plane0").ends_with(" limitForce on")) << line("fix demlink_plane0");
  EXPECT_TRUE(has(line("fix demlink_gravity"), "gravity 9.8100000000000005 vector 0 0 -1")) << line("fix demlink_gravity");
  // The floor is the rigid twin of beads (type 2) or beads itself, a z plane at 0.
  EXPECT_TRUE(has(line("fix demlink_plane0"), "primitive type") && has(line("fix demlink_plane0"), "zplane 0"))
      << line("fix demlink_plane0");
  // The delivered restitution 0.5 of our Hertz law needs another LIGGGHTS value.
  const double e = liggghtsRestitution(translated.world.pairTable()(0, 0).normal_damping, "e");
  EXPECT_GT(std::abs(e - 0.5), 0.01) << e;
  const std::string data = liggghtsDataFile(translated.world);
  EXPECT_TRUE(has(data, "1 atoms")) << data;
  EXPECT_TRUE(has(data, "\nAtoms\n\n1 1 0.0040000000000000001 2500")) << data;
}

TEST(LiggghtsRefusals, ClumpsNamed) {
  const std::string what = kindRefusal(R"({"name": "rocks", "clump_template": {}})");
  EXPECT_TRUE(has(what, "components[4].clump_template") && has(what, "rocks") && has(what, "multisphere")) << what;
}

TEST(LiggghtsRefusals, DeformableBodiesNamed) {
  for (const std::string kind : {"mass_spring_body", "fem_body"}) {
    const std::string what = kindRefusal(R"({"name": "sheet", ")" + kind + R"(": {}})");
    EXPECT_TRUE(has(what, "components[4]." + kind) && has(what, "sheet") && has(what, "deformable")) << what;
  }
}

TEST(LiggghtsRefusals, MovingMeshesAccepted) {
  const test::ScratchDir dir;
  test::writeText(dir.path() / "tri.stl",
                  "solid t\n facet normal 0 0 1\n  outer loop\n   vertex 0 0 0\n   vertex 0.01 0 0\n"
                  "   vertex 0 0.01 0\n  endloop\n endfacet\nendsolid t\n");
  std::vector<std::string> components = base();
  components.push_back(R"({"name": "blade", "mesh_body": {"stl_file": "tri.stl", "material": "beads",
      "linear_velocity": {"x": 0.1}}})");
  EXPECT_EQ(refusalOf(test::sceneOf(components), test::sceneOf(components), dir.path()), "(accepted)");
  TranslatedScene resting = translateScene(test::sceneOf(components), dir.path());
  const std::string stl = liggghtsStl(resting.world.meshes()[0]);
  EXPECT_TRUE(has(stl, "vertex 0.01 0 0")) << stl;
}

TEST(LiggghtsMeshMotion, StepAnglesComposeToTheStepsRotation) {
  // Rz(c) Ry(b) Rx(a) must be the rotation by w dt, about any axis; to first order
  // (a, b, c) = w dt, and the difference is second order (what the exact angles fix).
  const double dt = 1e-3;
  for (const core::Vec3& w : {core::Vec3(40, -25, 10), core::Vec3(0, 0, 2), core::Vec3(-3, 0.5, 0)}) {
    const core::Vec3 angles = liggghtsStepAngles(w, dt);
    const core::Mat3 composed = (Eigen::AngleAxisd(angles.z(), core::Vec3::UnitZ()) *
                                 Eigen::AngleAxisd(angles.y(), core::Vec3::UnitY()) *
                                 Eigen::AngleAxisd(angles.x(), core::Vec3::UnitX()))
                                    .toRotationMatrix();
    const core::Mat3 step = Eigen::AngleAxisd(w.norm() * dt, w.normalized()).toRotationMatrix();
    EXPECT_LT((composed - step).cwiseAbs().maxCoeff(), 1e-15) << w.transpose();
    EXPECT_LT((angles - w * dt).norm(), w.squaredNorm() * dt * dt) << w.transpose();
  }
  EXPECT_LT((liggghtsStepAngles(core::Vec3(0, 0, 2), 1e-3) - core::Vec3(0, 0, 2e-3)).norm(), 1e-18);
  EXPECT_EQ(liggghtsStepAngles(core::Vec3::Zero(), 1e-3), core::Vec3::Zero());
}

TEST(LiggghtsMeshMotion, FixesReadVariablesThatNameTheTwistsValues) {
  // The fixes read demlink_mesh2_<c>, defined once, whose formula names
  // demlink_mesh2_<c>_now, which each twist re-defines (liggghts_motion.hpp says why).
  const std::vector<std::string> setup = liggghtsMeshMotionSetup(2);
  ASSERT_EQ(setup.size(), 12u);
  EXPECT_EQ(setup[0], "variable demlink_mesh2_vx equal v_demlink_mesh2_vx_now");
  EXPECT_EQ(setup[5], "variable demlink_mesh2_wz equal v_demlink_mesh2_wz_now");
  EXPECT_EQ(setup[6], "variable demlink_mesh2_vx_now equal 0");
  const std::vector<LiggghtsFix> fixes = liggghtsMeshMotionFixes(2, core::Vec3(1, 0, 0));
  ASSERT_EQ(fixes.size(), 4u);
  EXPECT_EQ(fixes[0].command, "fix demlink_mesh2_slide all move/mesh mesh demlink_mesh2 linear/variable "
                              "v_demlink_mesh2_vx v_demlink_mesh2_vy v_demlink_mesh2_vz");
  EXPECT_EQ(fixes[1].command, "fix demlink_mesh2_turn_wx all move/mesh mesh demlink_mesh2 rotate/variable origin 1 0 0 "
                              "axis 1 0 0 omega v_demlink_mesh2_wx");
  EXPECT_EQ(fixes[3].id, "demlink_mesh2_turn_wz");
  EXPECT_TRUE(has(fixes[3].command, "axis 0 0 1 omega v_demlink_mesh2_wz")) << fixes[3].command;
  // Sliding at u = (0.1, 0, 0) m/s while turning at w = (0, 0, 2) rad/s: about z alone, the
  // rate is w's.
  const std::vector<std::string> twist = liggghtsMeshTwist(2, core::Vec3(0.1, 0, 0), core::Vec3(0, 0, 2), 1e-3);
  ASSERT_EQ(twist.size(), 6u);
  EXPECT_EQ(twist[0], "variable demlink_mesh2_vx_now equal 0.10000000000000001");
  EXPECT_EQ(twist[3], "variable demlink_mesh2_wx_now equal 0");
  EXPECT_EQ(twist[5], "variable demlink_mesh2_wz_now equal 2");
}

TEST(LiggghtsRefusals, UnmappedKindsNamed) {
  // A tracker of nodes: LIGGGHTS has no deformable bodies.
  const std::string what = kindRefusal(R"({"name": "thing", "tracker": {"nodes": ["cloth/3"]}})");
  EXPECT_TRUE(has(what, "components[4].tracker.nodes[0] = cloth/3") && has(what, "thing") &&
              has(what, "no deformable bodies") && has(what, "native backend"))
      << what;
  // Sources, sinks, sensors and particle trackers are mapped (liggghts_flows), FIXED facet
  // bodies go as meshes at rest and a pit generator's bed as initial particles: their kind
  // passes.
  for (const std::string kind : {"particle_source", "particle_sink", "region_sensor", "flow_sensor", "tracker",
                                 "facet_body", "pit_generator"}) {
    EXPECT_EQ(kindRefusal(R"({"name": "thing", ")" + kind + R"(": {}})"), "(accepted)") << kind;
  }
}

TEST(LiggghtsRefusals, FacetRolesOtherThanFixedNamed) {
  for (const std::string role : {"MOVING", "NON_COLLIDING"}) {
    const std::string what = kindRefusal(R"({"name": "lid", "facet_body": {"role": ")" + role + R"("}})");
    EXPECT_TRUE(has(what, "components[4].facet_body.role = " + role) && has(what, "lid") &&
                has(what, "only FIXED") && has(what, "native backend"))
        << what;
  }
  const std::string window = kindRefusal(R"({"name": "gate", "facet_body": {"role": "FIXED", "active_until": 0.5}})");
  EXPECT_TRUE(has(window, "components[4].facet_body.active_until = 0.5") && has(window, "switched on or off")) << window;
  const std::string clumps = kindRefusal(R"({"name": "pit", "pit_generator": {"clump_template": "rock"}})");
  EXPECT_TRUE(has(clumps, "components[4].pit_generator.clump_template = rock") && has(clumps, "multisphere"))
      << clumps;
}

TEST(LiggghtsScript, RanksSplitTheBoxAcrossGravity) {
  // A bed settles flat: the ranks' grid has one layer along gravity, before the box exists.
  for (const auto& [gravity, grid] : {std::pair{R"("gravity": {"z": -9.81}, )", "processors * * 1"},
                                      std::pair{R"("gravity": {"x": 3, "y": -1}, )", "processors 1 * *"},
                                      std::pair{R"("gravity": {"y": 9.81, "z": 1}, )", "processors * 1 *"},
                                      std::pair{R"("gravity": {}, )", "(none)"}}) {
    const std::string box = R"({"name": "box", "simulation_box": {"time_step": 1e-5, "end_time": 0.01, )" +
                            std::string(gravity) +
                            R"("bounds": {"lower": {"x": 0, "y": 0, "z": 0}, "upper": {"x": 0.1, "y": 0.1, "z": 0.1}}}})";
    TranslatedScene translated = translateScene(test::sceneOf({box, kBeads, kFloor, kBead}), {});
    translated.world.initialize();
    const std::vector<std::string> commands = liggghtsCommands(translated.world, "scene.data");
    const auto processors = std::find_if(commands.begin(), commands.end(),
                                         [](const std::string& c) { return c.starts_with("processors"); });
    EXPECT_EQ(processors == commands.end() ? std::string("(none)") : *processors, grid) << gravity;
    if (processors != commands.end()) {
      EXPECT_LT(processors, std::find(commands.begin(), commands.end(), "read_data scene.data")) << gravity;
    }
  }
}

TEST(LiggghtsScript, FixedFacetBodyIsAMeshAtRest) {
  std::vector<std::string> components = base();
  components.push_back(R"({"name": "shelf", "facet_body": {"role": "FIXED", "material": "beads",
      "triangles": {"triangles": [{"a": {"x": 0.01, "y": 0.01, "z": 0.02}, "b": {"x": 0.09, "y": 0.01, "z": 0.02},
                                   "c": {"x": 0.09, "y": 0.09, "z": 0.02}}]}}})");
  EXPECT_EQ(refusal(components), "(accepted)");
  TranslatedScene translated = translateScene(test::sceneOf(components), {});
  translated.world.initialize();
  ASSERT_EQ(translated.world.meshes().size(), 1u);
  const std::vector<std::string> commands = liggghtsCommands(translated.world, "scene.data", {"shelf.stl"});
  const auto has_line = [&](const std::string& part) {
    return std::any_of(commands.begin(), commands.end(), [&](const std::string& c) { return has(c, part); });
  };
  EXPECT_TRUE(has_line("fix demlink_mesh0 all mesh/surface/stress file shelf.stl type "));
  EXPECT_TRUE(has_line("wall/gran model hertz tangential history mesh n_meshes 1 meshes demlink_mesh0 limitForce on"));
  EXPECT_FALSE(has_line("move/mesh"));
  const std::string stl = liggghtsStl(translated.world.meshes()[0]);
  EXPECT_TRUE(has(stl, "vertex 0.089999999999999997 0.089999999999999997 0.02")) << stl;
}

TEST(LiggghtsRefusals, MovingFrameNamed) {
  std::vector<std::string> components = base();
  components[0] = R"({"name": "box", "simulation_box": {"time_step": 1e-5, "end_time": 0.01,
      "frame": {"linear_acceleration": {"x": 1.0}},
      "bounds": {"lower": {"x": 0, "y": 0, "z": 0}, "upper": {"x": 0.1, "y": 0.1, "z": 0.1}}}})";
  const std::string what = refusal(components);
  EXPECT_TRUE(has(what, "components[0].simulation_box.frame") && has(what, "fictitious")) << what;
}

TEST(LiggghtsRefusals, CohesionNamed) {
  std::vector<std::string> components = base();
  components.push_back(
      R"({"name": "wet", "material_pair": {"material_a": "beads", "material_b": "beads", "cohesion_energy_density": 1e4}})");
  const std::string what = refusal(components);
  EXPECT_TRUE(has(what, "cohesion_energy_density") && has(what, "cohesion is not mapped")) << what;
}

TEST(LiggghtsScript, RollingFrictionIsConstantDirectionalTorque) {
  std::vector<std::string> components = base();
  components[1] = R"({"name": "beads", "material": {"density": 2500, "youngs_modulus": 5e6, "poisson_ratio": 0.3,
      "restitution": 0.5, "sliding_friction": 0.5, "rolling_friction": 0.1}})";
  EXPECT_EQ(refusal(components), "(accepted)");
  TranslatedScene translated = translateScene(test::sceneOf(components), {});
  translated.world.initialize();
  const std::vector<std::string> commands = liggghtsCommands(translated.world, "scene.data");
  const auto line = [&](const std::string& start) {
    const auto found = std::find_if(commands.begin(), commands.end(),
                                    [&](const std::string& c) { return c.starts_with(start); });
    return found == commands.end() ? std::string("(missing)") : *found;
  };
  EXPECT_EQ(line("pair_style"), "pair_style gran model hertz tangential history rolling_friction cdt limitForce on");
  EXPECT_TRUE(has(line("fix demlink_plane0"), "wall/gran model hertz tangential history rolling_friction cdt primitive"))
      << line("fix demlink_plane0");
  // beads and the floor's rigid twin: mu_r 0.1 for every pair.
  const std::size_t types = translated.world.materials().size();
  std::string values;
  for (std::size_t k = 0; k < types * types; ++k) values += " 0.10000000000000001";
  EXPECT_EQ(line("fix demlink_rolling"), "fix demlink_rolling all property/global coefficientRollingFriction "
                                         "peratomtypepair " + std::to_string(types) + values);
  // Without rolling friction the law and the fixes stay as they were.
  TranslatedScene plain = translateScene(test::sceneOf(base()), {});
  plain.world.initialize();
  for (const std::string& command : liggghtsCommands(plain.world, "scene.data")) {
    EXPECT_FALSE(has(command, "rolling")) << command;
  }
}

TEST(LiggghtsRefusals, TiltedPlaneNamed) {
  std::vector<std::string> components = base();
  components[2] = R"({"name": "ramp", "plane": {"normal": {"y": 0.5, "z": 1}, "material": "beads"}})";
  const std::string what = refusal(components);
  EXPECT_TRUE(has(what, "plane ramp.normal") && has(what, "axis-aligned")) << what;
}

TEST(LiggghtsRefusals, MissingBoundsNamed) {
  std::vector<std::string> components = base();
  components[0] = kBoxNoBounds;
  const std::string what = refusal(components);
  EXPECT_TRUE(has(what, "components[0].simulation_box.bounds") && has(what, "fixed box")) << what;
}

TEST(NativeBackend, AdvancesTheCompiledWorld) {
  TranslatedScene a = translateScene(test::sceneOf(base()), {});
  TranslatedScene b = translateScene(test::sceneOf(base()), {});
  NativeBackend backend(a.world);
  backend.advanceTo(250);
  b.world.initialize();
  for (int k = 0; k < 250; ++k) b.world.step();
  EXPECT_EQ(backend.stepCount(), 250u);
  EXPECT_DOUBLE_EQ(backend.time(), 250 * 1e-5);
  EXPECT_EQ(backend.world().particles().position[0], b.world.particles().position[0]);
  // Free fall for 2.5 ms from z = 10 mm under 9.81 m/s^2 (velocity Verlet is exact for it).
  EXPECT_NEAR(backend.world().particles().position[0].z(), 0.01 - 0.5 * 9.81 * 0.0025 * 0.0025, 1e-12);
  EXPECT_THROW((void)parseBackendKind("--backend", "lammps"), core::InputError);
  EXPECT_EQ(parseBackendKind("--backend", "LIGGGHTS"), BackendKind::Liggghts);
}

}  // namespace
}  // namespace demlink::server
