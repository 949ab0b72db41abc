/// Clumps from sources and pits: a particle source of clumps meets its particles/s
/// rate (within one clump) without any member overlapping another particle or the
/// floor, every clump complete and rigid, seeded orientations; a kg/s clump source
/// reports exactly the mass the world gained; a pit of clumps settles to its target
/// height with only small overlaps (which also checks that the copied orientations
/// are those of the settled bed); bad engine input names the field.
#include <gtest/gtest.h>

#include <cmath>
#include <set>

#include "demlink/core/base/input_error.hpp"
#include "demlink/core/components/particle_source.hpp"
#include "demlink/core/setup/pit_generator.hpp"
#include "demlink/core/world.hpp"
#include "test_scenes.hpp"

namespace demlink::core {
namespace {

constexpr double kDt = 2.0e-5;  // [s]

/// A bent triplet of 1.5 mm spheres (bounding radius about 3.1 mm).
ClumpTemplate triplet() {
  return ClumpTemplate("triplet", {{Vec3(-0.0016, 0.0, 0.0), 0.0015},
                                   {Vec3(0.0, 0.0008, 0.0), 0.0015},
                                   {Vec3(0.0016, 0.0, 0.0), 0.0015}});
}

/// A 0.06 m box region centred 0.02 m above a floor at z = 0 (its lower part lies
/// below the floor, so the plane test matters), clumps of template `shape`.
ParticleSourceSpec clumpSource(std::uint32_t shape) {
  ParticleSourceSpec spec;
  spec.region.kind = SourceRegion::Kind::Box;
  spec.region.centre = Vec3(0.0, 0.0, 0.02);
  spec.region.half_extents = Vec3(0.03, 0.03, 0.03);
  spec.shape = SourceShape::ClumpTemplate;
  spec.clump_template = shape;
  spec.seed = 17;
  return spec;
}

void run(World& world, double duration) {
  const auto steps = static_cast<std::uint64_t>(std::llround(duration / kDt));
  for (std::uint64_t n = 0; n < steps; ++n) world.step();
}

/// Every member of every clump sits at its body-frame offset from the COM (rigid).
void expectCompleteAndRigid(const World& world) {
  const ParticleArrays& p = world.particles();
  for (const ClumpBody& body : world.clumps()) {
    const ClumpTemplate& shape = world.clumpTemplates()[body.template_index];
    ASSERT_EQ(body.member_slots.size(), shape.bodySpheres().size());
    for (std::size_t k = 0; k < body.member_slots.size(); ++k) {
      const std::uint32_t slot = body.member_slots[k];
      EXPECT_EQ(p.clump_id[slot], body.id);
      EXPECT_EQ(p.radius[slot], shape.bodySpheres()[k].radius);
      const Vec3 expected = body.position + body.orientation * shape.bodySpheres()[k].offset;
      EXPECT_LT((p.position[slot] - expected).norm(), 1e-12);
    }
  }
}

TEST(ClumpSource, ParticlesPerSecondRateWithoutOverlaps) {
  World world(test::fineSettings(kDt, 1.0));
  world.addMaterial(test::testMaterial(0.5));
  const std::uint32_t shape = world.addClumpTemplate(triplet());
  world.addPlane({"floor", Vec3::Zero(), Vec3::UnitZ(), 0});
  // Obstacles inside the region: a few free spheres at rest.
  for (int k = 0; k < 5; ++k) {
    ParticleSpec sphere;
    sphere.position = Vec3(-0.02 + 0.01 * k, 0.005 * k - 0.01, 0.01 + 0.004 * k);
    sphere.radius = 0.004;
    world.addParticle(sphere);
  }
  ParticleSourceSpec spec = clumpSource(shape);
  spec.rate_particles_per_s = 2000.0;
  spec.stop_time = 0.02;
  const ParticleSource& source = addParticleSource(world, "src", spec, "components[0].particle_source");
  run(world, 0.025);
  const SourceReport& r = source.report();
  EXPECT_NEAR(static_cast<double>(r.inserted_count), 2000.0 * 0.02, 1.0);
  EXPECT_EQ(r.shortfall_count, 0u);
  ASSERT_EQ(world.clumps().size(), r.inserted_count);
  EXPECT_EQ(world.particles().size(), 5 + 3 * r.inserted_count);
  expectCompleteAndRigid(world);
  // Nothing moves (no gravity, zero velocity), so the placement is what we see:
  // no member overlaps another particle (other clump or free sphere) or the floor.
  const ParticleArrays& p = world.particles();
  for (std::size_t i = 0; i < p.size(); ++i) {
    EXPECT_GE(p.position[i].z() - p.radius[i], -1e-12);
    for (std::size_t j = i + 1; j < p.size(); ++j) {
      if (p.clump_id[i] != 0 && p.clump_id[i] == p.clump_id[j]) continue;
      EXPECT_GE((p.position[i] - p.position[j]).norm() - p.radius[i] - p.radius[j], -1e-12) << i << " " << j;
    }
  }
  // Seeded orientations: all different.
  std::set<std::array<double, 4>> orientations;
  for (const ClumpBody& body : world.clumps()) {
    const Quat& q = body.orientation;
    orientations.insert({q.w(), q.x(), q.y(), q.z()});
  }
  EXPECT_EQ(orientations.size(), world.clumps().size());
}

TEST(ClumpSource, KilogramsPerSecondMassMatchesTheWorldsGain) {
  World world(test::fineSettings(kDt, 1.0));
  const std::uint32_t m = world.addMaterial(test::testMaterial(0.5));
  const std::uint32_t shape = world.addClumpTemplate(triplet());
  ParticleSpec sphere;  // something already there
  sphere.position = Vec3(0.5, 0.0, 0.0);
  sphere.radius = 0.004;
  world.addParticle(sphere);
  const double before = world.totalMass();
  ParticleSourceSpec spec = clumpSource(shape);
  spec.material = m;
  spec.rate_kg_per_s = 0.05;
  spec.velocity = Vec3(0.0, 0.0, -0.3);
  const ParticleSource& source = addParticleSource(world, "src", spec, "components[0].particle_source");
  run(world, 0.05);
  const SourceReport& r = source.report();
  const double clumpMass = 2500.0 * world.clumpTemplates()[shape].volume();  // [kg]
  ASSERT_GT(r.inserted_count, 10u);
  EXPECT_EQ(r.shortfall_count, 0u);
  const double gain = world.totalMass() - before;
  EXPECT_NEAR(r.inserted_mass, gain, 1e-12 * gain);
  double memberMass = 0.0;
  for (std::size_t i = 0; i < world.particles().size(); ++i) {
    if (world.particles().clump_id[i] != 0) memberMass += world.particles().mass[i];
  }
  EXPECT_NEAR(r.inserted_mass, memberMass, 1e-12 * gain);
  // Within one clump of rate x time, and every clump counted once.
  EXPECT_LE(r.inserted_mass, 0.05 * 0.05 + 1e-15);
  EXPECT_GT(r.inserted_mass, 0.05 * 0.05 - clumpMass);
  EXPECT_EQ(world.clumps().size(), r.inserted_count);
  // All move together with the source velocity (no gravity, so no contacts).
  for (const ClumpBody& body : world.clumps()) {
    EXPECT_LT((body.velocity - spec.velocity).norm(), 1e-12);
    EXPECT_LT(body.angular_momentum.norm(), 1e-18);
  }
  expectCompleteAndRigid(world);
}

/// A 0.16 x 0.08 m pit, bed 0.06 m deep, of 8 mm sphere pairs (bounding radius 14 mm).
/// The pair lies along a diagonal, off the template origin, so its principal
/// rotation and COM shift are not trivial.
PitSpec clumpPit(std::uint32_t shape) {
  PitSpec spec;
  spec.lower = Vec3(-0.08, -0.04, 0.0);
  spec.upper = Vec3(0.08, 0.04, 0.3);
  spec.target_height = 0.06;
  spec.clump_template = shape;
  spec.seed = 4;
  return spec;
}

TEST(ClumpPit, SettlesToTheTargetWithSmallOverlaps) {
  World world{SimulationSettings{}};
  world.addMaterial(test::testMaterial(0.3, 0.3));
  const std::uint32_t shape =
      world.addClumpTemplate(ClumpTemplate("pair", {{Vec3(0.002, -0.0042, 0.0042), 0.008}, {Vec3(0.002, 0.0042, -0.0042), 0.008}}));
  const PitSpec spec = clumpPit(shape);
  const PitReport report = generatePit(world, spec, "pit", "components[2].pit_generator");
  const double bounding = world.clumpTemplates()[shape].boundingRadius();  // [m]
  const double surface = spec.target_height;
  EXPECT_TRUE(report.settled);
  EXPECT_LT(report.final_mean_kinetic_energy, report.threshold);
  ASSERT_GT(report.kept, 20u);
  EXPECT_EQ(report.kept, world.clumps().size());
  EXPECT_NEAR(report.kept_mass, world.totalMass(), 1e-12 * world.totalMass());
  EXPECT_LE(report.bed_top, surface + 1e-12);
  EXPECT_GE(report.bed_top, surface - 2.0 * bounding);
  expectCompleteAndRigid(world);
  const ParticleArrays& p = world.particles();
  double top = 0.0;
  for (std::size_t i = 0; i < p.size(); ++i) {
    const double r = p.radius[i];
    top = std::max(top, p.position[i].z() + r);
    EXPECT_GE(p.position[i].z() - r, -0.05 * r);
    for (int k = 0; k < 2; ++k) {
      EXPECT_GE(p.position[i][k] - r, spec.lower[k] - 0.05 * r);
      EXPECT_LE(p.position[i][k] + r, spec.upper[k] + 0.05 * r);
    }
    // A wrongly converted orientation would turn the members into their neighbours.
    for (std::size_t j = i + 1; j < p.size(); ++j) {
      if (p.clump_id[i] == p.clump_id[j]) continue;
      EXPECT_LT(r + p.radius[j] - (p.position[i] - p.position[j]).norm(), 0.05 * r) << i << " " << j;
    }
  }
  EXPECT_NEAR(top, report.bed_top, 1e-12);
  for (const ClumpBody& body : world.clumps()) EXPECT_EQ(body.velocity, Vec3::Zero());
}

TEST(ClumpSource, BadInputNamesTheField) {
  auto fieldOf = [](auto&& action) {
    try {
      action();
    } catch (const InputError& error) {
      return error.field();
    }
    return std::string("(accepted)");
  };
  auto source = [&](std::uint32_t shape, double halfExtent) {
    return fieldOf([&] {
      World world(test::fineSettings(kDt, 1.0));
      world.addMaterial(test::testMaterial(0.5));
      world.addClumpTemplate(triplet());
      ParticleSourceSpec spec = clumpSource(shape);
      spec.rate_particles_per_s = 10.0;
      spec.region.half_extents = Vec3(0.03, halfExtent, 0.03);
      addParticleSource(world, "src", spec, "p");
      world.initialize();
    });
  };
  EXPECT_EQ(source(0, 0.03), "(accepted)");
  EXPECT_EQ(source(1, 0.03), "p.clump_template");
  EXPECT_EQ(source(0, 0.002), "p.box.half_extents[1]");  // thinner than the bounding radius
  auto pit = [&](std::uint32_t shape, double width) {
    return fieldOf([&] {
      World world{SimulationSettings{}};
      world.addMaterial(test::testMaterial(0.5));
      world.addClumpTemplate(triplet());
      PitSpec spec = clumpPit(shape);
      spec.upper.x() = spec.lower.x() + width;
      spec.max_settle_time = 1e-3;
      generatePit(world, spec, "pit", "q");
    });
  };
  EXPECT_EQ(pit(1, 0.16), "q.clump_template");
  EXPECT_EQ(pit(0, 0.005), "q.upper[0]");  // narrower than 1.15 clump diameters
}

}  // namespace
}  // namespace demlink::core
