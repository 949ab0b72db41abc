// RigidBody declarations become engine meshes: the four geometries follow one placement
// rule (vertices relative to reference_point, placed at position / orientation), and
// mistakes name the field.
#include <gtest/gtest.h>

#include "demlink/core/geometry/stl_reader.hpp"
#include "scene_test_support.hpp"
#include "test_support.hpp"

namespace demlink::server::test {
namespace {

const std::string kBox = R"({"name": "box", "simulation_box": {"time_step": 1e-5, "end_time": 0.1}})";
const std::string kGlass = R"({"name": "glass", "material": {}})";

core::World worldWith(const std::string& body) {
  return std::move(translateScene(sceneOf({kBox, kGlass, body}), {}).world);
}

TEST(TranslateRigidBody, BoxStlBytesAndStlFileGiveTheSameWorldVertices) {
  ScratchDir dir;
  const std::string pose = R"("reference_point": {"x": 0.1}, "position": {"x": 1, "y": 2, "z": 3},
      "orientation": {"w": 0.8, "z": 0.6}, "linear_velocity": {"x": 0.5})";
  core::World fromBox = worldWith(R"({"name": "b", "rigid_body": {"material": "glass",
      "box": {"centre": {"z": 0.05}, "size": {"x": 0.2, "y": 0.1, "z": 0.1}}, )" + pose + "}}");
  const core::MeshBody& box = fromBox.meshes().at(0);
  EXPECT_EQ(box.name(), "b");
  EXPECT_NEAR((box.position() - core::Vec3(1, 2, 3)).norm(), 0.0, 1e-15);
  EXPECT_EQ(box.linearVelocity(), core::Vec3(0.5, 0, 0));
  // The same box as STL (body frame = box frame, shifted by the centre).
  std::vector<core::Vec3> vertices;
  for (const core::Vec3& v : box.localVertices()) vertices.push_back(v + core::Vec3(0.1, 0, 0));
  const std::filesystem::path stl = dir.path() / "box.stl";
  core::writeStlBinary(stl.string(), vertices, box.triangles());
  core::World fromFile = worldWith(R"({"name": "b", "rigid_body": {"material": "glass", "stl_file": ")" +
                                   stl.string() + "\", " + pose + "}}");
  const core::MeshBody& file = fromFile.meshes().at(0);
  ASSERT_EQ(file.worldVertices().size(), box.worldVertices().size());
  // The STL reader numbers vertices by first use: compare each vertex with its nearest.
  const auto nearest = [](const std::vector<core::Vec3>& set, const core::Vec3& v) {
    double best = 1e300;
    for (const core::Vec3& w : set) best = std::min(best, (w - v).norm());
    return best;
  };
  for (const core::Vec3& v : box.worldVertices()) EXPECT_LT(nearest(file.worldVertices(), v), 1e-7);  // float STL
  v1::Scene scene = sceneOf({kBox, kGlass, R"({"name": "b", "rigid_body": {"material": "glass"}})"});
  scene.mutable_components(2)->mutable_rigid_body()->set_stl_data(readText(stl));
  core::World fromBytes = std::move(translateScene(scene, {}).world);
  // No reference point: the local vertices are the STL's own coordinates.
  for (const core::Vec3& v : file.localVertices()) {
    EXPECT_LT(nearest(fromBytes.meshes().at(0).localVertices(), v + core::Vec3(0.1, 0, 0)), 1e-15);
  }
}

TEST(TranslateRigidBody, MistakesNameTheField) {
  EXPECT_EQ(errorFieldAfterInitialize(sceneOf({kBox, kGlass, R"({"name": "b", "rigid_body": {"material": "glass"}})"})),
            "components[2].rigid_body");
  EXPECT_EQ(errorFieldAfterInitialize(sceneOf({kBox, kGlass, R"({"name": "b", "rigid_body": {"material": "steel",
      "box": {"size": {"x": 1, "y": 1, "z": 1}}}})"})),
            "components[2].rigid_body.material");
  EXPECT_EQ(errorFieldAfterInitialize(sceneOf({kBox, kGlass, R"({"name": "b", "rigid_body": {"material": "glass",
      "box": {"size": {"x": 1, "y": 0, "z": 1}}}})"})),
            "components[2].rigid_body.box.size[1]");
  v1::Scene bytes = sceneOf({kBox, kGlass, R"({"name": "b", "rigid_body": {"material": "glass"}})"});
  bytes.mutable_components(2)->mutable_rigid_body()->set_stl_data("solid nothing\nendsolid\n");
  EXPECT_EQ(errorFieldAfterInitialize(bytes).rfind("components[2].rigid_body.stl_data", 0), 0u);
}

}  // namespace
}  // namespace demlink::server::test
