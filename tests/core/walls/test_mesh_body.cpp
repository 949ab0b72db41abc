/// Tests for MeshBody kinematics and wrench accumulation, and the box/rectangle mesh helpers.
/// Rotations are checked against Rodrigues' formula written out here, velocities against
/// finite differences of the integrated motion, torques against hand-computed cross products.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <map>
#include <numbers>
#include <random>

#include "demlink/core/base/input_error.hpp"
#include "demlink/core/walls/mesh_body.hpp"
#include "demlink/core/geometry/stl_reader.hpp"

namespace demlink::core {
namespace {

/// Rotation matrix for angle theta about unit axis k: I + sin(theta) K + (1 - cos(theta)) K^2.
Mat3 rodrigues(const Vec3& k, double theta) {
  Mat3 kx;
  kx << 0.0, -k.z(), k.y(), k.z(), 0.0, -k.x(), -k.y(), k.x(), 0.0;
  return Mat3::Identity() + std::sin(theta) * kx + (1.0 - std::cos(theta)) * kx * kx;
}

MeshBody makeBox() {
  TriangleMesh box = axisAlignedBoxMesh(Vec3(-0.5, -0.2, -0.1), Vec3(0.3, 0.4, 0.6));
  return MeshBody("box", box.vertices, box.triangles, 3);
}

TEST(MeshBody, AdvanceRotatesExactlyAboutFixedWorldAxis) {
  MeshBody body = makeBox();
  const Vec3 axis0(0.3, -0.4, 0.2);
  const Quat q0(Eigen::AngleAxisd(0.9, axis0.normalized()));
  const Vec3 p0(1.0, 2.0, -0.5);
  body.setPose(p0, q0);
  const Vec3 omega(0.4, 1.5, -2.0);
  const Vec3 v(0.2, -0.1, 0.3);
  body.setVelocity(v, omega);
  const double dt = 0.37;
  body.advance(dt);

  const Mat3 r0 = rodrigues(axis0.normalized(), 0.9);
  const Mat3 step = rodrigues(omega.normalized(), omega.norm() * dt);
  for (std::size_t i = 0; i < body.localVertices().size(); ++i) {
    const Vec3 expected = p0 + v * dt + step * r0 * body.localVertices()[i];
    EXPECT_NEAR((body.worldVertices()[i] - expected).norm(), 0.0, 1e-14) << "vertex " << i;
  }
  EXPECT_NEAR(body.orientation().norm(), 1.0, 1e-15);
  EXPECT_NEAR((body.position() - (p0 + v * dt)).norm(), 0.0, 1e-15);
}

TEST(MeshBody, ManySmallStepsEqualOneLargeStep) {
  MeshBody a = makeBox();
  MeshBody b = makeBox();
  const Vec3 omega(-1.0, 0.5, 3.0);
  a.setVelocity(Vec3(1, 0, 0), omega);
  b.setVelocity(Vec3(1, 0, 0), omega);
  for (int k = 0; k < 1000; ++k) a.advance(1e-3);
  b.advance(1.0);
  for (std::size_t i = 0; i < a.worldVertices().size(); ++i) {
    EXPECT_NEAR((a.worldVertices()[i] - b.worldVertices()[i]).norm(), 0.0, 1e-12);
  }
}

TEST(MeshBody, WorldNormalsFollowRotationAndPointOutward) {
  MeshBody body = makeBox();
  body.setPose(Vec3(0.1, 0.2, 0.3), Quat(Eigen::AngleAxisd(2.0, Vec3(1, 1, 0).normalized())));
  const auto& w = body.worldVertices();
  Vec3 centroid = Vec3::Zero();
  for (const Vec3& x : w) centroid += x / static_cast<double>(w.size());
  for (std::size_t t = 0; t < body.triangles().size(); ++t) {
    const auto& tri = body.triangles()[t];
    const Vec3 n = (w[tri[1]] - w[tri[0]]).cross(w[tri[2]] - w[tri[0]]).normalized();
    EXPECT_NEAR((body.triangleNormals()[t] - n).norm(), 0.0, 1e-14);
    const Vec3 faceCentre = (w[tri[0]] + w[tri[1]] + w[tri[2]]) / 3.0;
    EXPECT_GT(n.dot(faceCentre - centroid), 0.0) << "triangle " << t << " normal points inward";
  }
}

TEST(MeshBody, VelocityAtHandComputedCase) {
  MeshBody body = makeBox();
  body.setVelocity(Vec3(1.0, 0.0, 0.0), Vec3(0.0, 0.0, 2.0));
  // w x r = (0,0,2) x (0,1,0) = (-2, 0, 0), so v = (1,0,0) + (-2,0,0).
  EXPECT_EQ(body.velocityAt(Vec3(0.0, 1.0, 0.0)), Vec3(-1.0, 0.0, 0.0));
}

TEST(MeshBody, VelocityAtMatchesFiniteDifferenceOfMotion) {
  MeshBody body = makeBox();
  body.setPose(Vec3(0.4, -0.3, 1.0), Quat(Eigen::AngleAxisd(0.3, Vec3::UnitY())));
  body.setVelocity(Vec3(0.5, 0.25, -1.0), Vec3(2.0, -1.0, 0.5));
  const double h = 1e-5;
  const auto before = body.worldVertices();
  const Vec3 predicted = body.velocityAt(before[6]);
  MeshBody back = body;
  back.advance(-h);
  body.advance(h);
  const Vec3 fd = (body.worldVertices()[6] - back.worldVertices()[6]) / (2.0 * h);
  EXPECT_NEAR((fd - predicted).norm(), 0.0, 1e-8);
}

TEST(MeshBody, TorqueAccumulatesAboutReferencePoint) {
  MeshBody body = makeBox();
  const Vec3 ref(2.0, -1.0, 0.5);
  body.setPose(ref, Quat::Identity());
  // F = (0,0,1) at ref + (1,0,0): torque (1,0,0) x (0,0,1) = (0,-1,0).
  body.addContactForce(Vec3(0, 0, 1), ref + Vec3(1, 0, 0));
  EXPECT_EQ(body.force(), Vec3(0, 0, 1));
  EXPECT_EQ(body.torque(), Vec3(0, -1, 0));
  // A couple: +F at ref + (0,1,0), -F at ref - (0,1,0) with F = (3,0,0): net force zero,
  // torque 2 * (0,1,0) x (3,0,0) = 2 * (0,0,-3).
  body.addContactForce(Vec3(3, 0, 0), ref + Vec3(0, 1, 0));
  body.addContactForce(Vec3(-3, 0, 0), ref - Vec3(0, 1, 0));
  EXPECT_EQ(body.force(), Vec3(0, 0, 1));
  EXPECT_EQ(body.torque(), Vec3(0, -1, -6));
  body.addWrench(Vec3(1, 1, 1), Vec3(0.5, 0, 0));
  EXPECT_EQ(body.force(), Vec3(1, 1, 2));
  EXPECT_EQ(body.torque(), Vec3(0.5, -1, -6));
  body.clearWrench();
  EXPECT_EQ(body.force(), Vec3::Zero());
  EXPECT_EQ(body.torque(), Vec3::Zero());
}

TEST(MeshBody, RandomForcesTorqueEqualsComponentWiseSum) {
  MeshBody body = makeBox();
  const Vec3 ref(0.3, 0.1, -0.2);
  body.setPose(ref, Quat::Identity());
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  double tx = 0, ty = 0, tz = 0;
  for (int k = 0; k < 50; ++k) {
    const Vec3 f(u(rng), u(rng), u(rng));
    const Vec3 x(u(rng), u(rng), u(rng));
    body.addContactForce(f, x);
    const double rx = x.x() - ref.x(), ry = x.y() - ref.y(), rz = x.z() - ref.z();
    tx += ry * f.z() - rz * f.y();
    ty += rz * f.x() - rx * f.z();
    tz += rx * f.y() - ry * f.x();
  }
  EXPECT_NEAR((body.torque() - Vec3(tx, ty, tz)).norm(), 0.0, 1e-12);
}

TEST(MeshBody, SetPoseNormalisesAndRejectsInvalidQuaternions) {
  MeshBody body = makeBox();
  body.setPose(Vec3::Zero(), Quat(2.0, 0.0, 0.0, 2.0));
  EXPECT_NEAR(body.orientation().norm(), 1.0, 1e-15);
  EXPECT_NEAR(body.orientation().w(), std::sqrt(0.5), 1e-15);
  const auto expectPoseError = [&body](const Quat& q) {
    try {
      body.setPose(Vec3::Zero(), q);
      ADD_FAILURE() << "expected InputError";
    } catch (const InputError& e) {
      EXPECT_EQ(e.field(), "pose.orientation");
    }
  };
  expectPoseError(Quat(std::nan(""), 0.0, 0.0, 1.0));
  expectPoseError(Quat(0.0, 0.0, 0.0, 0.0));
  EXPECT_THROW(body.setPose(Vec3(INFINITY, 0, 0), Quat::Identity()), InputError);
  EXPECT_THROW(body.setVelocity(Vec3::Zero(), Vec3(0, NAN, 0)), InputError);
}

TEST(MeshBody, MaxDisplacementSinceMarkBoundsEveryVertex) {
  MeshBody body = makeBox();
  body.setVelocity(Vec3(0.3, 0.0, 0.0), Vec3::Zero());
  body.advance(2.0);  // pure translation by 0.6: bound is exact
  EXPECT_NEAR(body.maxDisplacementSinceMark(), 0.6, 1e-15);
  body.markNeighbourBuild();
  EXPECT_EQ(body.maxDisplacementSinceMark(), 0.0);

  std::mt19937_64 rng(17);
  std::uniform_real_distribution<double> u(-2.0, 2.0);
  for (int trial = 0; trial < 50; ++trial) {
    body.markNeighbourBuild();
    const auto atMark = body.worldVertices();
    body.setVelocity(Vec3(u(rng), u(rng), u(rng)), Vec3(u(rng), u(rng), u(rng)));
    for (int k = 0; k < 5; ++k) body.advance(0.05 * (1.0 + u(rng)));
    double actual = 0.0;
    for (std::size_t i = 0; i < atMark.size(); ++i) {
      actual = std::max(actual, (body.worldVertices()[i] - atMark[i]).norm());
    }
    const double bound = body.maxDisplacementSinceMark();
    EXPECT_GE(bound, actual - 1e-12);
    // Cheap bound, but not absurd: translation + rotation terms each at most the true max.
    EXPECT_LE(bound, 2.0 * actual + 2.0 * body.boundingRadius() + 1e-12);
  }
}

TEST(MeshBody, RotationBoundUsesChordNotArc) {
  // Rotation by pi about z: vertex at distance r from the reference point moves by 2r.
  MeshBody body("seg", {Vec3(1, 0, 0), Vec3(0, 1, 0), Vec3(0, 0, 0)}, {{0, 1, 2}});
  body.setVelocity(Vec3::Zero(), Vec3(0, 0, std::numbers::pi));
  body.advance(1.0);
  EXPECT_NEAR(body.maxDisplacementSinceMark(), 2.0, 1e-12);
  EXPECT_NEAR((body.worldVertices()[0] - Vec3(-1, 0, 0)).norm(), 0.0, 1e-12);
}

TEST(MeshBody, ConstructorValidatesInput) {
  EXPECT_THROW(MeshBody("m", {Vec3::Zero()}, {}), InputError);
  try {
    MeshBody("m", {Vec3::Zero(), Vec3::UnitX(), Vec3::UnitY()}, {{0, 1, 3}});
    ADD_FAILURE() << "expected InputError";
  } catch (const InputError& e) {
    EXPECT_EQ(e.field(), "m.triangles[0]");
    EXPECT_EQ(e.value(), "3");
  }
}

TEST(MeshBody, FromStlStoresVerticesRelativeToReferencePoint) {
  const auto path = std::filesystem::temp_directory_path() / "demlink_test_mesh_body_box.stl";
  const TriangleMesh box = axisAlignedBoxMesh(Vec3(1.0, 2.0, 3.0), Vec3(2.0, 4.0, 3.5));
  writeStlBinary(path.string(), box.vertices, box.triangles);
  const Vec3 ref(1.5, 3.0, 3.25);
  const MeshBody body = MeshBody::fromStl("drum", path.string(), ref, 7);
  std::filesystem::remove(path);
  EXPECT_EQ(body.name(), "drum");
  EXPECT_EQ(body.materialIndex(), 7u);
  ASSERT_EQ(body.localVertices().size(), 8u);
  ASSERT_EQ(body.triangles().size(), 12u);
  EXPECT_EQ(body.position(), ref);
  EXPECT_EQ(body.maxDisplacementSinceMark(), 0.0);
  for (const Vec3& v : box.vertices) {  // file coordinates are exact in float
    const auto& local = body.localVertices();
    EXPECT_EQ(std::count(local.begin(), local.end(), Vec3(v - ref)), 1) << v.transpose();
  }
  for (std::size_t i = 0; i < 8; ++i) {
    EXPECT_NEAR((body.worldVertices()[i] - (body.localVertices()[i] + ref)).norm(), 0.0, 1e-15);
  }
  EXPECT_NEAR(body.boundingRadius(), std::sqrt(0.25 + 1.0 + 0.0625), 1e-15);
}

TEST(MeshHelpers, BoxIsClosedWithOutwardNormals) {
  const Vec3 lo(-1, 0, 2), hi(1, 0.5, 3);
  const TriangleMesh box = axisAlignedBoxMesh(lo, hi);
  ASSERT_EQ(box.vertices.size(), 8u);
  ASSERT_EQ(box.triangles.size(), 12u);
  // Closed and consistently oriented: every directed edge appears once, its reverse once.
  std::map<std::pair<std::uint32_t, std::uint32_t>, int> directed;
  double signedVolume = 0.0;
  for (const auto& t : box.triangles) {
    for (int k = 0; k < 3; ++k) ++directed[{t[k], t[(k + 1) % 3]}];
    const Vec3& a = box.vertices[t[0]];
    signedVolume += a.dot(box.vertices[t[1]].cross(box.vertices[t[2]])) / 6.0;
  }
  for (const auto& [edge, count] : directed) {
    EXPECT_EQ(count, 1);
    EXPECT_EQ(directed.count({edge.second, edge.first}), 1u);
  }
  // Divergence theorem: outward orientation gives the positive box volume.
  EXPECT_NEAR(signedVolume, 2.0 * 0.5 * 1.0, 1e-12);
  EXPECT_THROW((void)axisAlignedBoxMesh(hi, lo), InputError);
}

TEST(MeshHelpers, RectangleIsFlatSubdividedAndFacesUp) {
  const TriangleMesh r = rectangleMesh(Vec3(1.0, -2.0, 0.25), 0.5, 1.5, 3, 2);
  ASSERT_EQ(r.vertices.size(), 4u * 3u);
  ASSERT_EQ(r.triangles.size(), 2u * 3u * 2u);
  double area = 0.0;
  for (const auto& t : r.triangles) {
    const Vec3 n = (r.vertices[t[1]] - r.vertices[t[0]]).cross(r.vertices[t[2]] - r.vertices[t[0]]);
    EXPECT_GT(n.z(), 0.0);
    EXPECT_NEAR(n.x(), 0.0, 1e-15);
    EXPECT_NEAR(n.y(), 0.0, 1e-15);
    area += 0.5 * n.norm();
  }
  EXPECT_NEAR(area, 1.0 * 3.0, 1e-12);
  for (const Vec3& v : r.vertices) EXPECT_EQ(v.z(), 0.25);
  EXPECT_EQ(r.vertices.front(), Vec3(0.5, -3.5, 0.25));
  EXPECT_EQ(r.vertices.back(), Vec3(1.5, -0.5, 0.25));
  EXPECT_THROW((void)rectangleMesh(Vec3::Zero(), 1.0, 1.0, 0, 1), InputError);
  EXPECT_THROW((void)rectangleMesh(Vec3::Zero(), -1.0, 1.0, 1, 1), InputError);
}

}  // namespace
}  // namespace demlink::core
