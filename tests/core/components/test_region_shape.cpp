// Region shapes: membership of oriented boxes and true spheres at their corners and
// boundary (relative margin 1e-9 of the size), surfaces in their plane, the
// orientation built from a normal, and placements (fixed, moving, attached).
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "demlink/core/base/input_error.hpp"
#include "demlink/core/regions/region_shape.hpp"
#include "sensor_test_support.hpp"

namespace demlink::core {
namespace {

constexpr double kEps = 1.0e-9;

RegionPose tiltedPose() {
  RegionPose pose;
  pose.centre = Vec3(0.3, -0.2, 1.1);
  pose.rotation = (Eigen::AngleAxisd(0.7, Vec3(1.0, 2.0, -0.5).normalized())).toRotationMatrix();
  return pose;
}

TEST(RegionShape, OrientedBoxCornersJustInsideAndOutside) {
  const Vec3 sides(0.2, 0.4, 0.6);
  const VolumeShape box = VolumeShape::box(sides, "box");
  const RegionPose pose = tiltedPose();
  int insideCount = 0;
  for (int corner = 0; corner < 8; ++corner) {
    const Vec3 sign((corner & 1) ? 1.0 : -1.0, (corner & 2) ? 1.0 : -1.0, (corner & 4) ? 1.0 : -1.0);
    const Vec3 local = 0.5 * sides.cwiseProduct(sign);
    const Vec3 inside = pose.centre + pose.rotation * (local * (1.0 - kEps));
    EXPECT_TRUE(box.contains(pose, inside)) << "corner " << corner;
    insideCount += box.contains(pose, inside) ? 1 : 0;
    for (int axis = 0; axis < 3; ++axis) {
      Vec3 out = local * (1.0 - kEps);
      out[axis] = local[axis] * (1.0 + kEps);
      EXPECT_FALSE(box.contains(pose, pose.centre + pose.rotation * out)) << "corner " << corner << " axis " << axis;
    }
  }
  EXPECT_EQ(insideCount, 8);
  // The world-axis-aligned corner of the unrotated box is outside the tilted box.
  EXPECT_FALSE(box.contains(pose, pose.centre + 0.5 * sides * (1.0 - kEps)));
  EXPECT_NEAR(box.volume(), sides.prod(), 1e-15);
}

TEST(RegionShape, SphereIsATrueSphereNotACube) {
  const double r = 0.1;
  const VolumeShape sphere = VolumeShape::sphere(r, "sphere");
  RegionPose pose;
  pose.centre = Vec3(1.0, 2.0, 3.0);
  // Inside the circumscribed cube (every |component| < r) but outside the sphere.
  const Vec3 cubeCorner = pose.centre + Vec3(0.09, 0.09, 0.0);
  EXPECT_FALSE(sphere.contains(pose, cubeCorner));
  EXPECT_FALSE(sphere.contains(pose, pose.centre + Vec3::Constant(0.99 * r)));
  const Vec3 diagonal = Vec3(1.0, -1.0, 1.0).normalized();
  EXPECT_TRUE(sphere.contains(pose, pose.centre + (1.0 - kEps) * r * diagonal));
  EXPECT_FALSE(sphere.contains(pose, pose.centre + (1.0 + kEps) * r * diagonal));
  EXPECT_TRUE(sphere.contains(pose, pose.centre + (1.0 - kEps) * r * Vec3::UnitZ()));
  EXPECT_FALSE(sphere.contains(pose, pose.centre - (1.0 + kEps) * r * Vec3::UnitY()));
}

TEST(RegionShape, SurfacesInTheirPlane) {
  const SurfaceShape rectangle = SurfaceShape::rectangle(0.4, 0.2, "rect");
  EXPECT_TRUE(rectangle.containsInPlane(0.2 * (1 - kEps), -0.1 * (1 - kEps)));
  EXPECT_FALSE(rectangle.containsInPlane(0.2 * (1 + kEps), 0.0));
  EXPECT_FALSE(rectangle.containsInPlane(0.0, -0.1 * (1 + kEps)));
  EXPECT_NEAR(rectangle.area(), 0.08, 1e-15);
  const SurfaceShape disc = SurfaceShape::disc(0.1, "disc");
  EXPECT_TRUE(disc.containsInPlane(0.1 * (1 - kEps) * std::sqrt(0.5), 0.1 * (1 - kEps) * std::sqrt(0.5)));
  EXPECT_FALSE(disc.containsInPlane(0.08, 0.08));  // inside the square |x|, |y| < r
}

TEST(RegionShape, SurfaceOrientationFollowsNormalAndLengthAxis) {
  const Vec3 normal(1.0, 1.0, 0.0);
  const Quat q = surfaceOrientation(2.0 * normal, Vec3(0.0, 0.0, 5.0), "s");
  const Mat3 r = q.toRotationMatrix();
  EXPECT_LT((r.col(2) - normal.normalized()).norm(), 1e-14);
  EXPECT_LT((r.col(0) - Vec3::UnitZ()).norm(), 1e-14);
  EXPECT_NEAR(r.determinant(), 1.0, 1e-14);
  // Without a length axis: any right-handed frame with z along the normal.
  const Mat3 any = surfaceOrientation(Vec3(0.0, 0.0, -3.0), Vec3::Zero(), "s").toRotationMatrix();
  EXPECT_LT((any.col(2) + Vec3::UnitZ()).norm(), 1e-14);
  EXPECT_NEAR(any.determinant(), 1.0, 1e-14);
}

TEST(RegionShape, BadSizesAndNormalsNameTheField) {
  auto fieldOf = [](auto&& make) -> std::string {
    try {
      make();
    } catch (const InputError& e) {
      return e.field();
    }
    return "(no error)";
  };
  EXPECT_EQ(fieldOf([] { (void)VolumeShape::box(Vec3(1.0, 0.0, 1.0), "r.box"); }), "r.box.size.y");
  EXPECT_EQ(fieldOf([] { (void)VolumeShape::box(Vec3(-1.0, 1.0, 1.0), "r.box"); }), "r.box.size.x");
  EXPECT_EQ(fieldOf([] { (void)VolumeShape::sphere(-0.1, "r.sphere"); }), "r.sphere.radius");
  EXPECT_EQ(fieldOf([] { (void)SurfaceShape::disc(0.0, "s.disc"); }), "s.disc.radius");
  EXPECT_EQ(fieldOf([] { (void)SurfaceShape::rectangle(1.0, -2.0, "s.rect"); }), "s.rect.width");
  EXPECT_EQ(fieldOf([] { (void)SurfaceShape::rectangle(0.0, 2.0, "s.rect"); }), "s.rect.length");
  EXPECT_EQ(fieldOf([] { (void)surfaceOrientation(Vec3::Zero(), Vec3::Zero(), "s.disc"); }), "s.disc.normal");
  EXPECT_EQ(fieldOf([] { (void)surfaceOrientation(Vec3::UnitZ(), -2.0 * Vec3::UnitZ(), "s.r"); }),
            "s.r.length_axis");
  EXPECT_EQ(fieldOf([] {
              RegionPlacement p;
              p.orientation = Quat(0.0, 0.0, 0.0, 0.0);
              p.validate("r");
            }),
            "r.orientation");
  EXPECT_EQ(fieldOf([] {
              RegionPlacement p;
              p.attached_mesh = 0;
              p.velocity = Vec3::UnitX();
              p.validate("r");
            }),
            "r.velocity");
}

TEST(RegionShape, PlacementMovesAndFollowsAMesh) {
  World world(test::sensorSettings());
  const auto mat = world.addMaterial(test::testMaterial(0.5));
  const TriangleMesh plate = rectangleMesh(Vec3::Zero(), 0.01, 0.01, 1, 1);
  MeshBody body("plate", plate.vertices, plate.triangles, mat);
  body.setPose(Vec3(1.0, 0.0, 0.0), Quat(Eigen::AngleAxisd(std::numbers::pi / 2, Vec3::UnitZ())));
  world.addMesh(std::move(body));

  RegionPlacement attached;
  attached.centre = Vec3(0.5, 0.0, 0.0);  // body frame
  attached.attached_mesh = 0;
  attached.validate("r");
  attached.resolve(world.meshes().size(), "r");
  const RegionPose pose = attached.poseAt(world.meshes(), world.time());
  EXPECT_LT((pose.centre - Vec3(1.0, 0.5, 0.0)).norm(), 1e-14);
  EXPECT_LT((pose.rotation * Vec3::UnitX() - Vec3::UnitY()).norm(), 1e-14);

  RegionPlacement missing;
  missing.attached_mesh = 3;
  try {
    missing.resolve(world.meshes().size(), "components[2].region_sensor.region");
    ADD_FAILURE() << "expected an InputError";
  } catch (const InputError& e) {
    EXPECT_EQ(e.field(), "components[2].region_sensor.region.attached_to");
    EXPECT_EQ(e.value(), "3");
  }
}

}  // namespace
}  // namespace demlink::core
