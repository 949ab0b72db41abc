// Deformable bodies in a co-simulation: the compile report lists the body and its own
// critical step, the outputs carry the declared nodes and the reactions, a client's
// DeformableBodyInput moves the driven nodes (pose advanced by the twist over the
// interval), and inputs the body cannot take are refused naming the field.
#include <gtest/gtest.h>

#include "cosim_test_support.hpp"

namespace demlink::server::test {
namespace {

constexpr double kDt = 1e-4;  // [s]

/// A 5 x 5 sheet over [0, 0.4]^2, its x = 0 edge driven about the reference (0, 0.2, 0).
std::string sheetJson(const std::string& extra = "", const std::string& outputNodes = "[0, 24]") {
  return R"({"name": "sheet", "communication_interval": 0.001, "mass_spring_body": {
      "box": {"lo": {"x": 0, "y": 0, "z": -0.01}, "hi": {"x": 0.4, "y": 0.4, "z": 0.01}, "node_spacing": 0.1},
      "material": "glass", "total_mass": 1, "stiffness": 1000, "damping": 1,
      "driven": {"regions": [{"lo": {"x": -0.01, "y": -1, "z": -1}, "hi": {"x": 0.01, "y": 1, "z": 1}}]},
      "driven_reference": {"y": 0.2}, "output_nodes": {"nodes": )" +
         outputNodes + "}" + extra + "}}";
}

void compileSheet(CosimHarness& h, const std::string& extra = "", const std::string& more = "") {
  h.hello(1);
  h.declare(1, boxJson(kDt, 0.0, R"("coupling": {"expected_count": )" + std::string(more.empty() ? "3" : "4") + "}"));
  h.declare(1, R"({"name": "glass", "material": {}})");
  if (!more.empty()) h.declare(1, more);
  h.declare(1, sheetJson(extra));
}

v1::DataPackage sheetInput(std::uint32_t id, std::uint64_t step, const core::Vec3& position,
                           const core::Vec3& velocity) {
  v1::DataPackage p;
  p.set_component_id(id);
  p.set_step(step);
  v1::DeformableBodyInput& in = *p.mutable_deformable_body_input();
  setVec3(*in.mutable_position(), position);
  setQuat(*in.mutable_orientation(), core::Quat::Identity());
  setVec3(*in.mutable_linear_velocity(), velocity);
  return p;
}

TEST(CosimDeformable, ReportOutputsAndADrivenEdgeThatFollowsThePose) {
  ScratchDir dir;
  CosimHarness h(dir.path());
  compileSheet(h);
  ASSERT_TRUE(h.compiled(1)) << (h.errors(1).empty() ? "" : h.errors(1)[0].message());
  const v1::Compiled compiled = *h.compiled(1);
  EXPECT_NE(compiled.report().text().find("deformable sheet (mass_spring): 25 nodes"), std::string::npos)
      << compiled.report().text();
  bool listed = false;
  for (const std::string& stage : compiled.report().active_stages()) listed |= stage == "mass_spring:sheet";
  EXPECT_TRUE(listed);
  const std::uint32_t id = h.idOf(1, "sheet");
  ASSERT_NE(id, 0u);
  std::optional<v1::DataPackage> initial;
  for (const v1::DataPackage& p : compiled.initial_outputs()) {
    if (p.component_id() == id) initial = p;
  }
  ASSERT_TRUE(initial && initial->has_deformable_body());
  EXPECT_EQ(initial->deformable_body().nodes_size(), 2);
  EXPECT_EQ(initial->deformable_body().displacements_size(), 6);
  EXPECT_EQ(initial->deformable_body().node_count(), 25u);

  // Pose at step 0: the reference moved by (0, 0, 0.01), going up at 1 m/s. After the
  // 10-step interval the driven node 0 (on the x = 0 edge) is 0.01 + 1 m/s * 1 ms higher.
  h.send(1, sheetInput(id, 0, {0.0, 0.2, 0.01}, {0.0, 0.0, 1.0}));
  const std::optional<v1::DataPackage> after = h.lastData(1, id);
  ASSERT_TRUE(after && after->step() == 10u) << (h.errors(1).empty() ? "" : h.errors(1)[0].message());
  EXPECT_NEAR(after->deformable_body().displacements(2), 0.011, 1e-12);
  EXPECT_NEAR(after->deformable_body().displacements(0), 0.0, 1e-12);
  // Node 24 (x = 0.4, free) lags behind: the springs pull it up only gradually.
  EXPECT_LT(after->deformable_body().displacements(5), 0.011);
  EXPECT_NE(after->deformable_body().driven_force().z(), 0.0);
}

TEST(CosimDeformable, InputsItCannotTakeAreRefusedNamingTheField) {
  {
    ScratchDir dir;
    CosimHarness h(dir.path());
    compileSheet(h);
    ASSERT_TRUE(h.compiled(1));
    v1::DataPackage p = sheetInput(h.idOf(1, "sheet"), 0, {0.0, 0.2, 0.0}, core::Vec3::Zero());
    p.mutable_deformable_body_input()->mutable_orientation()->set_w(2.0);
    h.send(1, p);
    ASSERT_FALSE(h.errors(1).empty());
    EXPECT_EQ(h.errors(1).back().code(), v1::Error::INVALID_INPUT);
    EXPECT_EQ(h.errors(1).back().field(), "deformable_body_input.orientation");
  }
  {
    ScratchDir dir;
    CosimHarness h(dir.path());
    compileSheet(h, R"(, "attached_to": "tray")", R"({"name": "tray", "facet_body": {"role": "MOVING",
        "material": "glass", "box": {"size": {"x": 0.1, "y": 0.1, "z": 0.1}}}})");
    ASSERT_TRUE(h.compiled(1)) << (h.errors(1).empty() ? "" : h.errors(1)[0].message());
    h.send(1, sheetInput(h.idOf(1, "sheet"), 0, {0.0, 0.2, 0.0}, core::Vec3::Zero()));
    ASSERT_FALSE(h.errors(1).empty());
    EXPECT_EQ(h.errors(1).back().field(), "deformable_body_input");
    EXPECT_NE(h.errors(1).back().message().find("attached_to"), std::string::npos);
  }
  {
    ScratchDir dir;
    CosimHarness h(dir.path());
    h.hello(1);
    h.declare(1, boxJson(kDt, 0.0, R"("coupling": {"expected_count": 3})"));
    h.declare(1, R"({"name": "glass", "material": {}})");
    h.declare(1, sheetJson("", "[0, 25]"));
    ASSERT_FALSE(h.errors(1).empty());
    EXPECT_EQ(h.errors(1).back().code(), v1::Error::INVALID_DECLARATION);
    EXPECT_EQ(h.errors(1).back().field(), "sheet.mass_spring_body.output_nodes.nodes[1]");
  }
}

}  // namespace
}  // namespace demlink::server::test
