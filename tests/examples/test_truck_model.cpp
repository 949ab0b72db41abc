/// The truck example's model pieces against closed-form results: the suspension's static
/// equilibrium and steady load transfer (lever rule and moment balance), and the dump
/// body surface (closed, with the volume of the walls and floor).
#include <gtest/gtest.h>

#include <cmath>
#include <map>
#include <utility>

#include "dump_body_mesh.hpp"
#include "truck_model.hpp"

namespace {

using demlink::examples::truck::DumpBodyShape;
using demlink::examples::truck::TruckInputs;
using demlink::examples::truck::TruckModel;
using demlink::examples::truck::TruckParameters;

/// Runs the model with constant inputs long enough to settle (10 s at 1 ms).
TruckModel settle(const TruckParameters& p, const TruckInputs& in) {
  TruckModel m(p);
  for (int i = 0; i < 10000; ++i) m.step(in, 1e-3);
  return m;
}

// A load of weight W resting at x = d from the CG (force -W z, torque W d about y) is
// carried by the axles by the lever rule, on top of the empty body's weight.
TEST(TruckModel, StaticLoadFollowsTheLeverRule) {
  const TruckParameters p;
  const double weight = 3000.0;  // [N]
  const double d = 0.4;          // [m] load ahead of the CG
  TruckInputs in;
  in.dem_force = {0.0, 0.0, -weight};
  in.dem_torque = {0.0, weight * d, 0.0};  // r x F = (d, 0, 0) x (0, 0, -W) = (0, W d, 0)
  const TruckModel m = settle(p, in);
  const auto f = m.springForces();
  const double base = p.front_axle_x - p.rear_axle_x;
  const double total = p.body_mass * p.gravity + weight;
  const double front = (p.body_mass * p.gravity * -p.rear_axle_x + weight * (d - p.rear_axle_x)) / base;
  EXPECT_NEAR(f[0] + f[1] + f[2] + f[3], total, 1e-6 * total);
  EXPECT_NEAR(f[0] + f[1], front, 1e-6 * total);
  EXPECT_NEAR(f[0], f[1], 1e-6 * total);  // no lateral offset: no roll
}

// Accelerating at a: the chassis reaction m a acts h below the CG, so the rear axle gains
// m a h / wheelbase; turning (lateral a_y) the right side gains m a_y h / (2 half_track).
TEST(TruckModel, FrameAccelerationTransfersLoadByTheMomentBalance) {
  const TruckParameters p;
  const double h = -p.seat_height;
  const double base = p.front_axle_x - p.rear_axle_x;
  TruckInputs rest;
  const auto f0 = settle(p, rest).springForces();
  TruckInputs accelerating;
  accelerating.frame_acceleration = {1.5, 0.0, 0.0};
  const auto fa = settle(p, accelerating).springForces();
  const double expectedRear = p.body_mass * 1.5 * h / base;
  EXPECT_NEAR((fa[2] + fa[3]) - (f0[2] + f0[3]), expectedRear, 1e-6 * expectedRear);
  EXPECT_NEAR(fa[0] + fa[1] + fa[2] + fa[3], p.body_mass * p.gravity, 1e-6 * p.body_mass * p.gravity);
  TruckInputs turning;
  turning.frame_acceleration = {0.0, 0.8, 0.0};  // centripetal, towards +y (left turn)
  const auto ft = settle(p, turning).springForces();
  const double expectedSide = p.body_mass * 0.8 * h / (2.0 * p.half_track);
  EXPECT_NEAR((ft[1] + ft[3]) - (f0[1] + f0[3]), expectedSide, 1e-6 * expectedSide);  // right side
  EXPECT_NEAR((ft[0] + ft[2]) - (f0[0] + f0[2]), -expectedSide, 1e-6 * expectedSide);
}

// The surface is closed (every edge shared by exactly two triangles, in opposite
// directions) and encloses the walls' and floor's volume (divergence theorem).
TEST(DumpBodyMesh, ClosedSurfaceWithTheShellVolume) {
  const DumpBodyShape s{3.0, 2.0, 0.6, 0.08, 0.1};
  const auto triangles = demlink::examples::truck::dumpBodyTriangles(s);
  ASSERT_EQ(triangles.size(), 28U);
  std::map<std::pair<std::array<double, 3>, std::array<double, 3>>, int> edges;
  double volume = 0.0;
  for (const auto& t : triangles) {
    for (int k = 0; k < 3; ++k) {
      const auto& a = t[static_cast<std::size_t>(k)];
      const auto& b = t[static_cast<std::size_t>((k + 1) % 3)];
      ++edges[{a, b}];
    }
    const auto& a = t[0];
    const auto& b = t[1];
    const auto& c = t[2];
    volume += (a[0] * (b[1] * c[2] - b[2] * c[1]) - a[1] * (b[0] * c[2] - b[2] * c[0]) +
               a[2] * (b[0] * c[1] - b[1] * c[0])) / 6.0;
  }
  for (const auto& [edge, count] : edges) {
    EXPECT_EQ(count, 1);
    const auto reverse = edges.find({edge.second, edge.first});
    ASSERT_NE(reverse, edges.end());
  }
  const double outer = (3.0 + 0.16) * (2.0 + 0.16) * (0.6 + 0.1);
  const double cavity = 3.0 * 2.0 * 0.6;
  EXPECT_NEAR(volume, outer - cavity, 1e-9);
}

}  // namespace
