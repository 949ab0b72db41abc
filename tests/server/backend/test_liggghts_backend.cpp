/// The LIGGGHTS backend on libliggghts, on however many MPI ranks the test was started
/// with (ctest runs it alone and under mpirun -np 2): a sphere resting on a plane against
/// Hertz's closed form, and the deposition scene's final mean height against our engine.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <limits>
#include <numbers>
#include <stdexcept>
#include <string>
#include <vector>

#include "demlink/core/components/particle_tracker.hpp"
#include "demlink/core/checkpoint_file.hpp"
#include "demlink/server/backend/liggghts_backend.hpp"
#include "demlink/server/backend/liggghts_flows.hpp"
#include "demlink/server/backend/liggghts_script.hpp"
#include "liggghts_test_support.hpp"
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

TEST(LiggghtsBackend, RollingSphereDeceleratesAsOurs) {
  // A sphere rolling without slipping at 0.1 m/s on a plane with rolling friction mu_r = 0.1:
  // a constant directional torque mu_r R m g decelerates it at 5/7 mu_r g (0.7007 m/s^2) on
  // both engines (ours: docs/physics.md; LIGGGHTS: rolling_friction cdt).
  const v1::Scene scene = test::sceneOf({
      R"({"name": "box", "simulation_box": {"time_step": 1e-5, "end_time": 0.05,
          "bounds": {"lower": {"x": 0, "y": 0, "z": 0}, "upper": {"x": 0.04, "y": 0.02, "z": 0.02}}}})",
      R"({"name": "beads", "material": {"density": 2500, "youngs_modulus": 5e6, "poisson_ratio": 0.3,
          "restitution": 0.5, "sliding_friction": 0.5, "rolling_friction": 0.1}})",
      plane("floor", R"({"z": 0})", R"({"z": 1})"),
      R"({"name": "bead", "single_particle": {"material": "beads", "position": {"x": 0.01, "y": 0.01, "z": 0.001997},
          "velocity": {"x": 0.1}, "angular_velocity": {"y": 50}, "diameter": 0.004}})",
  });
  TranslatedScene native = translateScene(scene, {});
  NativeBackend ours(native.world);
  ours.advanceTo(5000);
  TranslatedScene translated = translateScene(scene, {});
  requireLiggghtsCompatible(scene, translated.world);
  LiggghtsBackend backend(translated.world);
  backend.advanceTo(5000);
  backend.syncParticles();
  const double expected = 0.1 - 5.0 / 7.0 * 0.1 * 9.81 * 0.05;  // 0.06497 m/s
  const double theirs = backend.world().particles().velocity[0].x();
  const double reference = ours.world().particles().velocity[0].x();
  const double lost = 0.1 - expected;
  EXPECT_NEAR(reference, expected, 0.02 * lost);
  EXPECT_NEAR(theirs, expected, 0.02 * lost) << "ranks " << mpiRanks();
  std::printf("rolling sphere after 0.05 s on %d rank(s): v = %.6g m/s on LIGGGHTS, %.6g m/s on ours, %.6g m/s "
              "closed form\n",
              mpiRanks(), theirs, reference, expected);
}

/// plate.stl in `folder`: a 20 mm square plate in its frame's z = 0 plane, centred on the origin.
void writePlateStl(const std::filesystem::path& folder) {
  test::writeText(folder / "plate.stl", "solid plate\n facet normal 0 0 1\n  outer loop\n   vertex -0.01 -0.01 0\n"
                                        "   vertex 0.01 -0.01 0\n   vertex 0.01 0.01 0\n  endloop\n endfacet\n"
                                        " facet normal 0 0 1\n  outer loop\n   vertex -0.01 -0.01 0\n"
                                        "   vertex 0.01 0.01 0\n   vertex -0.01 0.01 0\n  endloop\n endfacet\n"
                                        "endsolid plate\n");
}

TEST(LiggghtsBackend, SphereOnMeshHasOurWrench) {
  const test::ScratchDir dir;
  // A 20 mm square plate in the STL frame's z = 0 plane, its reference point at its centre.
  writePlateStl(dir.path());
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

TEST(LiggghtsBackend, SphereOnFixedFacetFloorRestsAsOnOurs) {
  // The pit floor of the excavator site in small: a FIXED facet body of two triangles.
  const v1::Scene scene = test::sceneOf({
      R"({"name": "box", "simulation_box": {"time_step": 1e-5, "end_time": 0.1,
          "bounds": {"lower": {"x": 0, "y": 0, "z": -0.005}, "upper": {"x": 0.02, "y": 0.02, "z": 0.02}}}})",
      kBeads,
      R"({"name": "floor", "facet_body": {"role": "FIXED", "material": "beads", "triangles": {"triangles": [
          {"a": {"x": 0, "y": 0, "z": 0}, "b": {"x": 0.02, "y": 0, "z": 0}, "c": {"x": 0.02, "y": 0.02, "z": 0}},
          {"a": {"x": 0, "y": 0, "z": 0}, "b": {"x": 0.02, "y": 0.02, "z": 0}, "c": {"x": 0, "y": 0.02, "z": 0}}]}}})",
      R"({"name": "bead", "single_particle": {"material": "beads",
          "position": {"x": 0.012, "y": 0.009, "z": 0.002}, "diameter": 0.004}})",
  });
  TranslatedScene native = translateScene(scene, {});
  NativeBackend ours(native.world);
  ours.advanceTo(10000);
  TranslatedScene translated = translateScene(scene, {});
  requireLiggghtsCompatible(scene, translated.world);
  LiggghtsBackend backend(translated.world);
  backend.advanceTo(10000);
  backend.syncParticles();
  const double r = 0.002;
  const double m = 2500.0 * 4.0 / 3.0 * std::numbers::pi * r * r * r;
  const double effective = 5e6 / (2.0 * (1.0 - 0.3 * 0.3));
  const double overlap = std::pow(m * 9.81 / (4.0 / 3.0 * effective * std::sqrt(r)), 2.0 / 3.0);
  const double theirs = r - backend.world().particles().position[0].z();
  const double reference = r - ours.world().particles().position[0].z();
  EXPECT_NEAR(reference, overlap, 0.01 * overlap);
  EXPECT_NEAR(theirs, overlap, 0.01 * overlap) << "ranks " << mpiRanks();
  EXPECT_NEAR(theirs, reference, 0.01 * overlap);
  EXPECT_NEAR(backend.world().meshes()[0].force().z(), -m * 9.81, 0.01 * m * 9.81);
  std::printf("sphere on a FIXED facet floor, %d rank(s): overlap LIGGGHTS %.6g m, ours %.6g m, Hertz %.6g m\n",
              mpiRanks(), theirs, reference, overlap);
}

TEST(LiggghtsBackend, PitGeneratorBedReachesLiggghtsAndStaysAtRest) {
  // A pit of 2-2.5 mm beads settled by our engine before the run, in an open FIXED facet box.
  const v1::Scene scene = test::sceneOf({
      R"({"name": "box", "simulation_box": {"time_step": 1e-5, "end_time": 0.05,
          "bounds": {"lower": {"x": -0.001, "y": -0.001, "z": -0.001}, "upper": {"x": 0.041, "y": 0.041, "z": 0.05}}}})",
      kBeads,
      R"({"name": "tub", "facet_body": {"role": "FIXED", "material": "beads", "box": {
          "centre": {"x": 0.02, "y": 0.02, "z": 0.02}, "size": {"x": 0.04, "y": 0.04, "z": 0.04}, "open_top": true}}})",
      R"({"name": "pit", "pit_generator": {"material": "beads", "sizes": {"uniform": {"r_min": 0.002, "r_max": 0.0025}},
          "lower": {"x": 0, "y": 0, "z": 0}, "upper": {"x": 0.04, "y": 0.04, "z": 0.04}, "target_height": 0.02,
          "seed": "7"}})",
  });
  TranslatedScene translated = translateScene(scene, {});
  requireLiggghtsCompatible(scene, translated.world);
  const core::ParticleArrays& p = translated.world.particles();
  ASSERT_GT(p.size(), 100u);
  double mass = 0.0;
  for (const double m : p.mass) mass += m;
  const double initial = meanZ(translated.world);
  LiggghtsBackend backend(translated.world);
  EXPECT_EQ(backend.particleCount(), p.size()) << "ranks " << mpiRanks();
  EXPECT_NEAR(backend.particleMass(), mass, 1e-12 * mass);
  // The bed was settled by our contact law and copied at rest; it relaxes by the same small
  // amount under both engines' Hertz-Mindlin (0.05 s).
  backend.advanceTo(5000);
  backend.syncParticles();
  TranslatedScene native = translateScene(scene, {});
  NativeBackend ours(native.world);
  ours.advanceTo(5000);
  EXPECT_EQ(backend.particleCount(), p.size());
  const double theirs = meanZ(backend.world());
  const double reference = meanZ(ours.world());
  EXPECT_NEAR(theirs, reference, 5e-6) << "ranks " << mpiRanks();  // a fifth of the relaxation
  std::printf("pit on %d rank(s): %zu beads, %.6g kg; mean z %.6g m at the start, after 0.05 s %.6g m on LIGGGHTS, "
              "%.6g m on ours\n",
              mpiRanks(), p.size(), mass, initial, theirs, reference);
}

// The 20 mm square plate of SphereOnMeshHasOurWrench, moving at a constant twist, under
// a sphere of the given material; the scene runs on both engines.
struct MovingPlateRun {
  core::Vec3 force_ours, torque_ours, force_theirs, torque_theirs;
  core::Vec3 sphere_ours, sphere_theirs;
};

MovingPlateRun runMovingPlate(const std::string& material, const std::string& motion, std::uint64_t steps) {
  const test::ScratchDir dir;
  writePlateStl(dir.path());
  const v1::Scene scene = test::sceneOf({
      R"({"name": "box", "simulation_box": {"time_step": 1e-5, "end_time": 0.1,
          "bounds": {"lower": {"x": -0.01, "y": -0.01, "z": -0.005}, "upper": {"x": 0.03, "y": 0.03, "z": 0.02}}}})",
      material,
      R"({"name": "plate", "mesh_body": {"stl_file": "plate.stl", "material": "beads",
          "position": {"x": 0.01, "y": 0.01, "z": 0}, )" + motion + "}}",
      R"({"name": "bead", "single_particle": {"material": "beads",
          "position": {"x": 0.012, "y": 0.01, "z": 0.00199}, "diameter": 0.004}})",
  });
  MovingPlateRun out;
  TranslatedScene native = translateScene(scene, dir.path());
  NativeBackend ours(native.world);
  ours.advanceTo(steps);
  out.force_ours = ours.world().meshes()[0].force();
  out.torque_ours = ours.world().meshes()[0].torque();
  out.sphere_ours = ours.world().particles().position[0];
  TranslatedScene translated = translateScene(scene, dir.path());
  requireLiggghtsCompatible(scene, translated.world);
  LiggghtsBackend backend(translated.world);
  // In strides, as a co-simulation advances it; the twist is set once, so the fixes stay.
  for (std::uint64_t step = 0; step < steps;) backend.advanceTo(step += steps / 10);
  backend.syncParticles();
  out.force_theirs = backend.world().meshes()[0].force();
  out.torque_theirs = backend.world().meshes()[0].torque();
  out.sphere_theirs = backend.world().particles().position[0];
  EXPECT_NEAR((backend.world().meshes()[0].position() - ours.world().meshes()[0].position()).norm(), 0.0, 1e-12);
  return out;
}

TEST(LiggghtsBackend, SlidingMeshCarriesItsReferencePoint) {
  // Frictionless: the sphere stays where it is while the plate slides 4 mm in x beneath it
  // (0.04 m/s for 0.1 s), from 2 mm ahead of the plate's reference point to 2 mm behind it:
  // torque about it (0, -0.002 m g, 0) at the end, (0, +0.002 m g, 0) at the start.
  const std::string slippery = R"({"name": "beads", "material": {"density": 2500, "youngs_modulus": 5e6,
      "poisson_ratio": 0.3, "restitution": 0.5, "sliding_friction": 0}})";
  const MovingPlateRun run = runMovingPlate(slippery, R"("linear_velocity": {"x": 0.04})", 10000);
  const double r = 0.002;
  const double weight = 2500.0 * 4.0 / 3.0 * std::numbers::pi * r * r * r * 9.81;
  EXPECT_NEAR(run.force_ours.z(), -weight, 0.02 * weight);
  EXPECT_NEAR(run.torque_ours.y(), -0.002 * weight, 0.02 * 0.002 * weight);
  EXPECT_NEAR(run.force_theirs.z(), run.force_ours.z(), 0.02 * weight) << "ranks " << mpiRanks();
  EXPECT_NEAR(run.torque_theirs.y(), run.torque_ours.y(), 0.02 * 0.002 * weight);
  EXPECT_NEAR(run.torque_theirs.x(), run.torque_ours.x(), 0.02 * 0.002 * weight);
  std::printf("sliding plate on %d rank(s): LIGGGHTS Fz %.6g N, My %.6g N m; ours Fz %.6g N, My %.6g N m\n",
              mpiRanks(), run.force_theirs.z(), run.torque_theirs.y(), run.force_ours.z(), run.torque_ours.y());
}

TEST(LiggghtsBackend, TurningAndSlidingMeshDragsTheSphereAsOurs) {
  // With friction the plate, sliding at 0.05 m/s in y and turning at 2 rad/s about z through
  // its moving reference point, drags the sphere; where the sphere is after 0.05 s depends on
  // the wall velocity under it all along (direction of turn, axis through the moving point).
  const MovingPlateRun run =
      runMovingPlate(kBeads, R"("linear_velocity": {"y": 0.05}, "angular_velocity": {"z": 2})", 5000);
  const core::Vec3 start(0.012, 0.01, 0.00199);
  const core::Vec3 ours = run.sphere_ours - start;
  const core::Vec3 theirs = run.sphere_theirs - start;
  EXPECT_GT(ours.head<2>().norm(), 5e-4);  // dragged: about 2/7 of the wall's travel
  EXPECT_LT((theirs - ours).head<2>().norm(), 0.02 * ours.head<2>().norm())
      << "ours (" << ours.x() << ", " << ours.y() << "), LIGGGHTS (" << theirs.x() << ", " << theirs.y() << ")";
  const double r = 0.002;
  const double weight = 2500.0 * 4.0 / 3.0 * std::numbers::pi * r * r * r * 9.81;
  EXPECT_NEAR(run.force_theirs.z(), run.force_ours.z(), 0.02 * weight);
  const double arm = (run.sphere_ours - core::Vec3(0.01, 0.0125, 0)).head<2>().norm();
  EXPECT_NEAR(run.torque_theirs.x(), run.torque_ours.x(), 0.02 * arm * weight);
  EXPECT_NEAR(run.torque_theirs.y(), run.torque_ours.y(), 0.02 * arm * weight);
  std::printf("turning plate on %d rank(s): sphere moved (%.6g, %.6g) mm on LIGGGHTS, (%.6g, %.6g) mm on ours; "
              "Mx %.6g / %.6g, My %.6g / %.6g N m\n",
              mpiRanks(), 1e3 * theirs.x(), 1e3 * theirs.y(), 1e3 * ours.x(), 1e3 * ours.y(), run.torque_theirs.x(),
              run.torque_ours.x(), run.torque_theirs.y(), run.torque_ours.y());
}

TEST(LiggghtsBackend, MeshFollowsATwistThatChangesEveryInterval) {
  // A co-simulation gives a client body a new twist each exchange interval, about a new
  // axis. The plate gets 20 of them (100 steps each, |w| = 40 rad/s about axes that swing
  // round, 0.1 m/s in changing directions), with no set-up after the first: LIGGGHTS's
  // mesh (dumped as STL, 6 significant digits: up to 9e-8 m of rounding) must end where our
  // engine puts it, to 1.5e-7 m; the 20 mm plate's corners move by more than 4 mm. Rates
  // w instead of the exact step angles (first order) miss by 4.5e-7 m here.
  const test::RankSharedDir dir;
  writePlateStl(dir.path());
  const v1::Scene scene = test::sceneOf({
      R"({"name": "box", "simulation_box": {"time_step": 1e-5, "end_time": 0.1,
          "bounds": {"lower": {"x": -0.05, "y": -0.05, "z": -0.05}, "upper": {"x": 0.05, "y": 0.05, "z": 0.05}}}})",
      kBeads,
      R"({"name": "plate", "mesh_body": {"stl_file": "plate.stl", "material": "beads"}})",
      R"({"name": "bead", "single_particle": {"material": "beads",
          "position": {"x": 0.04, "y": 0.04, "z": -0.045}, "diameter": 0.004}})",
  });
  TranslatedScene translated = translateScene(scene, dir.path());
  requireLiggghtsCompatible(scene, translated.world);
  LiggghtsBackend backend(translated.world);
  const std::vector<core::Vec3> start = translated.world.meshes()[0].worldVertices();
  for (int interval = 0; interval < 20; ++interval) {
    const double phase = 0.2 * interval;
    const core::Vec3 axis = core::Vec3(std::cos(phase), std::sin(phase), 0.5 - 0.05 * interval).normalized();
    const core::Vec3 velocity = 0.1 * core::Vec3(std::sin(phase), 0.3, std::cos(phase)).normalized();
    translated.world.mesh(0).setVelocity(velocity, 40.0 * axis);
    backend.advanceTo(backend.stepCount() + 100);
  }
  // mesh/stl wants a '*' in the name, which becomes the step.
  backend.command("write_dump all mesh/stl " + (dir.path() / "plate_at_end*.stl").string() + " " + liggghtsMeshFix(0));
  const std::filesystem::path dump = dir.path() / "plate_at_end2000.stl";
  (void)backend.particleCount();  // a collective: rank 0 has written the dump
  const std::vector<core::Vec3>& ours = backend.world().meshes()[0].worldVertices();
  double travel = 0.0;
  for (std::size_t k = 0; k < ours.size(); ++k) travel = std::max(travel, (ours[k] - start[k]).norm());
  EXPECT_GT(travel, 0.004);
  std::ifstream in(dump);
  std::string word;
  std::size_t vertices = 0;
  double worst = 0.0;
  while (in >> word) {
    if (word != "vertex") continue;
    core::Vec3 x;
    in >> x.x() >> x.y() >> x.z();
    double nearest = std::numeric_limits<double>::infinity();
    for (const core::Vec3& y : ours) nearest = std::min(nearest, (x - y).norm());
    worst = std::max(worst, nearest);
    ++vertices;
  }
  EXPECT_EQ(vertices, 6u) << dump;
  EXPECT_LT(worst, 1.5e-7) << "LIGGGHTS's mesh is off ours after 20 twists";
  std::printf("plate after 20 twists on %d rank(s): vertices moved up to %.4g m, LIGGGHTS's up to %.3g m from ours\n",
              mpiRanks(), travel, worst);
}

/// The scene's tracker.
const core::ParticleTracker& trackerOf(const core::World& world) {
  for (const auto& component : world.components()) {
    if (const auto* tracker = dynamic_cast<const core::ParticleTracker*>(component.get())) return *tracker;
  }
  throw std::runtime_error("no tracker");
}

TEST(LiggghtsBackend, TrackerFollowsTheSlidingSphereAsOnOurs) {
  // A sphere set down on a plane at 0.05 m/s slides, friction turns the slide into rolling
  // at 5/7 of that speed (Coulomb friction, mu = 0.5, on both engines), and it rolls on; a
  // tracker samples it every 5 ms for 0.3 s on both engines. (A bouncing sphere would
  // compare the two engines' wall restitution, not the tracker.) On LIGGGHTS its
  // trajectory stays within 20 um of ours, its velocity within 1 % of the start speed, and
  // the contact force it reports is the plane's m g up (LIGGGHTS's force less gravity).
  const v1::Scene scene = test::sceneOf({
      R"({"name": "box", "simulation_box": {"time_step": 1e-5, "end_time": 0.3,
          "bounds": {"lower": {"x": -0.02, "y": -0.02, "z": -0.005}, "upper": {"x": 0.05, "y": 0.02, "z": 0.03}}}})",
      kBeads,
      plane("floor", R"({"z": 0})", R"({"z": 1})"),
      R"({"name": "bead", "single_particle": {"material": "beads", "position": {"z": 0.002}, "diameter": 0.004,
          "velocity": {"x": 0.05}}})",
      R"({"name": "spy", "tracker": {"particle_ids": [1], "sample_every_steps": 500}})",
  });
  TranslatedScene native = translateScene(scene, {});
  NativeBackend ours(native.world);
  TranslatedScene translated = translateScene(scene, {});
  requireLiggghtsCompatible(scene, translated.world);
  LiggghtsBackend backend(translated.world);
  ASSERT_EQ(liggghtsStride(translated.world, 0), 500u);
  const double r = 0.002;
  const double weight = 2500.0 * 4.0 / 3.0 * std::numbers::pi * r * r * r * 9.81;
  double worstPosition = 0.0, worstVelocity = 0.0, worstForce = 0.0;
  for (std::uint64_t step = 500; step <= 30000; step += 500) {
    ours.advanceTo(step);
    backend.advanceTo(step);
    backend.syncParticles();
    const core::TrackedParticle& a = trackerOf(ours.world()).particles()[0];
    const core::TrackedParticle& b = trackerOf(backend.world()).particles()[0];
    ASSERT_EQ(b.status, core::TrackedParticle::Status::Present);
    ASSERT_EQ(trackerOf(backend.world()).sampleCount(), step / 500 + 1) << "one sample per stride, and at t = 0";
    worstPosition = std::max(worstPosition, (a.position - b.position).norm());
    worstVelocity = std::max(worstVelocity, (a.velocity - b.velocity).norm());
    if (step >= 5000) worstForce = std::max(worstForce, (b.force - core::Vec3(0, 0, weight)).norm());
  }
  const core::TrackedParticle& a = trackerOf(ours.world()).particles()[0];
  const core::TrackedParticle& b = trackerOf(backend.world()).particles()[0];
  EXPECT_NEAR(a.velocity.x(), 5.0 / 7.0 * 0.05, 0.01 * 0.05) << "rolling";
  EXPECT_LT(worstPosition, 2e-5) << "ranks " << mpiRanks();
  EXPECT_LT(worstVelocity, 0.01 * 0.05);
  EXPECT_NEAR(a.force.z(), weight, 0.01 * weight);
  EXPECT_LT(worstForce, 0.01 * weight) << "LIGGGHTS's contact force from 50 ms on";
  std::printf("tracked sphere on %d rank(s): trajectory within %.3g m of ours, velocity within %.3g m/s, contact "
              "force within %.3g N of m g (%.6g N); at 0.3 s x = %.6g m, vx = %.6g m/s on LIGGGHTS, %.6g m, %.6g m/s "
              "on ours\n",
              mpiRanks(), worstPosition, worstVelocity, worstForce, weight, b.position.x(), b.velocity.x(),
              a.position.x(), a.velocity.x());
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
  EXPECT_EQ(backend.world().removedAtBounds().count, 1u) << "ranks " << mpiRanks();
  EXPECT_NEAR(backend.world().removedAtBounds().mass, ours.world().removedAtBounds().mass, 1e-15);
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

TEST(LiggghtsCheckpoint, SettlingBedContinuesAfterARestart) {
  // The deposition scene checkpointed at 0.15 s, half way, and restarted in a new LIGGGHTS
  // instance: at 0.3 s it matches the unbroken run (the contact histories of the resting
  // contacts come back from the restart file; its first force evaluation after the restart
  // uses full-step velocities, so it is not bit-exact).
  const v1::Scene scene = depositionScene();
  const test::RankSharedDir dir;  // the checkpoint is written by rank 0
  const std::filesystem::path checkpoint = dir.path() / "ck.bin";
  TranslatedScene unbrokenScene = translateScene(scene, {});
  LiggghtsBackend unbroken(unbrokenScene.world);
  unbroken.advanceTo(15000);
  unbroken.advanceTo(30000);
  unbroken.syncParticles();
  {
    TranslatedScene firstScene = translateScene(scene, {});
    LiggghtsBackend first(firstScene.world);
    first.advanceTo(15000);
    first.syncParticles();
    first.writeCheckpoint(checkpoint);
  }
  TranslatedScene restartedScene = translateScene(scene, {});
  restartedScene.world.initialize();
  core::restoreCheckpointFile(restartedScene.world, checkpoint);
  LiggghtsBackend restarted(restartedScene.world, "", checkpoint);
  EXPECT_EQ(restarted.stepCount(), 15000u);
  restarted.advanceTo(30000);
  restarted.syncParticles();
  const core::ParticleArrays& a = unbroken.world().particles();
  const core::ParticleArrays& b = restarted.world().particles();
  ASSERT_EQ(a.size(), b.size());
  double worst = 0.0;
  for (std::size_t i = 0; i < a.size(); ++i) {
    ASSERT_EQ(a.id[i], b.id[i]);
    worst = std::max(worst, (a.position[i] - b.position[i]).norm());
  }
  const double za = meanZ(unbroken.world());
  const double zb = meanZ(restarted.world());
  EXPECT_LT(worst, 0.001) << "half the smallest radius";
  EXPECT_NEAR(zb, za, 0.005 * za);
  std::printf("bed restarted at 0.15 s on %d rank(s): at 0.3 s largest position difference %.3g m, mean z %.9g m "
              "(unbroken %.9g m, %.3g %%)\n",
              mpiRanks(), worst, zb, za, 100.0 * (zb - za) / za);
}

}  // namespace
}  // namespace demlink::server

int main(int argc, char** argv) {
  demlink::server::ensureMpi();
  ::testing::InitGoogleTest(&argc, argv);
  return RUN_ALL_TESTS();
}
