/// A moving plate (a mesh body under prescribed motion) pushed through the top layer of
/// a free 3 x 3 x 3 bonded block, in zero gravity: the bonds that hold the top layer to
/// the rest break (broken count > 0, the intact count never rises), and the particles
/// gain no energy beyond the plate's work on them: kinetic + bond strain energy stays
/// below the work W = -sum F_plate . v dt (the plate's force is the particles' force on it)
/// within 2 % (the contact's damping and the broken bonds only take energy away).
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "bonds/bond_test_scenes.hpp"
#include "demlink/core/walls/mesh_body.hpp"

namespace demlink::core {
namespace {

using test::addSphere;
using test::kBondGap;
using test::kBondRadius;

constexpr double kSpacing = 2.0 * kBondRadius + kBondGap;  // [m]

TEST(PlateBreaksBonds, APlatePushedThroughABondedBlockBreaksBondsAndGainsNoEnergy) {
  ParallelBondProperties props = test::bondProperties(1.0e9, 1.0e9);
  props.tensile_strength = 1.0e4;  // [Pa]: 0.03 N on a bond, below the plate's contact force
  props.shear_strength = 1.0e4;
  SimulationSettings settings = test::bondSettings(1.0e-6);
  settings.max_impact_velocity = 2.0;
  World world(settings);
  const auto rock = world.addMaterial(test::bondedMaterial());
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 3; ++j) {
      for (int k = 0; k < 3; ++k) addSphere(world, Vec3(i, j, k) * kSpacing);
    }
  }
  world.addBondRule(test::everywhere(props));
  // A plate with normal +x spanning only the top layer (z = 2 s +- 0.9 r), moving along +x.
  const TriangleMesh plate = rectangleMesh(Vec3::Zero(), 0.9 * kBondRadius, 4.0 * kSpacing, 1, 1);
  MeshBody body("plate", plate.vertices, plate.triangles, rock);
  const double speed = 1.0;  // [m/s]
  body.setPose(Vec3(-1.5 * kSpacing, kSpacing, 2.0 * kSpacing),
               Quat(Eigen::AngleAxisd(std::numbers::pi / 2.0, Vec3::UnitY())));
  body.setVelocity(Vec3(speed, 0.0, 0.0), Vec3::Zero());
  world.addMesh(std::move(body));
  world.initialize();
  world.step();
  ASSERT_EQ(world.bonds().counts().intact, 54u) << "3 x 3 x 3 spheres: 54 neighbouring pairs";

  const auto energy = [&] { return world.kineticEnergy() + world.bonds().strainEnergy(world.particles()); };
  const double start = energy();
  double work = 0.0;  // [J] done by the plate on the particles
  std::uint64_t previousIntact = world.bonds().counts().intact;
  double worst = 0.0;  // largest excess of energy over start + work [J]
  const double dt = settings.time_step;
  for (int n = 0; n < 8000; ++n) {  // 8 mm of plate travel: through the block
    world.step();
    work -= world.meshes()[0].force().dot(Vec3(speed, 0.0, 0.0)) * dt;
    const std::uint64_t intact = world.bonds().counts().intact;
    ASSERT_LE(intact, previousIntact) << "a broken bond stays broken, at step " << world.stepCount();
    previousIntact = intact;
    worst = std::max(worst, energy() - (start + work));
  }
  const BondCounts& counts = world.bonds().counts();
  EXPECT_GT(counts.broken, 0u) << "the plate must break bonds";
  EXPECT_EQ(counts.intact + counts.broken, 54u);
  ASSERT_GT(work, 0.0);
  EXPECT_LT(worst, 0.02 * work) << "energy exceeded the plate's work by " << worst << " J of " << work << " J";
  std::printf("plate: %llu of 54 bonds broke; plate work %.4g J, final energy %.4g J, largest excess %.3g J\n",
              static_cast<unsigned long long>(counts.broken), work, energy(), worst);
}

}  // namespace
}  // namespace demlink::core
