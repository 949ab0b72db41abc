/// Tests for sphere-vs-mesh contacts and their de-duplication. Expected values come from
/// independent geometry: the infinite plane for flat meshes, and the exact closest point of an
/// axis-aligned box (component-wise clamp) for the convex box.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <numeric>
#include <random>

#include "demlink/core/walls/mesh_body.hpp"
#include "demlink/core/walls/mesh_contact.hpp"
#include "demlink/core/walls/mesh_near_list.hpp"
#include "demlink/core/base/input_error.hpp"
#include "demlink/core/state/state_stream.hpp"

namespace demlink::core {
namespace {

using F = TriangleFeature;

std::vector<MeshContactPoint> contactsWithAll(const Vec3& centre, double radius,
                                              const TriangleMesh& mesh) {
  std::vector<std::uint32_t> all(mesh.triangles.size());
  std::iota(all.begin(), all.end(), 0u);
  std::vector<MeshContactPoint> out;
  collectSphereMeshContacts(centre, radius, all, mesh.vertices, mesh.triangles, out);
  return out;
}

/// Asserts exactly one contact equal to that of the infinite plane through `origin` with
/// unit normal `n` (centre on the positive side).
void expectSinglePlaneContact(const std::vector<MeshContactPoint>& contacts, const Vec3& centre,
                              double radius, const Vec3& origin, const Vec3& n) {
  ASSERT_EQ(contacts.size(), 1u) << "centre " << centre.transpose();
  const double height = (centre - origin).dot(n);
  const Vec3 foot = centre - height * n;
  EXPECT_NEAR((contacts[0].normal - n).norm(), 0.0, 1e-12);
  EXPECT_NEAR(contacts[0].overlap, radius - height, 1e-12);
  EXPECT_NEAR((contacts[0].point - foot).norm(), 0.0, 1e-12);
}

/// Number of triangles using vertex v.
int valence(const TriangleMesh& mesh, std::uint32_t v) {
  return static_cast<int>(
      std::count_if(mesh.triangles.begin(), mesh.triangles.end(),
                    [v](const auto& t) { return t[0] == v || t[1] == v || t[2] == v; }));
}

class FlatMesh : public ::testing::Test {
 protected:
  // 4 x 4 cells of 0.5 m on [-1, 1]^2 at z = 0; the vertex at the origin has valence 6.
  TriangleMesh mesh_ = rectangleMesh(Vec3::Zero(), 1.0, 1.0, 4, 4);
  const double radius_ = 0.1;
  const double height_ = 0.07;
};

TEST_F(FlatMesh, InteriorOfATriangleGivesOneFaceContact) {
  const Vec3 centre(0.1, 0.3, height_);
  const auto contacts = contactsWithAll(centre, radius_, mesh_);
  expectSinglePlaneContact(contacts, centre, radius_, Vec3::Zero(), Vec3::UnitZ());
  EXPECT_EQ(contacts[0].feature, F::Face);
}

TEST_F(FlatMesh, ExactlyAboveSharedGridEdgeGivesOneContact) {
  const Vec3 centre(0.25, 0.0, height_);  // midpoint of the edge (0,0)-(0.5,0)
  expectSinglePlaneContact(contactsWithAll(centre, radius_, mesh_), centre, radius_, Vec3::Zero(),
                           Vec3::UnitZ());
}

TEST_F(FlatMesh, ExactlyAboveSharedDiagonalEdgeGivesOneContact) {
  const Vec3 centre(0.25, 0.25, height_);  // midpoint of the diagonal (0,0)-(0.5,0.5)
  expectSinglePlaneContact(contactsWithAll(centre, radius_, mesh_), centre, radius_, Vec3::Zero(),
                           Vec3::UnitZ());
}

TEST_F(FlatMesh, ExactlyAboveVertexSharedBySixTrianglesGivesOneContact) {
  const std::uint32_t origin = 2 * 5 + 2;  // vertex (i=2, j=2)
  ASSERT_EQ(mesh_.vertices[origin], Vec3::Zero());
  ASSERT_EQ(valence(mesh_, origin), 6);
  const Vec3 centre(0.0, 0.0, height_);
  const auto contacts = contactsWithAll(centre, radius_, mesh_);
  expectSinglePlaneContact(contacts, centre, radius_, Vec3::Zero(), Vec3::UnitZ());
  EXPECT_TRUE(isVertex(contacts[0].feature));
}

TEST_F(FlatMesh, CentresVeryCloseToSharedVerticesAndEdgesMatchInfinitePlane) {
  // Offsets of 1e-8 .. 1e-3 radii from a valence-6 vertex: distance differences between the
  // neighbouring triangles' closest points are then far below any "1e-9 * radius" tolerance.
  std::mt19937_64 rng(4);
  std::uniform_real_distribution<double> angle(0.0, 2.0 * std::numbers::pi);
  std::uniform_real_distribution<double> logOffset(-8.0, -3.0);
  for (int k = 0; k < 3000; ++k) {
    const double delta = radius_ * std::pow(10.0, logOffset(rng));
    const double phi = angle(rng);
    const Vec3 base = (k % 2 == 0) ? Vec3(0.0, 0.0, 0.0) : Vec3(0.25, 0.25, 0.0);  // vertex/edge
    const Vec3 centre = base + Vec3(delta * std::cos(phi), delta * std::sin(phi), height_);
    expectSinglePlaneContact(contactsWithAll(centre, radius_, mesh_), centre, radius_, Vec3::Zero(),
                             Vec3::UnitZ());
  }
}

TEST_F(FlatMesh, RandomCentresOverInteriorMatchInfinitePlane) {
  std::mt19937_64 rng(99);
  std::uniform_real_distribution<double> xy(-0.85, 0.85);
  std::uniform_real_distribution<double> h(0.001, 0.0999);
  std::uniform_int_distribution<int> grid(-6, 6);
  for (int k = 0; k < 2000; ++k) {
    // Every other sample snaps to the 0.125 m lattice: grid vertices, edges and diagonals.
    const bool snap = (k % 2) == 1;
    const Vec3 centre(snap ? 0.125 * grid(rng) : xy(rng), snap ? 0.125 * grid(rng) : xy(rng),
                      h(rng));
    expectSinglePlaneContact(contactsWithAll(centre, radius_, mesh_), centre, radius_, Vec3::Zero(),
                             Vec3::UnitZ());
  }
}

TEST(MeshContact, TiltedFlatMeshMatchesInfinitePlaneIncludingVerticesAndEdges) {
  const TriangleMesh flat = rectangleMesh(Vec3::Zero(), 1.0, 1.0, 4, 4);
  const Mat3 rot = Eigen::AngleAxisd(0.7, Vec3(1.0, 2.0, -0.5).normalized()).toRotationMatrix();
  const Vec3 shift(0.3, -1.2, 2.5);
  TriangleMesh mesh = flat;
  for (Vec3& v : mesh.vertices) v = rot * v + shift;
  const Vec3 n = rot * Vec3::UnitZ();
  const double radius = 0.1;
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<double> h(0.001, 0.0999);
  std::uniform_real_distribution<double> xy(-0.85, 0.85);
  std::uniform_int_distribution<int> grid(-6, 6);
  for (int k = 0; k < 2000; ++k) {
    const bool snap = (k % 2) == 1;
    const Vec3 local(snap ? 0.125 * grid(rng) : xy(rng), snap ? 0.125 * grid(rng) : xy(rng), 0.0);
    const Vec3 centre = rot * local + shift + h(rng) * n;
    expectSinglePlaneContact(contactsWithAll(centre, radius, mesh), centre, radius, shift, n);
  }
}

TEST(MeshContact, SmallSphereOnFineMeshFarFromOriginGivesOneContact) {
  // Millimetre cells 300 km from the origin: coordinate rounding (ulp 6e-11 m) far exceeds
  // 1e-9 * radius, so the de-duplication tolerance must account for coordinate magnitude.
  // The rounded vertices also tilt each triangle by up to ~1e-7 rad, hence the tolerances.
  const double cell = 2e-3;
  const TriangleMesh flat = rectangleMesh(Vec3::Zero(), 2 * cell, 2 * cell, 4, 4);
  const Mat3 rot = Eigen::AngleAxisd(0.4, Vec3(0.3, -1.0, 0.2).normalized()).toRotationMatrix();
  const Vec3 shift(3.0e5, -3.0e3, 5.0e2);
  TriangleMesh mesh = flat;
  for (Vec3& v : mesh.vertices) v = rot * v + shift;
  const Vec3 n = rot * Vec3::UnitZ();
  const double radius = 1e-3;
  std::mt19937_64 rng(8);
  std::uniform_real_distribution<double> h(0.05 * radius, 0.95 * radius);
  std::uniform_int_distribution<int> grid(-6, 6);
  for (int k = 0; k < 1000; ++k) {
    const Vec3 local(0.25 * cell * grid(rng), 0.25 * cell * grid(rng), 0.0);
    const double height = h(rng);
    const Vec3 centre = rot * local + shift + height * n;
    const auto contacts = contactsWithAll(centre, radius, mesh);
    ASSERT_EQ(contacts.size(), 1u) << "local " << local.transpose();
    EXPECT_NEAR(contacts[0].overlap, radius - height, 3e-10);
    EXPECT_NEAR((contacts[0].normal - n).norm(), 0.0, 1e-6);
  }
}

TEST(MeshContact, ResultDoesNotDependOnCandidateOrder) {
  const TriangleMesh mesh = rectangleMesh(Vec3::Zero(), 1.0, 1.0, 4, 4);
  const Vec3 centre(0.0, 0.5, 0.05);  // above a shared vertex
  std::vector<std::uint32_t> order(mesh.triangles.size());
  std::iota(order.begin(), order.end(), 0u);
  std::vector<MeshContactPoint> reference;
  collectSphereMeshContacts(centre, 0.1, order, mesh.vertices, mesh.triangles, reference);
  ASSERT_EQ(reference.size(), 1u);
  std::mt19937_64 rng(3);
  for (int k = 0; k < 20; ++k) {
    std::shuffle(order.begin(), order.end(), rng);
    std::vector<MeshContactPoint> out;
    collectSphereMeshContacts(centre, 0.1, order, mesh.vertices, mesh.triangles, out);
    ASSERT_EQ(out.size(), 1u);
    EXPECT_EQ(out[0].triangle, reference[0].triangle);
    EXPECT_EQ(out[0].point, reference[0].point);
  }
}

TEST(MeshContact, ConvexRidgeOfBoxGivesOneEdgeContactAlongBisector) {
  const TriangleMesh box = axisAlignedBoxMesh(Vec3::Zero(), Vec3::Ones());
  const double radius = 0.2;
  const Vec3 centre(1.1, 0.5, 1.1);  // symmetric about the ridge x = 1, z = 1
  const auto contacts = contactsWithAll(centre, radius, box);
  ASSERT_EQ(contacts.size(), 1u);
  const Vec3 bisector = (Vec3::UnitX() + Vec3::UnitZ()).normalized();
  EXPECT_TRUE(isEdge(contacts[0].feature));
  EXPECT_NEAR((contacts[0].normal - bisector).norm(), 0.0, 1e-12);
  EXPECT_NEAR((contacts[0].point - Vec3(1.0, 0.5, 1.0)).norm(), 0.0, 1e-12);
  EXPECT_NEAR(contacts[0].overlap, radius - 0.1 * std::sqrt(2.0), 1e-12);
}

TEST(MeshContact, BoxCornerGivesOneVertexContact) {
  const TriangleMesh box = axisAlignedBoxMesh(Vec3::Zero(), Vec3::Ones());
  const double radius = 0.2;
  const Vec3 centre(1.1, 1.1, 1.1);
  const auto contacts = contactsWithAll(centre, radius, box);
  ASSERT_EQ(contacts.size(), 1u);
  EXPECT_TRUE(isVertex(contacts[0].feature));
  EXPECT_EQ(contacts[0].point, Vec3::Ones());
  EXPECT_NEAR((contacts[0].normal - Vec3::Ones().normalized()).norm(), 0.0, 1e-12);
  EXPECT_NEAR(contacts[0].overlap, radius - 0.1 * std::sqrt(3.0), 1e-12);
}

TEST(MeshContact, RandomCentresOutsideBoxGiveTheExactClosestPoint) {
  const Vec3 lo(-0.3, 0.2, 1.0), hi(0.9, 0.7, 1.6);
  const TriangleMesh box = axisAlignedBoxMesh(lo, hi);
  const double radius = 0.15;
  std::mt19937_64 rng(2024);
  std::uniform_real_distribution<double> ux(lo.x() - radius, hi.x() + radius);
  std::uniform_real_distribution<double> uy(lo.y() - radius, hi.y() + radius);
  std::uniform_real_distribution<double> uz(lo.z() - radius, hi.z() + radius);
  int tested = 0;
  while (tested < 3000) {
    const Vec3 centre(ux(rng), uy(rng), uz(rng));
    const Vec3 closest = centre.cwiseMax(lo).cwiseMin(hi);
    const double dist = (centre - closest).norm();
    if (!(dist > 0.0) || dist >= radius) continue;  // inside the box or out of reach
    ++tested;
    const auto contacts = contactsWithAll(centre, radius, box);
    ASSERT_EQ(contacts.size(), 1u) << "centre " << centre.transpose();
    EXPECT_NEAR((contacts[0].point - closest).norm(), 0.0, 1e-12);
    EXPECT_NEAR((contacts[0].normal - (centre - closest) / dist).norm(), 0.0, 1e-9);
    EXPECT_NEAR(contacts[0].overlap, radius - dist, 1e-12);
    // Number of clamped coordinates: 1 -> face, 2 -> edge, 3 -> corner.
    const int outside = static_cast<int>((centre.array() < lo.array()).count() +
                                         (centre.array() > hi.array()).count());
    const F feature = contacts[0].feature;
    const bool featureOk = (outside == 1 && feature == F::Face) ||
                           (outside == 2 && isEdge(feature)) || (outside == 3 && isVertex(feature));
    EXPECT_TRUE(featureOk) << "outside in " << outside << " axes, feature "
                           << static_cast<int>(feature);
  }
}

TEST(MeshContact, ConcaveValleyGivesTwoFaceContacts) {
  // Floor z = 0 (x, y in [0, 1], normal +z) and wall x = 0 (y, z in [0, 1], normal +x). The
  // meshes do not share vertex indices along the crease, only coordinates.
  TriangleMesh valley = rectangleMesh(Vec3(0.5, 0.5, 0.0), 0.5, 0.5, 2, 2);
  const TriangleMesh wallLocal = rectangleMesh(Vec3(-0.5, 0.5, 0.0), 0.5, 0.5, 2, 2);
  const auto offset = static_cast<std::uint32_t>(valley.vertices.size());
  for (const Vec3& v : wallLocal.vertices) valley.vertices.emplace_back(v.z(), v.y(), -v.x());
  for (const auto& t : wallLocal.triangles) {
    valley.triangles.push_back({t[0] + offset, t[1] + offset, t[2] + offset});
  }
  const double radius = 0.2;
  const Vec3 centre(0.15, 0.5, 0.15);  // y = 0.5 is also a shared edge on both planes
  auto contacts = contactsWithAll(centre, radius, valley);
  ASSERT_EQ(contacts.size(), 2u);
  std::sort(contacts.begin(), contacts.end(),
            [](const auto& p, const auto& q) { return p.normal.z() > q.normal.z(); });
  EXPECT_NEAR((contacts[0].normal - Vec3::UnitZ()).norm(), 0.0, 1e-12);
  EXPECT_NEAR((contacts[0].point - Vec3(0.15, 0.5, 0.0)).norm(), 0.0, 1e-12);
  EXPECT_NEAR(contacts[0].overlap, 0.05, 1e-12);
  EXPECT_NEAR((contacts[1].normal - Vec3::UnitX()).norm(), 0.0, 1e-12);
  EXPECT_NEAR((contacts[1].point - Vec3(0.0, 0.5, 0.15)).norm(), 0.0, 1e-12);
  EXPECT_NEAR(contacts[1].overlap, 0.05, 1e-12);
}

TEST(MeshContact, RandomCentresInsideBoxGiveOneFaceContactPerWallInReach) {
  // Inside a closed box every wall within reach is a separate concave contact (two-sided
  // triangles, normal pointing inward towards the centre).
  const Vec3 lo(0.0, 0.0, 0.0), hi(1.0, 0.8, 0.6);
  const TriangleMesh box = axisAlignedBoxMesh(lo, hi);
  const double radius = 0.2;
  std::mt19937_64 rng(77);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  for (int k = 0; k < 2000; ++k) {
    const Vec3 centre = lo + (hi - lo).cwiseProduct(Vec3(u(rng), u(rng), u(rng)));
    std::vector<std::pair<Vec3, double>> expected;  // (normal, overlap) per wall in reach
    for (int axis = 0; axis < 3; ++axis) {
      const double toLo = centre[axis] - lo[axis];
      const double toHi = hi[axis] - centre[axis];
      if (toLo < radius) expected.emplace_back(Vec3::Unit(axis), radius - toLo);
      if (toHi < radius) expected.emplace_back(-Vec3::Unit(axis), radius - toHi);
    }
    const auto contacts = contactsWithAll(centre, radius, box);
    ASSERT_EQ(contacts.size(), expected.size()) << "centre " << centre.transpose();
    for (const auto& [normal, overlap] : expected) {
      const auto match = std::find_if(contacts.begin(), contacts.end(), [&](const auto& c) {
        return (c.normal - normal).norm() < 1e-12 && std::abs(c.overlap - overlap) < 1e-12 &&
               c.feature == F::Face;
      });
      EXPECT_NE(match, contacts.end()) << "centre " << centre.transpose();
    }
  }
}

TEST(MeshContact, OpenBoundaryEdgeGivesOneEdgeContact) {
  const TriangleMesh mesh = rectangleMesh(Vec3::Zero(), 1.0, 1.0, 4, 4);
  const double radius = 0.1;
  const Vec3 centre(1.03, 0.1, 0.04);  // beyond the boundary x = 1
  const auto contacts = contactsWithAll(centre, radius, mesh);
  ASSERT_EQ(contacts.size(), 1u);
  EXPECT_TRUE(isEdge(contacts[0].feature));
  const Vec3 expectedNormal = Vec3(0.03, 0.0, 0.04) / 0.05;
  EXPECT_NEAR((contacts[0].normal - expectedNormal).norm(), 0.0, 1e-12);
  EXPECT_NEAR(contacts[0].overlap, radius - 0.05, 1e-12);
}

TEST(MeshContact, CentreBehindTriangleStillGivesFaceContactTowardsCentre) {
  const std::vector<Vec3> verts = {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0)};
  const std::vector<std::array<std::uint32_t, 3>> tris = {{0, 1, 2}};  // normal +z
  const std::vector<std::uint32_t> candidates = {0};
  std::vector<MeshContactPoint> out;
  collectSphereMeshContacts(Vec3(0.2, 0.2, -0.03), 0.05, candidates, verts, tris, out);
  ASSERT_EQ(out.size(), 1u);
  EXPECT_EQ(out[0].feature, F::Face);
  EXPECT_NEAR((out[0].normal + Vec3::UnitZ()).norm(), 0.0, 1e-12);
  EXPECT_NEAR(out[0].overlap, 0.02, 1e-15);
}

TEST(MeshContact, CentreOnTriangleUsesFaceNormal) {
  const std::vector<Vec3> verts = {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0)};
  const std::vector<std::array<std::uint32_t, 3>> tris = {{0, 2, 1}};  // normal -z
  const std::vector<std::uint32_t> candidates = {0};
  std::vector<MeshContactPoint> out;
  collectSphereMeshContacts(Vec3(0.25, 0.25, 0.0), 0.05, candidates, verts, tris, out);
  ASSERT_EQ(out.size(), 1u);
  EXPECT_EQ(out[0].normal, Vec3(0, 0, -1));
  EXPECT_EQ(out[0].overlap, 0.05);
}

TEST(MeshContact, NoContactOutOfReachAndExistingEntriesKept) {
  const TriangleMesh mesh = rectangleMesh(Vec3::Zero(), 1.0, 1.0, 2, 2);
  std::vector<std::uint32_t> all(mesh.triangles.size());
  std::iota(all.begin(), all.end(), 0u);
  std::vector<MeshContactPoint> out;
  out.push_back({42, Vec3(1, 2, 3), Vec3::UnitX(), 0.5, F::Face});
  collectSphereMeshContacts(Vec3(0.1, 0.1, 0.1), 0.1, all, mesh.vertices, mesh.triangles, out);
  ASSERT_EQ(out.size(), 1u);  // touching exactly (distance == radius) is not a contact
  collectSphereMeshContacts(Vec3(0.1, 0.1, 0.05), 0.1, all, mesh.vertices, mesh.triangles, out);
  ASSERT_EQ(out.size(), 2u);
  EXPECT_EQ(out[0].triangle, 42u);
  EXPECT_EQ(out[0].point, Vec3(1, 2, 3));
  EXPECT_NEAR(out[1].overlap, 0.05, 1e-15);
}

TEST(MeshContact, DuplicateCandidatesAreIgnored) {
  const TriangleMesh mesh = rectangleMesh(Vec3::Zero(), 1.0, 1.0, 2, 2);
  const std::vector<std::uint32_t> candidates = {1, 1, 3, 1};
  std::vector<MeshContactPoint> out;
  // Inside triangle 3 = upper-left half of cell (i=1, j=0): (0,-1), (1,0), (0,0).
  collectSphereMeshContacts(Vec3(0.2, -0.3, 0.05), 0.1, candidates, mesh.vertices, mesh.triangles,
                            out);
  ASSERT_EQ(out.size(), 1u);
  EXPECT_EQ(out[0].triangle, 3u);
  EXPECT_EQ(out[0].feature, F::Face);
}

}  // namespace
}  // namespace demlink::core

namespace demlink::core {
namespace {

/// A near list as MeshNearList::save writes it.
std::string nearListBytes(const std::vector<std::uint32_t>& slots, const std::vector<std::uint32_t>& offsets,
                          const std::vector<std::uint32_t>& triangles) {
  StateWriter out;
  out.writeVector(slots);
  out.writeVector(offsets);
  out.writeVector(triangles);
  out.writeVector(std::vector<Vec3>(triangles.size(), Vec3::Zero()));
  return out.bytes();
}

/// The message restoring `bytes` into a list of 10 slots and 8 triangles throws; empty if none.
std::string restoreError(const std::string& bytes) {
  MeshNearList list;
  StateReader in(bytes, "near.bin", "MESH");
  try {
    list.restore(in, 10, 8);
  } catch (const InputError& e) {
    return e.what();
  }
  return {};
}

// The force stage finds a chunk's entries and a contact's spring by binary search, so a
// checkpoint's list out of order is refused, naming what is out of order.
TEST(MeshNearListRestore, RefusesSlotsOrTrianglesOutOfOrder) {
  EXPECT_EQ(restoreError(nearListBytes({1, 4}, {0, 2, 3}, {0, 5, 2})), "");
  const std::string slots = restoreError(nearListBytes({4, 1}, {0, 2, 3}, {0, 5, 2}));
  EXPECT_NE(slots.find("slots are not strictly ascending"), std::string::npos) << slots;
  const std::string twice = restoreError(nearListBytes({4, 4}, {0, 2, 3}, {0, 5, 2}));
  EXPECT_NE(twice.find("slots are not strictly ascending"), std::string::npos) << twice;
  const std::string triangles = restoreError(nearListBytes({1, 4}, {0, 2, 3}, {5, 0, 2}));
  EXPECT_NE(triangles.find("triangles of slot 1"), std::string::npos) << triangles;
}

}  // namespace
}  // namespace demlink::core
