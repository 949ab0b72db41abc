// When a rigid mesh's near list may have missed a contact (mesh_rebuild_check.hpp): the
// particles' displacement seen from the mesh's frame against the skin.
//  - A mesh at its mark: the absolute displacement decides, with the whole skin.
//  - A translated or rotated mesh: particles carried along (a load in a bucket) leave the
//    list fresh however far they travel; particles left behind within the mesh's reach
//    make it stale once the mesh has moved more than the skin away from them, those out
//    of its reach do not.
//  - A mesh outside its collision window, and a changed particle count.
//  - In a world: a sphere resting in a tray carried at constant speed needs no rebuild
//    while the tray travels 50 skins; the rest still holds the sphere (no missed contact).
#include <gtest/gtest.h>

#include <vector>

#include "demlink/core/walls/mesh_rebuild_check.hpp"
#include "test_scenes.hpp"

namespace demlink::core {
namespace {

constexpr double kSkin = 0.01;  // [m]

MeshBody tray() {
  const TriangleMesh box = axisAlignedBoxMesh(Vec3(-0.1, -0.1, -0.02), Vec3(0.1, 0.1, 0.0));
  return MeshBody("tray", box.vertices, box.triangles, 0);
}

std::vector<Vec3> builtPositions() { return {Vec3(0.0, 0.0, 0.011), Vec3(0.05, -0.03, 0.02), Vec3(-0.2, 0.1, 0.3)}; }

bool stale(const MeshBody& mesh, const std::vector<Vec3>& now, char colliding = 1) {
  const std::vector<MeshBody> meshes{mesh};
  const std::vector<char> flags{colliding};
  const std::vector<double> radius(now.size(), 0.005);
  return meshNearListsStale(meshes, flags, builtPositions(), now, radius, kSkin, nullptr);
}

TEST(MeshRebuildCheck, AMeshAtItsMarkLetsParticlesUseTheWholeSkin) {
  std::vector<Vec3> now = builtPositions();
  now[1].x() += 0.9 * kSkin;  // beyond skin/2, the classic rule's limit
  EXPECT_FALSE(stale(tray(), now));
  now[1].x() += 0.2 * kSkin;
  EXPECT_TRUE(stale(tray(), now));
}

TEST(MeshRebuildCheck, ParticlesCarriedByATranslatedMeshKeepTheListFresh) {
  MeshBody mesh = tray();
  const Vec3 shift(0.3, -0.1, 0.05);  // 33 skins
  mesh.setPose(mesh.position() + shift, mesh.orientation());
  std::vector<Vec3> carried = builtPositions();
  for (Vec3& x : carried) x += shift;
  EXPECT_FALSE(stale(mesh, carried));
  carried[0].z() += 1.1 * kSkin;  // one particle lifts off the floor by more than the skin
  EXPECT_TRUE(stale(mesh, carried));
  // Left behind 33 skins away: out of the tray's reach (bounding radius 0.143 m), so no
  // contact of theirs can be missing now.
  EXPECT_FALSE(stale(mesh, builtPositions()));
}

TEST(MeshRebuildCheck, ParticlesLeftBehindWithinReachMakeTheListStale) {
  MeshBody mesh = tray();
  mesh.setPose(mesh.position() + Vec3(1.1 * kSkin, 0.0, 0.0), mesh.orientation());
  EXPECT_TRUE(stale(mesh, builtPositions()));
  std::vector<Vec3> now = builtPositions();
  now[2] += Vec3(1.0, 0.0, 0.0);  // the far particle: out of reach before and after
  for (int k = 0; k < 2; ++k) now[k].x() += 1.1 * kSkin;
  EXPECT_FALSE(stale(mesh, now));
}

TEST(MeshRebuildCheck, AMeshMovingLessThanTheSkinFromStillParticlesNeedsNoRebuild) {
  MeshBody mesh = tray();
  mesh.setPose(mesh.position() + Vec3(0.0, 0.0, 0.9 * kSkin), mesh.orientation());
  EXPECT_FALSE(stale(mesh, builtPositions()));
  // A particle moving 0.2 skin the other way: 1.1 skins apart in the mesh's frame.
  std::vector<Vec3> apart = builtPositions();
  apart[0].z() -= 0.2 * kSkin;
  EXPECT_TRUE(stale(mesh, apart));
  apart[0].z() += 0.15 * kSkin;  // 0.95 skin apart
  EXPECT_FALSE(stale(mesh, apart));
  mesh.setPose(mesh.position() + Vec3(0.0, 0.0, 0.2 * kSkin), mesh.orientation());
  EXPECT_TRUE(stale(mesh, builtPositions()));
}

TEST(MeshRebuildCheck, ParticlesCarriedByARotatedMeshKeepTheListFresh) {
  MeshBody mesh = tray();
  const Quat turn(Eigen::AngleAxisd(0.7, Vec3(0.2, 0.3, 1.0).normalized()));
  mesh.setPose(mesh.position(), turn * mesh.orientation());
  std::vector<Vec3> carried = builtPositions();
  for (Vec3& x : carried) x = mesh.position() + turn * (x - mesh.markPosition());
  EXPECT_FALSE(stale(mesh, carried));
  EXPECT_TRUE(stale(mesh, builtPositions()));  // particle 1, 6 cm off the axis, left behind by 4 skins
}

TEST(MeshRebuildCheck, AMeshOutOfContactAndAChangedCount) {
  MeshBody mesh = tray();
  mesh.setPose(mesh.position() + Vec3(1.0, 0.0, 0.0), mesh.orientation());
  EXPECT_FALSE(stale(mesh, builtPositions(), 0));
  std::vector<Vec3> more = builtPositions();
  more.emplace_back(1.0, 1.0, 1.0);
  EXPECT_TRUE(stale(tray(), more));
}

TEST(MeshRebuildCheck, ASphereRidingInACarriedTrayNeedsNoRebuild) {
  // No gravity, the sphere touching the tray's floor with the tray's velocity: carried
  // together, nothing moves relative to anything, so the lists stay valid throughout.
  const double speed = 1.0;  // [m/s]
  SimulationSettings s = test::fineSettings(1e-5, 2.0);
  s.gravity = Vec3::Zero();
  World world(s);
  const auto mat = world.addMaterial(test::testMaterial(0.5, 0.3));
  const TriangleMesh box = axisAlignedBoxMesh(Vec3(-0.1, -0.1, -0.02), Vec3(0.1, 0.1, 0.0));
  const auto index = world.addMesh(MeshBody("tray", box.vertices, box.triangles, mat));
  world.mesh(index).setVelocity(Vec3(speed, 0.0, 0.0), Vec3::Zero());
  ParticleSpec p;
  p.radius = 0.005;
  p.position = Vec3(0.0, 0.0, 0.005);
  p.velocity = Vec3(speed, 0.0, 0.0);
  world.addParticle(p);
  world.initialize();
  const double skin = world.neighbourList().skin();
  const std::uint64_t before = world.neighbourList().buildCount();
  const auto steps = static_cast<int>(50.0 * skin / speed / s.time_step);
  for (int n = 0; n < steps; ++n) world.step();
  EXPECT_EQ(world.neighbourList().buildCount(), before);
  EXPECT_NEAR(world.particles().position[0].x(), world.meshes()[index].position().x(), 1e-9);
  EXPECT_NEAR(world.particles().position[0].z(), 0.005, 1e-9);
}

}  // namespace
}  // namespace demlink::core
