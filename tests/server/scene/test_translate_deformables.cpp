// mass_spring_body and fem_body declarations: the specs carry every field (defaults filled in,
// paths resolved against the scene), the bodies land in the world, trackers follow their nodes
// by "body:node", and mistakes name the scene field.
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>

#include "demlink/core/components/node_tracker.hpp"
#include "demlink/server/scene/translate_deformables.hpp"
#include "scene_test_support.hpp"
#include "test_support.hpp"

namespace demlink::server::test {
namespace {

const std::string kBox = R"({"name": "box", "simulation_box": {"time_step": 1e-4, "end_time": 0.1}})";
const std::string kGlass = R"({"name": "glass", "material": {}})";
/// A 1 x 1 x 0.2 m box at 0.1 m spacing: 11 x 11 x 3 nodes (the solver paper's sheet).
const std::string kSheet = R"({"name": "sheet", "mass_spring_body": {
    "box": {"lo": {"x": -0.5, "y": -0.5, "z": -0.2}, "hi": {"x": 0.5, "y": 0.5, "z": 0.0}, "node_spacing": 0.1},
    "material": "glass", "total_mass": 500, "stiffness": 2e4, "damping": 1000,
    "fixed": {"nodes": [0], "regions": [{"lo": {"x": 0.49, "y": 0.49, "z": -0.21}, "hi": {"x": 0.51, "y": 0.51, "z": 0.01}}]}}})";

std::uint32_t resolveGlass(const std::string& name, const std::string& field) {
  if (name != "glass") throw core::InputError(field, name, "unknown material");
  return 7;
}

v1::MassSpringBody massSpringOf(const std::string& json) { return sceneOf({json}).components(0).mass_spring_body(); }

TEST(TranslateDeformables, MassSpringSpecCarriesEveryFieldAndTheDefaults) {
  const core::MassSpringSpec spec =
      translateMassSpringBody(massSpringOf(kSheet), "sheet", resolveGlass, {}, "components[2].mass_spring_body");
  EXPECT_EQ(spec.name, "sheet");
  EXPECT_EQ(spec.material, 7u);
  EXPECT_EQ(spec.total_mass, 500.0);
  EXPECT_EQ(spec.stiffness, 2e4);
  EXPECT_EQ(spec.damping, 1000.0);
  ASSERT_TRUE(spec.box.has_value());
  EXPECT_EQ(spec.box->lo, core::Vec3(-0.5, -0.5, -0.2));
  EXPECT_EQ(spec.box->node_spacing, 0.1);
  EXPECT_EQ(spec.fixed_nodes, std::vector<std::uint32_t>{0});
  ASSERT_EQ(spec.fixed_regions.size(), 1u);
  EXPECT_EQ(spec.fixed_regions[0].hi, core::Vec3(0.51, 0.51, 0.01));
  EXPECT_TRUE(std::isinf(spec.break_force));  // omitted: never breaks
  EXPECT_TRUE(std::isinf(spec.break_strain));
  EXPECT_TRUE(spec.driven_nodes.empty());
}

TEST(TranslateDeformables, ExplicitSpringsTakeTheBodysValuesUnlessGiven) {
  const core::MassSpringSpec spec = translateMassSpringBody(
      massSpringOf(R"({"name": "rope", "mass_spring_body": {"material": "glass", "total_mass": 2, "stiffness": 100,
          "damping": 3, "break_force": 50, "explicit_nodes": {
            "nodes": [{"x": 0}, {"x": 1}, {"x": 2}],
            "springs": [{"a": 0, "b": 1}, {"a": 1, "b": 2, "stiffness": 400, "damping": 0, "rest_length": 0.5}]}}})"),
      "rope", resolveGlass, {}, "p");
  ASSERT_EQ(spec.springs.size(), 2u);
  EXPECT_EQ(spec.springs[0].stiffness, 100.0);
  EXPECT_EQ(spec.springs[0].damping, 3.0);
  EXPECT_LT(spec.springs[0].rest_length, 0.0);  // the initial distance
  EXPECT_EQ(spec.springs[1].stiffness, 400.0);
  EXPECT_EQ(spec.springs[1].damping, 0.0);
  EXPECT_EQ(spec.springs[1].rest_length, 0.5);
  EXPECT_EQ(spec.break_force, 50.0);
  EXPECT_EQ(spec.nodes.size(), 3u);
}

TEST(TranslateDeformables, FemSpecResolvesFilesAgainstTheSceneDirectory) {
  ScratchDir dir;
  std::ofstream(dir.path() / "block.msh") << "$MeshFormat\n";
  const v1::FemBody body = sceneOf({R"({"name": "block", "fem_body": {"material": "glass",
      "integrator": "CENTRAL_DIFFERENCE", "rayleigh_alpha": 1e-3, "rayleigh_beta": 2,
      "mesh": {"msh_file": "block.msh", "youngs_modulus": 1e6, "poisson_ratio": 0.25, "density": 1000,
               "mass": "CONSISTENT", "offset": {"z": 1}}, "driven": {"nodes": [3]},
      "driven_reference": {"x": 0.5}}})"}).components(0).fem_body();
  const core::FemSpec spec = translateFemBody(body, "block", resolveGlass, dir.path(), "p");
  EXPECT_EQ(spec.msh_path, (dir.path() / "block.msh").string());
  EXPECT_EQ(spec.integrator, core::FemIntegrator::kCentralDifference);
  EXPECT_EQ(spec.mass, core::FemMass::kConsistent);
  EXPECT_EQ(spec.rayleigh_alpha, 1e-3);
  EXPECT_EQ(spec.rayleigh_beta, 2.0);
  EXPECT_EQ(spec.youngs_modulus, 1e6);
  EXPECT_EQ(spec.poisson_ratio, 0.25);
  EXPECT_EQ(spec.density, 1000.0);
  EXPECT_EQ(spec.offset, core::Vec3(0, 0, 1));
  EXPECT_EQ(spec.driven_nodes, std::vector<std::uint32_t>{3});
  EXPECT_EQ(spec.driven_reference, core::Vec3(0.5, 0, 0));
}

std::string fieldOf(const std::string& body) { return errorFieldAfterInitialize(sceneOf({kBox, kGlass, body})); }

TEST(TranslateDeformables, MistakesNameTheSceneField) {
  const std::string head = R"({"name": "s", "mass_spring_body": {"material": "glass", "total_mass": 1, "stiffness": 1, )";
  const std::string box = R"("box": {"lo": {}, "hi": {"x": 1, "y": 1}, "node_spacing": 0.5})";
  EXPECT_EQ(fieldOf(head + R"("box": {"lo": {}, "hi": {"x": 1, "y": 1}, "node_spacing": 0}}})"),
            "components[2].mass_spring_body.box.node_spacing");
  EXPECT_EQ(fieldOf(head + R"("box": {"hi": {"x": 1, "y": 1}, "node_spacing": 0.5}}})"),
            "components[2].mass_spring_body.box.lo");
  EXPECT_EQ(fieldOf(R"({"name": "s", "mass_spring_body": {"material": "glass", "total_mass": 1, "stiffness": 1}})"),
            "components[2].mass_spring_body");
  EXPECT_EQ(fieldOf(R"({"name": "s", "mass_spring_body": {"material": "steel", "total_mass": 1, "stiffness": 1, )" +
                    box + "}}"),
            "components[2].mass_spring_body.material");
  EXPECT_EQ(fieldOf(R"({"name": "s", "mass_spring_body": {"material": "glass", "total_mass": 0, "stiffness": 1, )" +
                    box + "}}"),
            "components[2].mass_spring_body.total_mass");
  EXPECT_EQ(fieldOf(head + box + R"(, "break_strain": -1}})"), "components[2].mass_spring_body.break_strain");
  EXPECT_EQ(fieldOf(head + box + R"(, "fixed": {"regions": [{"lo": {"x": 1}, "hi": {}}]}}})"),
            "components[2].mass_spring_body.fixed.regions[0].hi[0]");
  EXPECT_EQ(fieldOf(head + box + R"(, "attached_to": "bucket"}})"), "components[2].mass_spring_body.attached_to");
  EXPECT_EQ(fieldOf(head + R"("stl_file": "no_such.stl"}})"), "components[2].mass_spring_body.stl_file");
  EXPECT_EQ(fieldOf(head + R"("explicit_nodes": {"nodes": [{}, {"x": 1}], "springs": [{"a": 0, "b": 2}]}}})"),
            "components[2].mass_spring_body.explicit_nodes.springs[0].b");
  EXPECT_EQ(fieldOf(R"({"name": "f", "fem_body": {"material": "glass", "mesh": {"msh_file": "none.msh"}}})"),
            "components[2].fem_body.mesh.msh_file");
  EXPECT_EQ(fieldOf(R"({"name": "f", "fem_body": {"material": "glass"}})"), "components[2].fem_body");
  EXPECT_EQ(fieldOf(R"({"name": "f", "fem_body": {"material": "glass", "rayleigh_alpha": -1,
      "matrices": {"mass_matrix_file": "m.mtx"}}})"),
            "components[2].fem_body.rayleigh_alpha");
}

TEST(TranslateDeformables, TheSheetIsInTheWorldAndATrackerFollowsItsNodes) {
  TranslatedScene scene = translateScene(
      sceneOf({kBox, kGlass, kSheet,
               R"({"name": "centre", "tracker": {"nodes": ["sheet:302", "sheet:0"], "sample_interval": 0.01}})"}),
      {});
  ASSERT_EQ(scene.world.deformableBodies().size(), 1u);
  const core::DeformableBody& sheet = *scene.world.deformableBodies()[0];
  EXPECT_EQ(sheet.name(), "sheet");
  EXPECT_EQ(sheet.nodeCount(), 11u * 11u * 3u);
  EXPECT_NEAR(sheet.totalMass(), 500.0, 1e-9);
  const auto* tracker = dynamic_cast<const core::NodeTracker*>(scene.world.components().at(0).get());
  ASSERT_NE(tracker, nullptr);
  EXPECT_EQ(tracker->name(), "centre");
  scene.world.initialize();
  // Node 302 = (5, 5, 2): the centre of the top layer.
  const std::vector<double>& row = tracker->latestRow();
  ASSERT_EQ(row.size(), 1u + 2u * 9u);
  EXPECT_NEAR(row[1], 0.0, 1e-12);
  EXPECT_NEAR(row[2], 0.0, 1e-12);
  EXPECT_NEAR(row[3], 0.0, 1e-12);
  EXPECT_EQ(tracker->columns()[3], "sheet_302_z_m");

  const auto trackerField = [](const std::string& node) {
    return errorFieldAfterInitialize(sceneOf(
        {kBox, kGlass, kSheet, R"({"name": "t", "tracker": {"nodes": [")" + node + R"("], "sample_every_steps": 1}})"}));
  };
  EXPECT_EQ(trackerField("sheet:363"), "components[3].tracker.nodes[0]");  // 363 nodes: 0..362
  EXPECT_EQ(trackerField("sheet"), "components[3].tracker.nodes[0]");
  EXPECT_EQ(trackerField("sheet:x"), "components[3].tracker.nodes[0]");
  EXPECT_EQ(trackerField("plate:1"), "components[3].tracker.nodes[0]");
  EXPECT_EQ(trackerField("sheet:362"), "(accepted)");
}

TEST(TranslateDeformables, AnAttachedBodysDrivenNodesRideOnTheMeshExactly) {
  // A MOVING facet box translating and spinning about z carries a sheet whose nodes are all
  // driven: each node must stay where the rigid motion puts it, x(t) = p(t) + R(t) (X - p0).
  TranslatedScene scene = translateScene(
      sceneOf({kBox, kGlass, R"({"name": "tray", "facet_body": {"role": "MOVING", "material": "glass",
          "box": {"centre": {"x": 0.2, "y": 0.1, "z": -0.1}, "size": {"x": 0.1, "y": 0.1, "z": 0.1}},
          "linear_velocity": {"x": 0.3, "z": 0.5}, "angular_velocity": {"z": 2.0}}})",
               R"({"name": "sheet", "mass_spring_body": {"material": "glass", "total_mass": 1, "stiffness": 100,
          "box": {"lo": {"x": 0, "y": 0, "z": -0.01}, "hi": {"x": 0.4, "y": 0.2, "z": 0.01}, "node_spacing": 0.1},
          "driven": {"regions": [{"lo": {"x": -1, "y": -1, "z": -1}, "hi": {"x": 1, "y": 1, "z": 1}}]},
          "attached_to": "tray"}})"}),
      {});
  core::World& world = scene.world;
  world.initialize();
  const core::DeformableBody& sheet = *world.deformableBodies().at(0);
  std::vector<core::Vec3> initial;
  for (std::size_t n = 0; n < sheet.nodeCount(); ++n) initial.push_back(sheet.nodePosition(n));
  const core::Vec3 p0(0.2, 0.1, -0.1);
  for (int step = 0; step < 500; ++step) world.step();
  const double t = world.time();
  const core::Vec3 p = p0 + t * core::Vec3(0.3, 0.0, 0.5);
  const core::Mat3 rotation = Eigen::AngleAxisd(2.0 * t, core::Vec3::UnitZ()).toRotationMatrix();
  EXPECT_NEAR((world.meshes()[0].position() - p).norm(), 0.0, 1e-12);
  for (std::size_t n = 0; n < sheet.nodeCount(); ++n) {
    const core::Vec3 expected = p + rotation * (initial[n] - p0);
    EXPECT_NEAR((sheet.nodePosition(n) - expected).norm(), 0.0, 1e-9) << "node " << n;
    const core::Vec3 velocity = core::Vec3(0.3, 0.0, 0.5) + core::Vec3(0, 0, 2.0).cross(expected - p);
    EXPECT_NEAR((sheet.nodeVelocity(n) - velocity).norm(), 0.0, 1e-9) << "node " << n;
  }
}

TEST(TranslateDeformables, OutputNodesAreTheGivenOnesOrABoundedStrideOfTheSurface) {
  v1::DeformableOutputNodes given;
  given.add_nodes(4);
  given.add_nodes(1);
  EXPECT_EQ(outputNodesOf(given, 5, 5, "o"), (std::vector<std::uint32_t>{4, 1}));
  given.add_nodes(5);
  EXPECT_THROW((void)outputNodesOf(given, 5, 5, "o"), core::InputError);
  v1::DeformableOutputNodes all;
  EXPECT_EQ(outputNodesOf(all, 10, 4, "o"), (std::vector<std::uint32_t>{0, 1, 2, 3}));
  all.set_max_count(3);
  // 10 surface nodes, at most 3: stride ceil(10 / 3) = 4.
  EXPECT_EQ(outputNodesOf(all, 12, 10, "o"), (std::vector<std::uint32_t>{0, 4, 8}));
}

}  // namespace
}  // namespace demlink::server::test
