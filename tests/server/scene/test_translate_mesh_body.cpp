// The one path from a mesh declaration to core::MeshBody (translate_mesh_body) and the
// protobuf conversions every translator shares (proto_convert).
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "demlink/core/base/input_error.hpp"
#include "demlink/server/scene/proto_convert.hpp"
#include "demlink/server/scene/translate_mesh_body.hpp"
#include "scene_test_support.hpp"
#include "test_support.hpp"

namespace demlink::server::test {
namespace {

const std::string kBox = R"({"name": "box", "simulation_box": {"time_step": 1e-5, "end_time": 0.1}})";
const std::string kGlass = R"({"name": "glass", "material": {}})";

/// Two triangles of a unit square and one with a repeated corner, which the reader drops
/// with a warning.
constexpr const char* kStlWithDegenerate = R"(solid part
facet normal 0 0 1
 outer loop
  vertex 0 0 0
  vertex 1 0 0
  vertex 1 1 0
 endloop
endfacet
facet normal 0 0 1
 outer loop
  vertex 0 0 0
  vertex 1 1 0
  vertex 0 1 0
 endloop
endfacet
facet normal 0 0 1
 outer loop
  vertex 0 0 0
  vertex 0 0 0
  vertex 0 1 0
 endloop
endfacet
endsolid part
)";

core::InputError errorOf(const std::function<void()>& call) {
  try {
    call();
  } catch (const core::InputError& error) {
    return error;
  }
  ADD_FAILURE() << "expected an InputError";
  return core::InputError("(none)", "", "");
}

TEST(TranslateMeshBody, TheThreeDeclarationsOfOneStlGiveTheSameBody) {
  const ScratchDir dir;
  test::writeText(dir.path() / "part.stl", kStlWithDegenerate);
  const std::string pose = R"("stl_file": "part.stl", "material": "glass", "reference_point": {"x": 0.5},
      "position": {"x": 1, "y": 2, "z": 3}, "orientation": {"w": 0.8, "z": 0.6},
      "linear_velocity": {"x": 0.5}, "angular_velocity": {"z": 2})";
  const TranslatedScene t = translateScene(
      sceneOf({kBox, kGlass, R"({"name": "mesh", "mesh_body": {)" + pose + "}}",
               R"({"name": "facet", "facet_body": {"role": "MOVING", )" + pose + "}}",
               R"({"name": "rigid", "rigid_body": {)" + pose + "}}"}),
      dir.path());
  ASSERT_EQ(t.world.meshes().size(), 3u);
  const core::MeshBody& mesh = t.world.meshes()[0];
  EXPECT_EQ(mesh.localVertices().front(), core::Vec3(-0.5, 0, 0));
  EXPECT_EQ(mesh.position(), core::Vec3(1, 2, 3));
  EXPECT_EQ(mesh.angularVelocity(), core::Vec3(0, 0, 2));
  for (std::size_t k = 1; k < 3; ++k) {
    const core::MeshBody& other = t.world.meshes()[k];
    SCOPED_TRACE(other.name());
    EXPECT_EQ(other.localVertices(), mesh.localVertices());
    EXPECT_EQ(other.worldVertices(), mesh.worldVertices());
    EXPECT_EQ(other.triangles(), mesh.triangles());
    EXPECT_EQ(other.orientation().coeffs(), mesh.orientation().coeffs());
    EXPECT_EQ(other.linearVelocity(), mesh.linearVelocity());
    EXPECT_EQ(other.angularVelocity(), mesh.angularVelocity());
    // The STL reader's warning (the dropped triangle) reaches the compile report.
    EXPECT_EQ(other.loadWarnings(), mesh.loadWarnings());
  }
  EXPECT_FALSE(mesh.loadWarnings().empty());
}

TEST(TranslateMeshBody, BuildPlacesTheGeometryAndNamesTheCollisionWindow) {
  MeshBodyDeclaration d;
  d.name = "plate";
  d.mesh = core::axisAlignedBoxMesh(core::Vec3(0, 0, 0), core::Vec3(1, 1, 1));
  d.reference_point = core::Vec3(0.5, 0.5, 0.5);
  d.position = core::Vec3(0, 0, 2);
  d.active_from = 1.0;
  d.active_until = 2.0;
  const core::MeshBody body = buildMeshBody(d, "components[3].facet_body");
  EXPECT_EQ(body.localVertices().front(), core::Vec3(-0.5, -0.5, -0.5));
  EXPECT_EQ(body.worldVertices().front(), core::Vec3(-0.5, -0.5, 1.5));
  EXPECT_FALSE(body.collidesAt(0.999));
  EXPECT_TRUE(body.collidesAt(1.0));
  EXPECT_TRUE(body.collidesAt(1.999));
  EXPECT_FALSE(body.collidesAt(2.0));

  d.active_until = 0.5;
  EXPECT_EQ(errorOf([&] { (void)buildMeshBody(d, "components[3].facet_body"); }).field(),
            "components[3].facet_body.active_until");
  d.active_until = 2.0;
  d.stl_file = "/nonexistent/part.stl";
  EXPECT_EQ(errorOf([&] { (void)buildMeshBody(d, "components[3].rigid_body"); }).field(),
            "components[3].rigid_body.stl_file");
}

TEST(ProtoConvert, ChecksNameTheFieldAndPathsFollowTheScene) {
  v1::Vector3 v;
  v.set_y(std::numeric_limits<double>::quiet_NaN());
  EXPECT_EQ(errorOf([&] { (void)toFiniteVec3(v, "p.velocity"); }).field(), "p.velocity[1]");
  v1::Quaternion q;
  EXPECT_EQ(errorOf([&] { (void)toUnitQuat(q, "p.orientation"); }).field(), "p.orientation");
  q.set_w(2.0);
  EXPECT_EQ(toUnitQuat(q, "p.orientation").w(), 1.0);
  EXPECT_EQ(toQuat(q).w(), 2.0);  // unchecked: as given

  v1::Vector3 out;
  setVec3(out, core::Vec3(1, 2, 3));
  EXPECT_EQ(toVec3(out), core::Vec3(1, 2, 3));

  const ScratchDir dir;
  test::writeText(dir.path() / "a.csv", "x\n");
  EXPECT_EQ(resolveExistingSceneFile("a.csv", dir.path(), "f"), std::filesystem::canonical(dir.path() / "a.csv"));
  EXPECT_EQ(errorOf([&] { (void)resolveExistingSceneFile("b.csv", dir.path(), "f"); }).field(), "f");
  EXPECT_EQ(errorOf([&] { (void)resolveExistingSceneFile("", dir.path(), "f"); }).value(), "\"\"");
}

}  // namespace
}  // namespace demlink::server::test
