// Triangle meshes in the world.
//  - A flat, subdivided mesh must act exactly like an infinite plane: impacts on a
//    face interior, on a shared edge and on a vertex shared by six triangles, and a
//    sphere sliding and rolling across many triangles (tangential spring handed on
//    from triangle to triangle).
//  - A moving mesh pushes a particle: a wall of infinite mass at speed V hitting a
//    resting sphere elastically sends it off at 2V.
//  - The mesh floor under a settled bed carries the bed's weight within 1 %.
#include <random>

#include <gtest/gtest.h>

#include "test_scenes.hpp"

namespace demlink::core {
namespace {

constexpr double kRadius = 0.005;

/// Trajectory (position, velocity, spin) of one sphere launched at `start` with
/// `velocity` onto the z = 0 floor, given either as a plane or a flat mesh.
struct Trajectory {
  std::vector<Vec3> position;
  std::vector<Vec3> velocity;
  std::vector<Vec3> spin;
};

Trajectory launch(bool useMesh, const Vec3& start, const Vec3& velocity, double gravity, int steps) {
  SimulationSettings s = test::fineSettings(2e-6, 1.5);
  s.gravity = Vec3(0.0, 0.0, -gravity);
  World world(s);
  const auto mat = world.addMaterial(test::testMaterial(0.5, 0.3));
  if (useMesh) {
    // 0.1 x 0.1 m in 10 x 10 cells: triangles 1 cm wide, smaller than the path.
    TriangleMesh floor = rectangleMesh(Vec3::Zero(), 0.05, 0.05, 10, 10);
    world.addMesh(MeshBody("floor", floor.vertices, floor.triangles, mat));
  } else {
    world.addPlane({"floor", Vec3::Zero(), Vec3::UnitZ(), mat});
  }
  ParticleSpec p;
  p.radius = kRadius;
  p.position = start;
  p.velocity = velocity;
  world.addParticle(p);
  world.initialize();
  Trajectory t;
  for (int n = 0; n < steps; ++n) {
    world.step();
    t.position.push_back(world.particles().position[0]);
    t.velocity.push_back(world.particles().velocity[0]);
    t.spin.push_back(world.particles().angular_velocity[0]);
  }
  return t;
}

void expectSameTrajectory(const Trajectory& plane, const Trajectory& mesh, double tolerance) {
  ASSERT_EQ(plane.position.size(), mesh.position.size());
  for (std::size_t n = 0; n < plane.position.size(); ++n) {
    ASSERT_LT((plane.position[n] - mesh.position[n]).norm(), tolerance * kRadius) << "step " << n;
    ASSERT_LT((plane.velocity[n] - mesh.velocity[n]).norm(), tolerance) << "step " << n;
    ASSERT_LT((plane.spin[n] - mesh.spin[n]).norm() * kRadius, tolerance) << "step " << n;
  }
}

TEST(MeshWorld, ImpactOnFlatMeshEqualsPlaneAtFaceEdgeAndVertex) {
  // Vertex (i, j) of the rectangle lies at (-0.05 + 0.01 i, -0.05 + 0.01 j).
  const std::vector<Vec3> spots = {
      Vec3(0.0031, 0.0017, 0.0),  // face interior
      Vec3(0.0, 0.0043, 0.0),     // on the edge x = 0 shared by two cells
      Vec3(0.0, 0.0, 0.0),        // on a vertex shared by six triangles
      Vec3(0.0043, 0.0057, 0.0),  // on a diagonal edge (x - y = const inside a cell)
  };
  for (const Vec3& spot : spots) {
    const Vec3 start = spot + Vec3(0.0, 0.0, kRadius + 1e-5);
    const Trajectory plane = launch(false, start, Vec3(0.0, 0.0, -1.0), 0.0, 1500);
    const Trajectory mesh = launch(true, start, Vec3(0.0, 0.0, -1.0), 0.0, 1500);
    ASSERT_GT(plane.velocity.back().z(), 0.0) << "the sphere must have bounced";
    expectSameTrajectory(plane, mesh, 1e-12);
  }
}

TEST(MeshWorld, SlidingAndRollingAcrossTrianglesEqualsPlane) {
  // Lands sliding, then rolls across ~7 triangles and their shared edges.
  // Slip (0.5 m/s) is gone after v / (7/2 mu g) = 0.05 s; we follow it for 0.12 s.
  const Vec3 start(-0.031, -0.012, kRadius + 1e-5);
  const Vec3 velocity(0.5, 0.2, -0.2);
  const Trajectory plane = launch(false, start, velocity, 9.81, 60000);
  const Trajectory mesh = launch(true, start, velocity, 9.81, 60000);
  const double travelled = (plane.position.back() - start).head<2>().norm();
  ASSERT_GT(travelled, 0.03) << "the path must cross several triangles";
  const Vec3 endSpin = plane.spin.back();
  const Vec3 endVelocity = plane.velocity.back();
  ASSERT_LT(std::abs(endVelocity.x() - endSpin.y() * plane.position.back().z()), 1e-3)
      << "the sphere should have ended up rolling";
  expectSameTrajectory(plane, mesh, 1e-9);
}

TEST(MeshWorld, MovingMeshPushesParticle) {
  // A box wall moving at V along +x hits a sphere at rest; e = 1, no friction,
  // no gravity: the sphere leaves at 2V, and the push on the mesh is -x.
  const double speed = 0.5;
  SimulationSettings s = test::fineSettings(1e-6, 2.0 * speed);
  World world(s);
  const auto mat = world.addMaterial(test::testMaterial(1.0, 0.0));
  const TriangleMesh box = axisAlignedBoxMesh(Vec3(-0.02, -0.02, -0.02), Vec3(0.0, 0.02, 0.02));
  const auto index = world.addMesh(MeshBody("pusher", box.vertices, box.triangles, mat));
  world.mesh(index).setVelocity(Vec3(speed, 0.0, 0.0), Vec3::Zero());
  ParticleSpec p;
  p.radius = kRadius;
  p.position = Vec3(kRadius + 0.001, 0.0013, -0.0021);  // in front of the face x = 0
  world.addParticle(p);
  world.initialize();
  Vec3 impulseOnMesh = Vec3::Zero();
  for (int n = 0; n < 8000; ++n) {
    world.step();
    impulseOnMesh += world.meshes()[index].force() * s.time_step;
  }
  const double mass = world.particles().mass[0];
  EXPECT_NEAR(world.particles().velocity[0].x() / (2.0 * speed), 1.0, 0.01);
  EXPECT_NEAR(world.particles().velocity[0].tail<2>().norm(), 0.0, 1e-9);
  // Newton's third law: the mesh received the opposite of the particle's momentum.
  EXPECT_NEAR(impulseOnMesh.x() / (-2.0 * speed * mass), 1.0, 0.01);
  EXPECT_NEAR(world.meshes()[index].position().x(), speed * world.time(), 1e-12);
}

TEST(MeshWorld, MeshFloorCarriesTheWeightOfASettledBed) {
  SimulationSettings s;
  s.time_step = 1e-5;
  s.max_impact_velocity = 1.0;
  s.restitution_tolerance = 0.2;  // the floor's load, not restitution, is tested
  World world(s);
  const auto grains = test::addBoxedLattice(world);
  const TriangleMesh floor = rectangleMesh(Vec3(0.015, 0.015, 0.0), 0.03, 0.03, 7, 5);
  const auto floorIndex = world.addMesh(MeshBody("floor", floor.vertices, floor.triangles, grains));
  world.initialize();
  for (int n = 0; n < 60000; ++n) world.step();
  const double weight = world.totalMass() * 9.81;
  EXPECT_LT(world.kineticEnergy(), 1e-6 * weight * 0.03) << "bed has not settled";
  EXPECT_NEAR(world.meshes()[floorIndex].force().z() / -weight, 1.0, 0.01);
}

}  // namespace
}  // namespace demlink::core
