/// ParticleSource: rates (particles/s and kg/s) against rate x time, reported
/// totals against what the world gained, no overlaps at insertion with particles,
/// planes and meshes, shortfall, a region riding on a moving mesh, validation,
/// determinism.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "demlink/core/base/input_error.hpp"
#include "demlink/core/walls/mesh_body.hpp"
#include "demlink/core/components/particle_source.hpp"
#include "demlink/core/geometry/triangle_geometry.hpp"
#include "demlink/core/world.hpp"
#include "test_scenes.hpp"

namespace demlink::core {
namespace {

constexpr double kDt = 5.0e-5;  // [s]

SimulationSettings sourceSettings(bool gravity) {
  SimulationSettings s = test::fineSettings(kDt, 2.0);
  s.restitution_tolerance = 0.2;  // tests insertion, not restitution
  if (gravity) s.gravity = Vec3(0.0, 0.0, -9.81);
  return s;
}

/// A 0.2 m box region centred at (0, 0, 1), spheres r in [8, 10] mm, 1000 per second.
ParticleSourceSpec boxSource() {
  ParticleSourceSpec spec;
  spec.region.kind = SourceRegion::Kind::Box;
  spec.region.centre = Vec3(0.0, 0.0, 1.0);
  spec.region.half_extents = Vec3(0.1, 0.1, 0.1);
  spec.rate_particles_per_s = 1000.0;
  spec.sizes = SizeDistribution::uniform(0.008, 0.01);
  spec.seed = 11;
  return spec;
}

void run(World& world, double duration) {
  const auto steps = static_cast<std::uint64_t>(std::llround(duration / kDt));
  for (std::uint64_t n = 0; n < steps; ++n) world.step();
}

/// Smallest gap between sphere `i` and every other sphere [m].
double smallestGap(const ParticleArrays& p, std::size_t i) {
  double gap = 1.0e300;
  for (std::size_t j = 0; j < p.size(); ++j) {
    if (j != i) gap = std::min(gap, (p.position[i] - p.position[j]).norm() - p.radius[i] - p.radius[j]);
  }
  return gap;
}

TEST(ParticleSource, ParticlesPerSecondRateAndTotals) {
  World world(sourceSettings(true));
  world.addMaterial(test::testMaterial(0.5));
  ParticleSourceSpec spec = boxSource();
  spec.start_time = 0.01;
  spec.stop_time = 0.06;
  const ParticleSource& source = addParticleSource(world, "src", spec, "components[0].particle_source");
  run(world, 0.08);
  const SourceReport& r = source.report();
  // Requested: 1000/s over the active 0.05 s; within one particle.
  EXPECT_NEAR(static_cast<double>(r.inserted_count), 1000.0 * 0.05, 1.0);
  EXPECT_NEAR(r.requested_count, 50.0, 1e-9);
  EXPECT_EQ(r.shortfall_count, 0u);
  EXPECT_EQ(r.inserted_count, world.particles().size());
  EXPECT_NEAR(r.inserted_mass, world.totalMass(), 1e-12 * world.totalMass());
}

TEST(ParticleSource, KilogramsPerSecondRateWithinOneParticle) {
  World world(sourceSettings(true));
  const std::uint32_t m = world.addMaterial(test::testMaterial(0.5));
  ParticleSourceSpec spec = boxSource();
  spec.rate_particles_per_s.reset();
  spec.rate_kg_per_s = 5.0;
  spec.material = m;
  const ParticleSource& source = addParticleSource(world, "src", spec, "src");
  run(world, 0.1);
  const SourceReport& r = source.report();
  const double largest = test::sphereMass(0.01, 2500.0);
  EXPECT_NEAR(r.requested_mass, 5.0 * 0.1, 1e-9);
  EXPECT_LE(r.inserted_mass, 0.5 + 1e-12);
  EXPECT_GT(r.inserted_mass, 0.5 - largest);
  EXPECT_GT(r.inserted_count, 40u);
  EXPECT_EQ(r.inserted_count, world.particles().size());
  EXPECT_NEAR(r.inserted_mass, world.totalMass(), 1e-12 * world.totalMass());
}

TEST(ParticleSource, NoOverlapWithParticlesPlaneOrMesh) {
  World world(sourceSettings(false));
  world.addMaterial(test::testMaterial(0.5));
  // Existing particles on a 4 x 4 x 3 lattice in the region (z = 0.925 .. 1.025); a
  // plane keeping particles below z = 1.08 and a flat mesh at z = 1.05 cut the region.
  constexpr std::uint64_t kLattice = 48;
  for (std::uint64_t i = 0; i < kLattice; ++i) {
    ParticleSpec s;
    s.radius = 0.012;
    s.position = Vec3(-0.075 + 0.05 * static_cast<double>(i % 4), -0.075 + 0.05 * static_cast<double>((i / 4) % 4),
                      0.925 + 0.05 * static_cast<double>(i / 16));
    world.addParticle(s);
  }
  world.addPlane({"cut", Vec3(0.0, 0.0, 1.08), -Vec3::UnitZ(), 0});
  const TriangleMesh sheetMesh = rectangleMesh(Vec3(0.0, 0.0, 1.05), 0.2, 0.2, 3, 3);
  MeshBody sheet("sheet", sheetMesh.vertices, sheetMesh.triangles, 0);
  world.addMesh(std::move(sheet));
  ParticleSourceSpec spec = boxSource();
  spec.rate_particles_per_s = 200.0 / kDt;  // 200 in the first step
  spec.stop_time = kDt;
  spec.max_attempts = 200;
  const ParticleSource& source = addParticleSource(world, "src", spec, "src");
  world.initialize();
  world.step();  // no gravity, no velocity, no contact: insertion positions are unchanged
  const ParticleArrays& p = world.particles();
  ASSERT_GT(source.report().inserted_count, 50u);
  const MeshBody& mesh = world.meshes()[0];
  for (std::size_t i = 0; i < p.size(); ++i) {
    if (p.id[i] <= kLattice) continue;
    EXPECT_GE(smallestGap(p, i), -1e-12);
    EXPECT_GE(1.08 - p.position[i].z() - p.radius[i], -1e-12);
    for (const auto& t : mesh.triangles()) {
      const Vec3& a = mesh.worldVertices()[t[0]];
      const Vec3 q = closestPointOnTriangle(p.position[i], a, mesh.worldVertices()[t[1]], mesh.worldVertices()[t[2]]).point;
      EXPECT_GE((q - p.position[i]).norm() - p.radius[i], -1e-12);
    }
  }
}

TEST(ParticleSource, ShortfallWhenTheRegionIsFull) {
  World world(sourceSettings(false));
  world.addMaterial(test::testMaterial(0.5));
  ParticleSourceSpec spec = boxSource();
  spec.region.half_extents = Vec3(0.03, 0.03, 0.03);
  spec.sizes = SizeDistribution::fixed(0.01);
  spec.rate_particles_per_s = 1.0e5;  // 5 per step into a box that holds about 27
  const ParticleSource& source = addParticleSource(world, "src", spec, "src");
  run(world, 40 * kDt);
  const SourceReport& r = source.report();
  EXPECT_GT(r.shortfall_count, 0u);
  EXPECT_LT(r.inserted_count, 60u);
  EXPECT_NEAR(static_cast<double>(r.inserted_count + r.shortfall_count), 200.0, 1.0);  // 1e5/s x 40 dt
  EXPECT_NEAR(r.shortfall_mass, static_cast<double>(r.shortfall_count) * test::sphereMass(0.01, 2500.0),
              1e-12 * r.shortfall_mass);
  EXPECT_EQ(r.inserted_count, world.particles().size());
  for (std::size_t i = 0; i < world.particles().size(); ++i) EXPECT_GE(smallestGap(world.particles(), i), -1e-12);
}

TEST(ParticleSource, RegionAttachedToAMovingMeshFollowsIt) {
  World world(sourceSettings(false));
  world.addMaterial(test::testMaterial(0.5));
  const TriangleMesh plate = rectangleMesh(Vec3::Zero(), 0.05, 0.05, 1, 1);
  MeshBody body("carrier", plate.vertices, plate.triangles, 0);
  body.setVelocity(Vec3(2.0, 0.0, 0.0), Vec3(0.0, 0.0, 3.0));
  world.addMesh(std::move(body));
  ParticleSourceSpec spec = boxSource();
  spec.region.centre = Vec3(0.3, 0.0, 0.2);  // body frame
  spec.region.half_extents = Vec3(0.1, 0.05, 0.05);
  spec.attached_mesh = "carrier";
  spec.rate_particles_per_s = 2000.0;
  spec.velocity = Vec3(0.0, 0.0, 2.0);
  addParticleSource(world, "src", spec, "src");
  world.initialize();
  std::uint64_t seen = 0;
  int checked = 0;
  for (int n = 0; n < 400; ++n) {
    world.step();
    const MeshBody& mesh = world.meshes()[0];
    const ParticleArrays& p = world.particles();
    for (std::size_t i = 0; i < p.size(); ++i) {
      // Inserted this step, then drifted one step at its velocity (unchanged unless it
      // touched an older particle after the drift).
      if (p.id[i] <= seen || !p.force[i].isZero(0.0)) continue;
      const Vec3 inserted = p.position[i] - kDt * p.velocity[i];
      const Vec3 expectedVelocity = spec.velocity + mesh.velocityAt(inserted);
      EXPECT_NEAR((p.velocity[i] - expectedVelocity).norm(), 0.0, 1e-12);
      const Vec3 local = mesh.orientation().conjugate() * (inserted - mesh.position()) - spec.region.centre;
      for (int k = 0; k < 3; ++k) EXPECT_LE(std::abs(local[k]), spec.region.half_extents[k] - p.radius[i] + 1e-12);
      ++checked;
    }
    for (std::size_t i = 0; i < p.size(); ++i) seen = std::max(seen, p.id[i]);
  }
  EXPECT_GE(checked, 30);
  EXPECT_GT(world.meshes()[0].position().x(), 0.039);  // it moved 2 m/s x 0.02 s
}

TEST(ParticleSource, SameSeedSameParticlesOtherSeedOthers) {
  auto positions = [](std::uint64_t seed) {
    World world(sourceSettings(true));
    world.addMaterial(test::testMaterial(0.5));
    ParticleSourceSpec spec = boxSource();
    spec.seed = seed;
    spec.sizes = SizeDistribution::normal(0.009, 0.001, 0.008, 0.01);
    addParticleSource(world, "src", spec, "src");
    run(world, 0.02);
    std::vector<double> out;
    for (std::size_t i = 0; i < world.particles().size(); ++i) {
      out.push_back(world.particles().radius[i]);
      for (int k = 0; k < 3; ++k) out.push_back(world.particles().position[i][k]);
    }
    return out;
  };
  const std::vector<double> a = positions(5);
  EXPECT_GT(a.size(), 40u);
  EXPECT_EQ(a, positions(5));
  EXPECT_NE(a, positions(6));
}

TEST(ParticleSource, FutureSizesEnterTheTimeStepCheck) {
  SimulationSettings s = sourceSettings(true);
  s.time_step = 1.0e-4;  // fine for 10 mm spheres, too large for 1 mm ones
  World fine(s);
  fine.addMaterial(test::testMaterial(0.5));
  addParticleSource(fine, "src", boxSource(), "src");
  EXPECT_NO_THROW(fine.initialize());
  World coarse(s);
  coarse.addMaterial(test::testMaterial(0.5));
  ParticleSourceSpec spec = boxSource();
  spec.sizes = SizeDistribution::uniform(0.001, 0.01);
  addParticleSource(coarse, "src", spec, "src");
  EXPECT_THROW(coarse.initialize(), InputError);
}

TEST(ParticleSource, BadInputNamesTheField) {
  auto fieldOf = [](const std::function<void(ParticleSourceSpec&)>& edit) {
    World world(sourceSettings(true));
    world.addMaterial(test::testMaterial(0.5));
    ParticleSourceSpec spec = boxSource();
    edit(spec);
    try {
      addParticleSource(world, "src", spec, "p");
      world.initialize();
    } catch (const InputError& e) {
      return e.field();
    }
    return std::string("(accepted)");
  };
  EXPECT_EQ(fieldOf([](ParticleSourceSpec&) {}), "(accepted)");
  EXPECT_EQ(fieldOf([](ParticleSourceSpec& s) { s.rate_particles_per_s = -1.0; }), "p.rate_particles_per_s");
  EXPECT_EQ(fieldOf([](ParticleSourceSpec& s) { s.rate_kg_per_s = 1.0; }), "p.rate_particles_per_s");
  EXPECT_EQ(fieldOf([](ParticleSourceSpec& s) { s.rate_particles_per_s.reset(); }), "p.rate_particles_per_s");
  EXPECT_EQ(fieldOf([](ParticleSourceSpec& s) {
              s.rate_particles_per_s.reset();
              s.rate_kg_per_s = -2.0;
            }),
            "p.rate_kg_per_s");
  EXPECT_EQ(fieldOf([](ParticleSourceSpec& s) { s.region.half_extents.y() = 0.0; }), "p.box.half_extents[1]");
  EXPECT_EQ(fieldOf([](ParticleSourceSpec& s) { s.region.half_extents.z() = 0.005; }), "p.box.half_extents[2]");
  EXPECT_EQ(fieldOf([](ParticleSourceSpec& s) {
              s.region.kind = SourceRegion::Kind::Disc;
              s.region.radius = -1.0;
            }),
            "p.disc.radius");
  EXPECT_EQ(fieldOf([](ParticleSourceSpec& s) { s.material = 3; }), "p.material");
  EXPECT_EQ(fieldOf([](ParticleSourceSpec& s) { s.sizes = SizeDistribution::uniform(0.01, 0.005); }), "p.sizes.r_max");
  EXPECT_EQ(fieldOf([](ParticleSourceSpec& s) { s.stop_time = 0.0; }), "p.stop_time");
  EXPECT_EQ(fieldOf([](ParticleSourceSpec& s) { s.start_time = -1.0; }), "p.start_time");
  EXPECT_EQ(fieldOf([](ParticleSourceSpec& s) { s.attached_mesh = "nothing"; }), "p.attached_mesh");
  EXPECT_EQ(fieldOf([](ParticleSourceSpec& s) { s.shape = SourceShape::ClumpTemplate; }), "p.clump_template");
  EXPECT_EQ(fieldOf([](ParticleSourceSpec& s) { s.max_attempts = 0; }), "p.max_attempts");
}

TEST(ParticleSource, DiscRegionKeepsCentresOnTheDisc) {
  World world(sourceSettings(false));
  world.addMaterial(test::testMaterial(0.5));
  ParticleSourceSpec spec = boxSource();
  spec.region.kind = SourceRegion::Kind::Disc;
  spec.region.radius = 0.1;
  // Normal along x: the disc's z axis turned onto world x.
  spec.region.orientation = Quat::FromTwoVectors(Vec3::UnitZ(), Vec3::UnitX());
  spec.rate_particles_per_s = 20.0 / kDt;
  spec.stop_time = kDt;
  const ParticleSource& source = addParticleSource(world, "src", spec, "src");
  run(world, kDt);
  ASSERT_GT(source.report().inserted_count, 10u);
  const ParticleArrays& p = world.particles();
  for (std::size_t i = 0; i < p.size(); ++i) {
    const Vec3 d = p.position[i] - spec.region.centre;
    EXPECT_NEAR(d.x(), 0.0, 1e-12);
    EXPECT_LE(std::hypot(d.y(), d.z()), 0.1 - p.radius[i] + 1e-12);
    EXPECT_GE(smallestGap(p, i), -1e-12);
  }
}

}  // namespace
}  // namespace demlink::core
