/// DeformableSurface: the barycentric coupling D_d2dof (forces to nodes) and its
/// transpose (node velocities to the contact point), active flags, the displacement mark.
#include <gtest/gtest.h>

#include "demlink/core/deformable/deformable_surface.hpp"
#include "demlink/core/base/input_error.hpp"

namespace demlink::core {
namespace {

DeformableSurface triangleSurface() {
  DeformableSurface s(4, {{0, 1, 2}, {1, 3, 2}}, 0, "surface");
  s.positions() = {Vec3(0.0, 0.0, 0.0), Vec3(1.0, 0.0, 0.0), Vec3(0.0, 2.0, 0.0), Vec3(1.0, 2.0, 0.5)};
  s.velocities() = {Vec3(1.0, 0.0, 0.0), Vec3(0.0, 2.0, 0.0), Vec3(0.0, 0.0, 3.0), Vec3(9.0, 9.0, 9.0)};
  return s;
}

TEST(DeformableSurface, ContactForceSpreadsByBarycentricWeightsAndVelocityIsItsTranspose) {
  DeformableSurface s = triangleSurface();
  const Vec3 weights(0.2, 0.3, 0.5);
  const Vec3 q = weights[0] * s.positions()[0] + weights[1] * s.positions()[1] + weights[2] * s.positions()[2];
  const Vec3 v = s.velocityAt(0, q);
  EXPECT_LT((v - Vec3(0.2, 0.6, 1.5)).norm(), 1e-14);
  const Vec3 f(1.0, -2.0, 4.0);
  s.addContactForce(0, q, f);
  for (int k = 0; k < 3; ++k) EXPECT_LT((s.nodeForces()[k] - weights[k] * f).norm(), 1e-14) << k;
  EXPECT_EQ(s.nodeForces()[3], Vec3::Zero());
  // Power consistency: F . v(q) = sum_nodes f_i . v_i.
  double nodePower = 0.0;
  for (int k = 0; k < 4; ++k) nodePower += s.nodeForces()[k].dot(s.velocities()[k]);
  EXPECT_NEAR(f.dot(v), nodePower, 1e-13);
  s.clearForces();
  EXPECT_EQ(s.nodeForces()[0], Vec3::Zero());
}

TEST(DeformableSurface, MarkActiveFlagsAndBadTriangles) {
  DeformableSurface s = triangleSurface();
  s.markNeighbourBuild();
  s.positions()[2].z() += 0.25;
  EXPECT_DOUBLE_EQ(s.maxDisplacementSinceMark(), 0.25);
  EXPECT_EQ(s.active(), (std::vector<char>{1, 1}));
  s.setActive(1, false);
  EXPECT_EQ(s.active(), (std::vector<char>{1, 0}));
  EXPECT_THROW(DeformableSurface(3, {{0, 1, 3}}, 0, "s"), InputError);
  EXPECT_THROW(DeformableSurface(3, {{0, 1, 1}}, 0, "s"), InputError);
}

}  // namespace
}  // namespace demlink::core
