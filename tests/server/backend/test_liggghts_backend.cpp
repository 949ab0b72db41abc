/// The LIGGGHTS backend on libliggghts, on however many MPI ranks the test was started
/// with (ctest runs it alone and under mpirun -np 2): a sphere resting on a plane against
/// Hertz's closed form, and the deposition scene's final mean height against our engine.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <numbers>
#include <string>
#include <vector>

#include "demlink/server/backend/liggghts_backend.hpp"
#include "demlink/server/backend/liggghts_script.hpp"
#include "scene_test_support.hpp"
#include "test_support.hpp"

namespace demlink::server {
namespace {

double meanZ(const core::World& world) {
  double sum = 0.0;
  for (const core::Vec3& x : world.particles().position) sum += x.z();
  return sum / static_cast<double>(world.particles().size());
}

const std::string kBeads = R"({"name": "beads", "material": {"density": 2500, "youngs_modulus": 5e6,
    "poisson_ratio": 0.3, "restitution": 0.5, "sliding_friction": 0.5}})";

std::string plane(const std::string& name, const std::string& point, const std::string& normal) {
  return R"({"name": ")" + name + R"(", "plane": {"point": )" + point + R"(, "normal": )" + normal +
         R"(, "material": "beads"}})";
}

TEST(LiggghtsBackend, RestingSphereHasHertzOverlap) {
  const v1::Scene scene = test::sceneOf({
      R"({"name": "box", "simulation_box": {"time_step": 1e-5, "end_time": 0.1,
          "bounds": {"lower": {"x": 0, "y": 0, "z": 0}, "upper": {"x": 0.02, "y": 0.02, "z": 0.02}}}})",
      kBeads,
      plane("floor", R"({"z": 0})", R"({"z": 1})"),
      R"({"name": "bead", "single_particle": {"material": "beads",
          "position": {"x": 0.01, "y": 0.01, "z": 0.002}, "diameter": 0.004}})",
  });
  TranslatedScene translated = translateScene(scene, {});
  LiggghtsBackend backend(translated.world);
  backend.advanceTo(10000);  // 0.1 s: the bounce has died out (restitution 0.5)
  backend.syncParticles();
  // Hertz: m g = 4/3 E* sqrt(R) delta^(3/2), E* = E / (2 (1 - nu^2)) for two equal materials.
  const double r = 0.002;
  const double m = 2500.0 * 4.0 / 3.0 * std::numbers::pi * r * r * r;
  const double effective = 5e6 / (2.0 * (1.0 - 0.3 * 0.3));
  const double overlap = std::pow(m * 9.81 / (4.0 / 3.0 * effective * std::sqrt(r)), 2.0 / 3.0);
  const double z = backend.world().particles().position[0].z();
  EXPECT_NEAR(r - z, overlap, 0.01 * overlap) << "ranks " << mpiRanks();
  EXPECT_EQ(backend.stepCount(), 10000u);
  EXPECT_NEAR(backend.time(), 0.1, 1e-12);
}

TEST(LiggghtsBackend, SphereOnMeshHasOurWrench) {
  const test::ScratchDir dir;
  // A 20 mm square plate in the STL frame's z = 0 plane, its reference point at its centre.
  test::writeText(dir.path() / "plate.stl", R"(solid plate
 facet normal 0 0 1
  outer loop
   vertex -0.01 -0.01 0
   vertex 0.01 -0.01 0
   vertex 0.01 0.01 0
  endloop
 endfacet
 facet normal 0 0 1
  outer loop
   vertex -0.01 -0.01 0
   vertex 0.01 0.01 0
   vertex -0.01 0.01 0
  endloop
 endfacet
endsolid plate
)");
  const v1::Scene scene = test::sceneOf({
      R"({"name": "box", "simulation_box": {"time_step": 1e-5, "end_time": 0.1,
          "bounds": {"lower": {"x": -0.001, "y": -0.001, "z": -0.005}, "upper": {"x": 0.021, "y": 0.021, "z": 0.02}}}})",
      kBeads,
      R"({"name": "plate", "mesh_body": {"stl_file": "plate.stl", "material": "beads",
          "position": {"x": 0.01, "y": 0.01, "z": 0}}})",
      R"({"name": "bead", "single_particle": {"material": "beads",
          "position": {"x": 0.012, "y": 0.01, "z": 0.002}, "diameter": 0.004}})",
  });
  TranslatedScene native = translateScene(scene, dir.path());
  NativeBackend ours(native.world);
  ours.advanceTo(10000);
  const core::MeshBody& reference = ours.world().meshes()[0];
  TranslatedScene translated = translateScene(scene, dir.path());
  requireLiggghtsCompatible(scene, translated.world);
  LiggghtsBackend backend(translated.world);
  backend.advanceTo(10000);
  backend.syncParticles();
  const core::MeshBody& theirs = backend.world().meshes()[0];
  // At rest the plate carries the sphere's weight, 2 mm off its reference point along x:
  // F = (0, 0, -m g), torque about the reference point (0, 0.002 m g, 0).
  const double r = 0.002;
  const double weight = 2500.0 * 4.0 / 3.0 * std::numbers::pi * r * r * r * 9.81;
  EXPECT_NEAR(reference.force().z(), -weight, 0.01 * weight);
  EXPECT_NEAR(reference.torque().y(), 0.002 * weight, 0.01 * 0.002 * weight);
  EXPECT_NEAR(theirs.force().z(), reference.force().z(), 0.02 * weight) << "ranks " << mpiRanks();
  EXPECT_NEAR(theirs.force().x(), reference.force().x(), 0.02 * weight);
  EXPECT_NEAR(theirs.torque().y(), reference.torque().y(), 0.02 * 0.002 * weight);
  EXPECT_NEAR(theirs.torque().x(), reference.torque().x(), 0.02 * 0.002 * weight);
  std::printf("mesh wrench on %d rank(s): LIGGGHTS Fz %.6g N, My %.6g N m; ours Fz %.6g N, My %.6g N m\n",
              mpiRanks(), theirs.force().z(), theirs.torque().y(), reference.force().z(), reference.torque().y());
}

TEST(LiggghtsBackend, ParticleLeavingTheBoxIsRemovedAsByOurEngine) {
  const v1::Scene scene = test::sceneOf({
      R"({"name": "box", "simulation_box": {"time_step": 1e-5, "end_time": 0.01, "max_impact_velocity": 3.0,
          "bounds": {"lower": {"x": 0, "y": 0, "z": 0}, "upper": {"x": 0.02, "y": 0.02, "z": 0.02}}}})",
      kBeads,
      plane("floor", R"({"z": 0})", R"({"z": 1})"),
      R"({"name": "stays", "single_particle": {"material": "beads",
          "position": {"x": 0.005, "y": 0.01, "z": 0.002}, "diameter": 0.004}})",
      R"({"name": "leaves", "single_particle": {"material": "beads",
          "position": {"x": 0.015, "y": 0.01, "z": 0.015}, "velocity": {"z": 2.0}, "diameter": 0.004}})",
  });
  TranslatedScene native = translateScene(scene, {});
  NativeBackend ours(native.world);
  ours.advanceTo(1000);  // 10 ms: the second sphere left through the top at about 2.5 ms
  TranslatedScene translated = translateScene(scene, {});
  LiggghtsBackend backend(translated.world);
  backend.advanceTo(1000);
  backend.syncParticles();
  ASSERT_EQ(ours.world().removedAtBounds().count, 1u);
  EXPECT_EQ(backend.lostParticles().count, 1u) << "ranks " << mpiRanks();
  EXPECT_NEAR(backend.lostParticles().mass, ours.world().removedAtBounds().mass, 1e-15);
  ASSERT_EQ(backend.world().particles().size(), 1u);
  EXPECT_EQ(backend.world().particles().id[0], ours.world().particles().id[0]);
  EXPECT_NEAR(backend.world().particles().position[0].z(), ours.world().particles().position[0].z(), 1e-7);
}

/// The deposition benchmark's scene (bench/deposition), shrunk to 144 spheres in a
/// 40 mm box, settled for 0.3 s.
v1::Scene depositionScene() {
  return test::sceneOf({
      R"({"name": "box", "simulation_box": {"time_step": 1e-5, "end_time": 0.3, "max_impact_velocity": 2.0,
          "bounds": {"lower": {"x": 0, "y": 0, "z": 0}, "upper": {"x": 0.04, "y": 0.04, "z": 0.06}}}})",
      kBeads,
      plane("floor", R"({"z": 0})", R"({"z": 1})"),
      plane("wall_x0", R"({"x": 0})", R"({"x": 1})"),
      plane("wall_x1", R"({"x": 0.04})", R"({"x": -1})"),
      plane("wall_y0", R"({"y": 0})", R"({"y": 1})"),
      plane("wall_y1", R"({"y": 0.04})", R"({"y": -1})"),
      R"({"name": "spheres", "particle_lattice": {"material": "beads", "radius": 0.002, "radius_max": 0.003,
          "origin": {"x": 0.0045, "y": 0.0045, "z": 0.0035}, "spacing": 0.0065,
          "counts": {"nx": 6, "ny": 6, "nz": 4}, "jitter": 0.0002, "seed": "12345"}})",
  });
}

TEST(LiggghtsBackend, DepositionMeanHeightMatchesNativeEngine) {
  const v1::Scene scene = depositionScene();
  TranslatedScene native = translateScene(scene, {});
  NativeBackend ours(native.world);
  ours.advanceTo(30000);
  TranslatedScene translated = translateScene(scene, {});
  requireLiggghtsCompatible(scene, translated.world);
  LiggghtsBackend backend(translated.world);
  backend.advanceTo(15000);  // in two runs, as the runner does between outputs
  backend.advanceTo(30000);
  backend.syncParticles();
  const double theirs = meanZ(backend.world());
  const double reference = meanZ(ours.world());
  const double initial = meanZ(translateScene(scene, {}).world);
  // The bed has formed: the mean fell by a third, and the kinetic energy is tiny.
  EXPECT_LT(reference, 0.7 * initial);
  EXPECT_LT(backend.world().kineticEnergy(), 1e-6);
  EXPECT_NEAR(theirs, reference, 0.02 * reference) << "ranks " << mpiRanks() << ": LIGGGHTS " << theirs
                                                   << " m, ours " << reference << " m";
  std::printf("deposition mean z on %d rank(s): LIGGGHTS %.6g m, ours %.6g m (%.2f %%)\n", mpiRanks(), theirs,
              reference, 100.0 * (theirs - reference) / reference);
}

}  // namespace
}  // namespace demlink::server

int main(int argc, char** argv) {
  demlink::server::ensureMpi();
  ::testing::InitGoogleTest(&argc, argv);
  return RUN_ALL_TESTS();
}
