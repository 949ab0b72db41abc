// SimulationBox.coarse_graining: a factor alpha turns a lattice's and a source's grains into
// parcels alpha times larger carrying the mass of alpha^3 grains (Bierwisch et al. 2009),
// scales an explicit linear stiffness by alpha, keeps the material (cohesion included) and
// the mass flow, and the compile report says so.
#include <cmath>
#include <string>

#include <gtest/gtest.h>

#include "demlink/core/base/input_error.hpp"
#include "demlink/server/scene/scene_translator.hpp"
#include "scene_test_support.hpp"

namespace demlink::server {
namespace {

using test::sceneOf;

/// Box with `fields`, a cohesive linear-law material, a 4 x 4 x 4 lattice of 2 mm grains and
/// a source of 2 mm grains at 2000 grains/s.
v1::Scene scene(const std::string& fields) {
  return sceneOf({R"({"name": "box", "simulation_box": {"end_time": 1, "time_step": 1e-4,
                      "allow_unsafe_time_step": true, "contact_model": "LINEAR_SPRING_DASHPOT",
                      "linear_normal_stiffness": 1000)" + fields + "}}",
                  R"({"name": "soil", "material": {"cohesion_energy_density": 15000}})",
                  R"({"name": "bed", "particle_lattice": {"material": "soil", "radius": 0.002, "spacing": 0.005,
                      "jitter": 0.0002, "counts": {"nx": 4, "ny": 4, "nz": 4}}})",
                  R"({"name": "src", "particle_source": {"material": "soil", "sizes": {"radius": 0.002},
                      "box": {"lower": {"x": 1, "y": 0, "z": 0}, "upper": {"x": 1.3, "y": 0.3, "z": 0.3}},
                      "rate_particles_per_s": 2000}})"});
}

/// Mass of the particles whose centre lies on the side x > 0.5 (the source's) [kg].
double massBeyond(const core::ParticleArrays& p, bool sourceSide) {
  double mass = 0.0;
  for (std::size_t i = 0; i < p.size(); ++i) {
    if ((p.position[i].x() > 0.5) == sourceSide) mass += p.mass[i];
  }
  return mass;
}

TEST(CoarseGrainingScene, FactorTwoScalesParcelsAndKeepsMaterialAndMassFlow) {
  TranslatedScene grains = translateScene(scene(""), {});
  TranslatedScene parcels = translateScene(scene(R"(, "coarse_graining": 2)"), {});
  EXPECT_EQ(grains.coarse_graining.factor, 1.0);
  EXPECT_EQ(parcels.coarse_graining.factor, 2.0);
  // Lattice: 64 grains of 2 mm become 8 parcels of 4 mm.
  ASSERT_EQ(grains.world.particles().size(), 64u);
  ASSERT_EQ(parcels.world.particles().size(), 8u);
  EXPECT_DOUBLE_EQ(parcels.world.particles().radius[0], 0.004);
  // Linear stiffness x alpha keeps delta / R; the material (k_c too) is kept.
  EXPECT_DOUBLE_EQ(parcels.world.settings().linear_normal_stiffness, 2000.0);
  EXPECT_EQ(parcels.world.materials()[0].cohesion_energy_density, 15000.0);
  EXPECT_EQ(parcels.world.materials()[0].density, grains.world.materials()[0].density);

  grains.world.initialize();
  parcels.world.initialize();
  // The lattice's mass is the grains' (exact: 4 is a multiple of 2).
  EXPECT_NEAR(massBeyond(parcels.world.particles(), false), massBeyond(grains.world.particles(), false),
              1e-12 * massBeyond(grains.world.particles(), false));
  // The source: the same mass flow, in parcels of 8 grains' mass. After 0.2 s the grain
  // source has made 400 grains, the parcel source 50 parcels (rate 2000 / 8 = 250 /s);
  // each may be one emission short of the rate, so the masses agree within one parcel.
  while (grains.world.time() < 0.2 - 1e-9) grains.world.step();
  while (parcels.world.time() < 0.2 - 1e-9) parcels.world.step();
  const double grainMass = massBeyond(grains.world.particles(), true);
  const double parcelMass = massBeyond(parcels.world.particles(), true);
  const double oneParcel = 8.0 * grains.world.particles().mass[0];
  EXPECT_GT(grainMass, 0.0);
  EXPECT_NEAR(parcelMass, grainMass, oneParcel) << "grain source " << grainMass << " kg, parcels " << parcelMass;
  for (std::size_t i = 0; i < parcels.world.particles().size(); ++i) {
    EXPECT_DOUBLE_EQ(parcels.world.particles().radius[i], 0.004);
  }
}

TEST(CoarseGrainingScene, ReportNamesTheFactorAndBadFactorsAreRefused) {
  EXPECT_TRUE(coarseGrainingReportLines(core::CoarseGraining{1.0}).empty());
  const std::vector<std::string> lines = coarseGrainingReportLines(core::CoarseGraining{2.0});
  ASSERT_EQ(lines.size(), 1u);
  EXPECT_NE(lines[0].find("coarse graining: factor 2"), std::string::npos) << lines[0];
  EXPECT_NE(lines[0].find("mass of 8 grains"), std::string::npos) << lines[0];
  for (const char* bad : {"0.5", "-1", "0"}) {
    try {
      (void)translateScene(scene(std::string(R"(, "coarse_graining": )") + bad), {});
      ADD_FAILURE() << bad << " accepted";
    } catch (const core::InputError& error) {
      EXPECT_EQ(error.field(), "components[0].simulation_box.coarse_graining") << bad;
    }
  }
}

}  // namespace
}  // namespace demlink::server
