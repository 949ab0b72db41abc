/// The clump fit of closed meshes: a sphere is found again, errors fall as spheres are
/// added, the grid sampling sees the solid, and the fit is deterministic.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "demlink/core/particles/clump_fit.hpp"
#include "demlink/core/geometry/closed_surface.hpp"
#include "walls/closed_meshes.hpp"

namespace demlink::core {
namespace {

ClumpTemplate fitted(const StlMesh& mesh, const SolidMassProperties& solid, const SolidSamples& samples,
                     std::size_t count, bool matchVolume) {
  std::vector<ClumpSphere> spheres = inscribedSpheres(mesh, samples, count);
  if (matchVolume) {
    const double scale = volumeMatchingScale(spheres, solid.volume);
    for (ClumpSphere& sphere : spheres) sphere.radius *= scale;
  }
  return ClumpTemplate("fit", spheres);
}

TEST(SolidSamples, InsideSamplesFillTheVolumeAndDepthIsTheDistanceToTheSurface) {
  // Two separate boxes, the second above part of the first: the samples between them and
  // above the first are outside, also in the columns whose ray crosses both.
  StlMesh mesh = test::boxMesh(Vec3(0, 0, 0), Vec3(1.0, 0.6, 0.4));
  const StlMesh second = test::boxMesh(Vec3(0.5, 0, 0.6), Vec3(1.0, 0.6, 1.0));
  const auto offset = static_cast<std::uint32_t>(mesh.vertices.size());
  mesh.vertices.insert(mesh.vertices.end(), second.vertices.begin(), second.vertices.end());
  for (auto tri : second.triangles) mesh.triangles.push_back({tri[0] + offset, tri[1] + offset, tri[2] + offset});
  requireClosedSurface(mesh, "two boxes");
  const SolidSamples samples = sampleSolid(mesh, 80);
  const double h = samples.spacing;
  double volume = 0.0;
  for (std::size_t index = 0; index < samples.size(); ++index) {
    const Vec3 p = samples.point(index);
    const bool inFirst = p.x() > 0 && p.x() < 1.0 && p.y() > 0 && p.y() < 0.6 && p.z() > 0 && p.z() < 0.4;
    const bool inSecond = p.x() > 0.5 && p.x() < 1.0 && p.y() > 0 && p.y() < 0.6 && p.z() > 0.6 && p.z() < 1.0;
    ASSERT_EQ(samples.inside[index] != 0, inFirst || inSecond) << "sample at " << p.transpose();
    if (samples.inside[index] == 0) continue;
    volume += h * h * h;
    // The nearest outside sample is at most one spacing farther than the surface.
    const double exact = distanceToSurface(mesh, p);
    EXPECT_GE(samples.depth[index], exact - 1e-12);
    EXPECT_LE(samples.depth[index], exact + 1.0001 * h);
  }
  EXPECT_NEAR(volume, 1.0 * 0.6 * 0.4 + 0.5 * 0.6 * 0.4, 0.03 * 0.36);
}

TEST(ClumpFit, OneSphereFitsASphere) {
  const double radius = 0.02;
  const StlMesh mesh = test::uvSphere(radius, 48);
  const SolidMassProperties solid = solidMassProperties(mesh, "sphere");
  const SolidSamples samples = sampleSolid(mesh, 48);
  const std::vector<ClumpSphere> one = inscribedSpheres(mesh, samples, 1);
  ASSERT_EQ(one.size(), 1u);
  // The centre is found within a tenth of a grid spacing (the sample's refinement); the
  // inscribed radius is the distance to the nearest facet, which the facets' sagitta keeps
  // within 0.3 % of R.
  EXPECT_LT(one[0].offset.norm(), 0.1 * samples.spacing);
  EXPECT_LT(one[0].radius, radius);
  EXPECT_GT(one[0].radius, 0.997 * radius);
  // Matched volume: one sphere of the mesh's volume exactly.
  const ClumpTemplate clump = fitted(mesh, solid, samples, 1, true);
  EXPECT_NEAR(clump.spheres()[0].radius, std::cbrt(3.0 * solid.volume / (4.0 * std::numbers::pi)), 1e-8 * radius);
  const ClumpFitErrors errors = compareWithSolid(clump, solid);
  EXPECT_LT(std::abs(errors.volume), 1e-8);
  EXPECT_LT(errors.centre_of_mass, samples.spacing / std::cbrt(solid.volume));
  EXPECT_LT(errors.principal_moments.cwiseAbs().maxCoeff(), 1e-2);
}

/// The largest relative error of fits with 1, 2, 4, 8, 16 spheres.
std::vector<double> errorsByCount(const StlMesh& mesh, bool matchVolume) {
  requireClosedSurface(mesh, "shape");
  const SolidMassProperties solid = solidMassProperties(mesh, "shape");
  const SolidSamples samples = sampleSolid(mesh, 64);
  std::vector<double> out;
  for (const std::size_t count : {1u, 2u, 4u, 8u, 16u}) {
    out.push_back(compareWithSolid(fitted(mesh, solid, samples, count, matchVolume), solid).largest());
  }
  return out;
}

TEST(ClumpFit, CapsuleErrorsFallAsSpheresAreAdded) {
  const std::vector<double> errors = errorsByCount(test::capsule(0.5, 2.0, 16), true);
  for (std::size_t k = 1; k < errors.size(); ++k) EXPECT_LT(errors[k], errors[k - 1] * 1.05) << k;
  EXPECT_LT(errors.back(), 0.25 * errors.front());
  EXPECT_LT(errors.back(), 0.06);
}

TEST(ClumpFit, BoxErrorsFallAsSpheresAreAdded) {
  const std::vector<double> errors = errorsByCount(test::boxMesh(Vec3(0, 0, 0), Vec3(0.04, 0.02, 0.012)), true);
  EXPECT_LT(errors.back(), 0.5 * errors.front());
  EXPECT_LT(errors[3], errors[0]);
  EXPECT_LT(errors.back(), 0.1);
}

TEST(ClumpFit, PlateSpheresSpreadOverTheWholePlate) {
  // A 10 x 100 x 40 mm plate: 16 spheres of the plate's half thickness cannot cover it;
  // crowded in its middle, the volume-matched clump would miss most of the inertia.
  const std::vector<double> errors = errorsByCount(test::boxMesh(Vec3(0, 0, 0), Vec3(0.01, 0.1, 0.04)), true);
  EXPECT_GT(errors.front(), 0.5);
  EXPECT_LT(errors.back(), 0.1);
}

TEST(ClumpFit, InscribedSpheresStayInsideAndTheFitIsRepeatable) {
  const StlMesh mesh = test::capsule(0.5, 2.0, 12);
  const SolidSamples samples = sampleSolid(mesh, 40);
  const std::vector<ClumpSphere> first = inscribedSpheres(mesh, samples, 8);
  const std::vector<ClumpSphere> again = inscribedSpheres(mesh, samples, 8);
  ASSERT_EQ(first.size(), 8u);
  for (std::size_t k = 0; k < first.size(); ++k) {
    EXPECT_EQ(first[k].offset, again[k].offset);
    EXPECT_EQ(first[k].radius, again[k].radius);
    // Inscribed: the centre is inside the capsule and the sphere within it.
    const Vec3& c = first[k].offset;
    const double axial = std::clamp(c.z(), -1.0, 1.0);
    const double depth = 0.5 - (c - Vec3(0, 0, axial)).norm();
    EXPECT_LE(first[k].radius, depth + 1e-12);
  }
  const std::vector<ClumpSphere> prefix = inscribedSpheres(mesh, samples, 3);
  for (std::size_t k = 0; k < prefix.size(); ++k) EXPECT_EQ(prefix[k].offset, first[k].offset);
}

}  // namespace
}  // namespace demlink::core
