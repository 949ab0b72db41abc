/// Volume, centre of mass and inertia of closed meshes against closed forms, and the
/// refusal of meshes that bound no solid.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "demlink/core/base/input_error.hpp"
#include "demlink/core/geometry/closed_surface.hpp"
#include "demlink/core/geometry/solid_mass_properties.hpp"
#include "walls/closed_meshes.hpp"

namespace demlink::core {
namespace {

SolidMassProperties properties(const StlMesh& mesh) {
  requireClosedSurface(mesh, "test");
  return solidMassProperties(mesh, "test");
}

void expectMatrixNear(const Mat3& actual, const Mat3& expected, double tolerance) {
  EXPECT_LT((actual - expected).norm(), tolerance * expected.norm()) << "actual\n" << actual << "\nexpected\n" << expected;
}

TEST(SolidMassProperties, BoxMatchesClosedForm) {
  const double a = 0.3;
  const double b = 0.2;
  const double c = 0.1;
  const Vec3 lo(-0.05, 0.4, 1.0);
  const SolidMassProperties p = properties(test::boxMesh(lo, lo + Vec3(a, b, c)));
  const double volume = a * b * c;
  EXPECT_NEAR(p.volume, volume, 1e-14 * volume);
  EXPECT_LT((p.centroid - (lo + 0.5 * Vec3(a, b, c))).norm(), 1e-14);
  const Mat3 expected = Vec3(volume * (b * b + c * c) / 12, volume * (a * a + c * c) / 12, volume * (a * a + b * b) / 12)
                            .asDiagonal();
  expectMatrixNear(p.inertia, expected, 1e-12);
  EXPECT_NEAR(p.principal.moments[0], volume * (b * b + c * c) / 12, 1e-12 * volume * a * a);
  EXPECT_NEAR(p.principal.moments[2], volume * (a * a + b * b) / 12, 1e-12 * volume * a * a);
  EXPECT_NEAR(p.principal.axes(0, 0), 1.0, 1e-12);  // smallest moment about the longest side, x
  EXPECT_NEAR(p.principal.axes(2, 2), 1.0, 1e-12);  // largest about the shortest, z
  EXPECT_NEAR(p.bounding_radius, 0.5 * std::sqrt(a * a + b * b + c * c), 1e-14);
}

TEST(SolidMassProperties, CubeHasEqualMoments) {
  const double side = 2.0;
  const SolidMassProperties p = properties(test::boxMesh(Vec3(-1, -1, -1), Vec3(1, 1, 1)));
  const double moment = std::pow(side, 5) / 6.0;
  for (int k = 0; k < 3; ++k) EXPECT_NEAR(p.principal.moments[k], moment, 1e-13 * moment);
  EXPECT_LT(p.centroid.norm(), 1e-15);
}

TEST(SolidMassProperties, TetrahedronMatchesClosedForm) {
  // Corner tetrahedron of edge L: V = L^3/6, centroid L/4 (1,1,1); about the centroid
  // I_xx = L^5/80 and I_xy = +L^5/480, so the moments are 5 L^5/480 (twice) and L^5/60
  // about (1,1,1).
  const double side = 0.7;
  const Vec3 origin(3.0, -2.0, 0.5);
  const SolidMassProperties p = properties(test::cornerTetrahedron(origin, side));
  const double l5 = std::pow(side, 5);
  EXPECT_NEAR(p.volume, side * side * side / 6, 1e-14);
  EXPECT_LT((p.centroid - (origin + Vec3::Constant(side / 4))).norm(), 1e-13);
  Mat3 expected = Mat3::Constant(l5 / 480);
  expected.diagonal().setConstant(l5 / 80);
  expectMatrixNear(p.inertia, expected, 1e-11);
  EXPECT_NEAR(p.principal.moments[0], 5 * l5 / 480, 1e-11 * l5);
  EXPECT_NEAR(p.principal.moments[1], 5 * l5 / 480, 1e-11 * l5);
  EXPECT_NEAR(p.principal.moments[2], l5 / 60, 1e-11 * l5);
  EXPECT_NEAR(std::abs(p.principal.axes.col(2).dot(Vec3::Ones().normalized())), 1.0, 1e-10);
}

TEST(SolidMassProperties, PolygonPrismIsExactAndConvergesToTheCylinder) {
  // A regular n-gon of circumradius R: area A = n R^2 sin(t) / 2 and polar moment
  // J = n R^4 sin(t) (2 + cos(t)) / 12, t = 2 pi / n (sum of its centre triangles).
  const double radius = 0.4;
  const double height = 1.5;
  double previous = 1.0;
  for (const std::uint32_t sides : {8u, 16u, 32u, 64u, 128u}) {
    const SolidMassProperties p = properties(test::polygonPrism(radius, height, sides));
    const double t = 2.0 * std::numbers::pi / sides;
    const double area = sides * radius * radius * std::sin(t) / 2;
    const double polar = sides * std::pow(radius, 4) * std::sin(t) * (2 + std::cos(t)) / 12;
    EXPECT_NEAR(p.volume, area * height, 1e-13 * area * height);
    EXPECT_LT((p.centroid - Vec3(0, 0, height / 2)).norm(), 1e-13);
    EXPECT_NEAR(p.inertia(2, 2), polar * height, 1e-12 * polar * height);
    EXPECT_NEAR(p.inertia(0, 0), polar * height / 2 + area * height * height * height / 12, 1e-12 * p.inertia(0, 0));
    const double cylinder = std::numbers::pi * radius * radius * height;
    const double error = std::abs(p.volume - cylinder) / cylinder;
    EXPECT_LT(error, previous / 3.5) << sides << " sides";  // O(n^-2)
    previous = error;
  }
  EXPECT_LT(previous, 5e-4);
}

TEST(SolidMassProperties, TriangulatedSphereConvergesToTheBall) {
  const double radius = 0.25;
  const double volume = 4.0 / 3.0 * std::numbers::pi * std::pow(radius, 3);
  const double moment = 0.4 * volume * radius * radius;
  double previousVolume = 1.0;
  double previousMoment = 1.0;
  for (const std::uint32_t rings : {8u, 16u, 32u, 64u}) {
    const SolidMassProperties p = properties(test::uvSphere(radius, rings));
    const double volumeError = std::abs(p.volume - volume) / volume;
    const double momentError = (p.principal.moments.array() - moment).abs().maxCoeff() / moment;
    EXPECT_LT(volumeError, previousVolume / 3.0) << rings;
    EXPECT_LT(momentError, previousMoment / 3.0) << rings;
    EXPECT_LT(p.centroid.norm(), 1e-15);
    previousVolume = volumeError;
    previousMoment = momentError;
  }
  EXPECT_LT(previousVolume, 2e-3);
  EXPECT_LT(previousMoment, 3e-3);
}

TEST(SolidMassProperties, RigidMotionMovesTheCentroidAndRotatesTheTensor) {
  const StlMesh box = test::boxMesh(Vec3(-0.3, -0.2, -0.1), Vec3(0.3, 0.2, 0.1));
  const SolidMassProperties atOrigin = properties(box);
  const Mat3 rotation = Eigen::AngleAxisd(0.7, Vec3(1, 2, 3).normalized()).toRotationMatrix();
  const Vec3 shift(1000.0, -250.0, 42.0);
  StlMesh moved = box;
  for (Vec3& v : moved.vertices) v = rotation * v + shift;
  const SolidMassProperties p = properties(moved);
  EXPECT_NEAR(p.volume, atOrigin.volume, 1e-10 * atOrigin.volume);
  EXPECT_LT((p.centroid - shift).norm(), 1e-10);
  expectMatrixNear(p.inertia, rotation * atOrigin.inertia * rotation.transpose(), 1e-8);
  for (int k = 0; k < 3; ++k) {
    EXPECT_NEAR(p.principal.moments[k], atOrigin.principal.moments[k], 1e-8 * atOrigin.principal.moments[2]);
  }
}

/// The InputError's reason for `mesh`, or "" when it is accepted.
std::string refusal(const StlMesh& mesh) {
  try {
    (void)properties(mesh);
  } catch (const InputError& error) {
    EXPECT_EQ(error.field(), "test");
    return error.reason();
  }
  return "";
}

TEST(SolidMassProperties, RefusesMeshesThatBoundNoSolid) {
  const StlMesh box = test::boxMesh(Vec3(0, 0, 0), Vec3(1, 1, 1));
  ASSERT_EQ(refusal(box), "");

  StlMesh open = box;
  open.triangles.pop_back();
  EXPECT_NE(refusal(open).find("the surface is open"), std::string::npos) << refusal(open);

  StlMesh flipped = box;
  std::swap(flipped.triangles[3][1], flipped.triangles[3][2]);
  EXPECT_NE(refusal(flipped).find("inconsistent orientation"), std::string::npos) << refusal(flipped);

  StlMesh inverted = box;
  for (auto& tri : inverted.triangles) std::swap(tri[1], tri[2]);
  EXPECT_NE(refusal(inverted).find("volume is negative"), std::string::npos) << refusal(inverted);

  StlMesh doubled = box;
  doubled.triangles.insert(doubled.triangles.end(), box.triangles.begin(), box.triangles.end());
  EXPECT_NE(refusal(doubled).find("not a manifold"), std::string::npos) << refusal(doubled);

  StlMesh sheet;  // one triangle, both sides: closed, but it encloses nothing
  sheet.vertices = {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(1, 1, 0)};
  sheet.triangles = {{0, 1, 2}, {0, 2, 1}};
  EXPECT_NE(refusal(sheet).find("encloses no volume"), std::string::npos) << refusal(sheet);
}

}  // namespace
}  // namespace demlink::core
