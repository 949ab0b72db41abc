/// A column of clumps collapses into a steeper heap than a column of spheres of
/// the same material and the same particle volume: the clumps' shape interlocks
/// where spheres roll off each other (no rolling resistance between grains; the
/// floor plane has rolling resistance so that its first layer does not roll away).
/// The heap is measured by height / base radius (the horizontal radius around the
/// column axis holding 95 % of the particles). Numbers of a larger run (an 8 x 8 x 12
/// column, collapseColumn(.., 8, 12, 1.5)) are in docs/clumps.md.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "demlink/core/base/random.hpp"
#include "demlink/core/world.hpp"
#include "test_scenes.hpp"

namespace demlink::core {
namespace {

struct Heap {
  double height = 0.0;       ///< highest particle top above the floor [m]
  double base_radius = 0.0;  ///< 95 % of the particles lie within this horizontal radius [m]
  double kinetic = 0.0;      ///< kinetic energy at the end [J]
  std::uint64_t steps = 0;
  [[nodiscard]] double aspect() const { return height / base_radius; }
};

/// Four overlapping spheres (1.5 mm radii) at the corners of a tetrahedron of
/// edge 2.4 mm [m]: a compact but non-round grain.
ClumpTemplate grainTemplate() {
  const double a = 0.0024 / std::sqrt(8.0);  // half the cube edge of the tetrahedron [m]
  return ClumpTemplate("grain", {{Vec3(a, a, a), 0.0015},
                                 {Vec3(a, -a, -a), 0.0015},
                                 {Vec3(-a, a, -a), 0.0015},
                                 {Vec3(-a, -a, a), 0.0015}});
}

Heap collapseColumn(bool clumps, int side, int layers, double duration) {
  SimulationSettings settings;
  settings.time_step = 3.5e-5;
  settings.max_impact_velocity = 1.0;
  settings.restitution_tolerance = 0.2;  // a pile's angle, not restitution, is tested
  World world(settings);
  Material grain = test::testMaterial(0.3, 0.5);
  grain.youngs_modulus = 5.0e6;
  const auto grains = world.addMaterial(grain);
  Material floorMaterial = grain;
  floorMaterial.name = "floor";
  floorMaterial.rolling_friction = 0.6;
  const auto floor = world.addMaterial(floorMaterial);
  world.addPlane({"floor", Vec3::Zero(), Vec3::UnitZ(), floor});
  const ClumpTemplate shape = grainTemplate();
  const double spacing = 2.05 * shape.boundingRadius();
  const double equalVolumeRadius = std::cbrt(3.0 * shape.volume() / (4.0 * std::numbers::pi));
  const auto shapeIndex = world.addClumpTemplate(shape);
  Random rng(11);
  for (int iz = 0; iz < layers; ++iz) {
    for (int iy = 0; iy < side; ++iy) {
      for (int ix = 0; ix < side; ++ix) {
        const Vec3 point((ix - 0.5 * (side - 1)) * spacing, (iy - 0.5 * (side - 1)) * spacing,
                         shape.boundingRadius() + 0.0005 + iz * spacing);
        if (clumps) {
          ClumpSpec spec;
          spec.template_index = shapeIndex;
          spec.material = grains;
          spec.position = point;
          spec.orientation = uniformRotation(rng);
          world.addClump(spec);
        } else {
          ParticleSpec sphere;
          sphere.radius = equalVolumeRadius;
          sphere.material = grains;
          // The same small random offsets break the lattice's symmetry for spheres too.
          sphere.position = point + 0.0002 * Vec3(rng.uniform() - 0.5, rng.uniform() - 0.5, 0.0);
          world.addParticle(sphere);
        }
      }
    }
  }
  world.initialize();
  Heap heap;
  const auto steps = static_cast<std::uint64_t>(duration / settings.time_step);
  for (std::uint64_t s = 0; s < steps; ++s) world.step();
  heap.steps = steps;
  heap.kinetic = world.kineticEnergy();
  const ParticleArrays& p = world.particles();
  std::vector<double> radial;
  for (std::size_t i = 0; i < p.size(); ++i) {
    heap.height = std::max(heap.height, p.position[i].z() + p.radius[i]);
    radial.push_back(std::hypot(p.position[i].x(), p.position[i].y()));
  }
  std::sort(radial.begin(), radial.end());
  heap.base_radius = radial[static_cast<std::size_t>(0.95 * static_cast<double>(radial.size() - 1))];
  return heap;
}

TEST(ClumpPile, ClumpsStandSteeperThanSpheres) {
  // 4 x 4 x 14 = 224 particles each; 0.8 s of collapse.
  const Heap spheres = collapseColumn(false, 4, 14, 0.8);
  const Heap clumps = collapseColumn(true, 4, 14, 0.8);
  std::printf("spheres: H = %.4f m, R95 = %.4f m, H/R = %.3f, KE = %.3g J\n", spheres.height, spheres.base_radius,
              spheres.aspect(), spheres.kinetic);
  std::printf("clumps:  H = %.4f m, R95 = %.4f m, H/R = %.3f, KE = %.3g J\n", clumps.height, clumps.base_radius,
              clumps.aspect(), clumps.kinetic);
  EXPECT_GT(clumps.aspect(), 1.15 * spheres.aspect());
}

}  // namespace
}  // namespace demlink::core
