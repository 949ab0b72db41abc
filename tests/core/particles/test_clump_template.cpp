/// Mass properties of clump templates against analytic results: a single sphere,
/// two disjoint spheres (parallel axis theorem; both exact up to the rounding of
/// summing ~10^5 rays, tolerance 1e-12, because no quadrature ray is cut) and two overlapping equal spheres (union = two spheres
/// minus the lens; exact values by integrating the axisymmetric profile), plus the
/// principal body frame and the rejected inputs.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <numbers>

#include "demlink/core/particles/clump_template.hpp"
#include "demlink/core/base/input_error.hpp"

namespace demlink::core {
namespace {

constexpr double kPi = std::numbers::pi;

/// Exact integrals of the union of two equal spheres of radius R whose centres
/// are d apart on an axis, from the profile r^2(s) = R^2 - s^2 of each half
/// (s measured from that half's centre, from -d/2 to R). The integrands are
/// polynomials of degree <= 4 in s, so 3-point Gauss-Legendre is exact.
struct PairExact {
  double volume;      ///< [m^3]
  double axial;       ///< moment about the axis per unit density [m^5]
  double transverse;  ///< moment about a perpendicular axis through the COM per unit density [m^5]
};

PairExact overlappingPairExact(double R, double d) {
  const double a = -0.5 * d;
  const double b = R;
  const double nodes[3] = {-std::sqrt(0.6), 0.0, std::sqrt(0.6)};
  const double weights[3] = {5.0 / 9.0, 8.0 / 9.0, 5.0 / 9.0};
  PairExact e{0.0, 0.0, 0.0};
  for (int k = 0; k < 3; ++k) {
    const double s = 0.5 * (a + b) + 0.5 * (b - a) * nodes[k];
    const double w = 0.5 * (b - a) * weights[k];
    const double r2 = R * R - s * s;
    const double x = s + 0.5 * d;  // distance from the union's centre along the axis
    e.volume += 2.0 * w * kPi * r2;
    e.axial += 2.0 * w * 0.5 * kPi * r2 * r2;
    e.transverse += 2.0 * w * kPi * r2 * (0.25 * r2 + x * x);
  }
  return e;
}

TEST(ClumpTemplate, SingleSphereIsExact) {
  const double R = 0.003;      // [m]
  const double rho = 2500.0;   // [kg/m^3]
  const Vec3 c(0.01, -0.02, 0.005);
  const ClumpTemplate t("ball", {{c, R}});
  const double volume = 4.0 / 3.0 * kPi * R * R * R;
  EXPECT_NEAR(t.volume(), volume, 1e-13 * volume);
  EXPECT_NEAR((t.centreOfMass() - c).norm(), 0.0, 1e-13 * R);
  const double inertia = 0.4 * rho * volume * R * R;
  for (int k = 0; k < 3; ++k) EXPECT_NEAR(rho * t.principalMomentsPerDensity()[k], inertia, 1e-12 * inertia);
  EXPECT_NEAR(t.bodySpheres()[0].offset.norm(), 0.0, 1e-13 * R);
  EXPECT_NEAR(t.boundingRadius(), R, 1e-13 * R);
}

TEST(ClumpTemplate, DisjointSpheresFollowParallelAxisTheorem) {
  const double r1 = 0.002;
  const double r2 = 0.001;
  const double D = 0.005;  // centre distance > r1 + r2 [m]
  const Vec3 axis = Vec3(2.0, -1.0, 2.0) / 3.0;
  const Vec3 c1(0.001, 0.002, 0.0);
  const ClumpTemplate t("pair", {{c1, r1}, {c1 + D * axis, r2}});
  const double v1 = 4.0 / 3.0 * kPi * r1 * r1 * r1;
  const double v2 = 4.0 / 3.0 * kPi * r2 * r2 * r2;
  const double volume = v1 + v2;
  EXPECT_NEAR(t.volume(), volume, 1e-12 * volume);
  const Vec3 com = c1 + (v2 * D / volume) * axis;
  EXPECT_NEAR((t.centreOfMass() - com).norm(), 0.0, 1e-12 * D);
  const double d1 = v2 * D / volume;
  const double d2 = D - d1;
  const double axial = 0.4 * (v1 * r1 * r1 + v2 * r2 * r2);
  const double transverse = axial + v1 * d1 * d1 + v2 * d2 * d2;
  // Principal moments ascending: the axis, then the two equal transverse ones.
  const Vec3 moments = t.principalMomentsPerDensity();
  EXPECT_NEAR(moments[0], axial, 1e-12 * transverse);
  EXPECT_NEAR(moments[1], transverse, 1e-12 * transverse);
  EXPECT_NEAR(moments[2], transverse, 1e-12 * transverse);
  // The tensor about the template axes: I = A n n^T + T (1 - n n^T).
  const Mat3 expected = axial * axis * axis.transpose() + transverse * (Mat3::Identity() - axis * axis.transpose());
  EXPECT_NEAR((t.inertiaPerDensity() - expected).norm(), 0.0, 1e-12 * transverse);
}

/// Accuracy stated in docs/clumps.md: with the default 256 x 512 directions per
/// sphere the relative errors stay below 1e-5 for every overlap (the worst case,
/// d ~ 1.3 R, has the tangent cone and the intersection circle nearly together).
TEST(ClumpTemplate, OverlappingPairMatchesLensFormula) {
  const double R = 0.002;  // [m]
  const Vec3 axis = Vec3(1.0, 2.0, 2.0) / 3.0;
  for (const double ratio : {0.2, 0.7, 1.0, 1.3, 1.5, 1.9}) {
    const double d = ratio * R;
    const Vec3 middle(0.003, -0.001, 0.002);
    const ClumpTemplate t("pair", {{middle - 0.5 * d * axis, R}, {middle + 0.5 * d * axis, R}});
    const PairExact exact = overlappingPairExact(R, d);
    // The union volume is also two spheres minus the lens pi (4R + d)(2R - d)^2 / 12.
    const double lens = kPi * (4.0 * R + d) * (2.0 * R - d) * (2.0 * R - d) / 12.0;
    const double sphere = 4.0 / 3.0 * kPi * R * R * R;
    EXPECT_NEAR(exact.volume, 2.0 * sphere - lens, 1e-14 * sphere) << "test formula, ratio " << ratio;
    EXPECT_NEAR(t.volume(), exact.volume, 1e-5 * exact.volume) << "ratio " << ratio;
    EXPECT_NEAR((t.centreOfMass() - middle).norm(), 0.0, 1e-5 * R) << "ratio " << ratio;
    const Vec3 moments = t.principalMomentsPerDensity();
    EXPECT_NEAR(moments[0], exact.axial, 1e-5 * exact.axial) << "ratio " << ratio;
    EXPECT_NEAR(moments[1], exact.transverse, 1e-5 * exact.transverse) << "ratio " << ratio;
    EXPECT_NEAR(moments[2], exact.transverse, 1e-5 * exact.transverse) << "ratio " << ratio;
  }
}

TEST(ClumpTemplate, OverlapErrorShrinksWithMoreDirections) {
  const double R = 1.0;
  const double d = 1.0;
  const PairExact exact = overlappingPairExact(R, d);
  const Vec3 axis = Vec3(0.3, 0.4, 0.866).normalized();
  const std::vector<ClumpSphere> pair = {{-0.5 * d * axis, R}, {0.5 * d * axis, R}};
  double previous = 1.0;
  for (const int n : {16, 32, 64, 128, 256}) {
    const double error = std::abs(unionMoments(pair, n).volume - exact.volume) / exact.volume;
    EXPECT_LT(error, previous) << n << " directions";
    previous = error;
  }
  EXPECT_LT(previous, 1e-6);
  // A lone sphere is exact at any direction count that resolves quadratics.
  const UnionMoments lone = unionMoments({{Vec3(0.1, 0.2, 0.3), R}}, 4);
  EXPECT_NEAR(lone.volume, 4.0 / 3.0 * kPi, 1e-14);
  EXPECT_NEAR(lone.second(0, 0), 4.0 * kPi / 15.0, 1e-14);
}

TEST(ClumpTemplate, BodyFrameIsPrincipalAndCentred) {
  const ClumpTemplate t("tri", {{Vec3(0.0, 0.0, 0.0), 1.0}, {Vec3(1.2, 0.1, 0.0), 0.7}, {Vec3(0.1, 0.9, 0.3), 0.5}});
  // Integrated again in the body frame: the two quadratures differ by their error (<= 1e-5).
  const UnionMoments body = unionMoments(t.bodySpheres());
  EXPECT_NEAR(body.centroid.norm(), 0.0, 1e-5);
  const Mat3 inertia = body.second.trace() * Mat3::Identity() - body.second;
  const double scale = t.principalMomentsPerDensity().maxCoeff();
  for (int a = 0; a < 3; ++a) {
    EXPECT_NEAR(inertia(a, a), t.principalMomentsPerDensity()[a], 1e-5 * scale);
    for (int b = 0; b < 3; ++b) {
      if (a != b) {
        EXPECT_NEAR(inertia(a, b), 0.0, 1e-5 * scale);
      }
    }
  }
  EXPECT_LT(t.principalMomentsPerDensity()[0], t.principalMomentsPerDensity()[1]);
  EXPECT_LT(t.principalMomentsPerDensity()[1], t.principalMomentsPerDensity()[2]);
  EXPECT_NEAR(t.principalRotation().toRotationMatrix().determinant(), 1.0, 1e-14);
}

void expectField(const std::vector<ClumpSphere>& spheres, const std::string& field) {
  try {
    const ClumpTemplate t("bad", spheres, "components[2].clump_template");
    ADD_FAILURE() << "accepted; expected an error on " << field;
  } catch (const InputError& e) {
    EXPECT_EQ(e.field(), field) << e.what();
  }
}

TEST(ClumpTemplate, RejectsBadSpheresNamingTheField) {
  const double nan = std::nan("");
  expectField({}, "components[2].clump_template.spheres");
  expectField({{Vec3::Zero(), 0.0}}, "components[2].clump_template.spheres[0].radius");
  expectField({{Vec3::Zero(), 1.0}, {Vec3::Zero(), -1.0}}, "components[2].clump_template.spheres[1].radius");
  expectField({{Vec3::Zero(), 1.0}, {Vec3(0.0, nan, 0.0), 1.0}}, "components[2].clump_template.spheres[1].offset[1]");
  expectField({{Vec3(std::numeric_limits<double>::infinity(), 0, 0), 1.0}},
              "components[2].clump_template.spheres[0].offset[0]");
  expectField({{Vec3::Zero(), 1e-200}}, "components[2].clump_template.spheres");
}

}  // namespace
}  // namespace demlink::core
