/// The LIGGGHTS input of particle sources and the hand-over stride (liggghts_flows.hpp):
/// continuous size distributions as discrete classes that keep our mean particle mass, the
/// insertion commands of a box and a disc source, and the refusals naming the field. No
/// LIGGGHTS or MPI needed.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "demlink/core/base/input_error.hpp"
#include "demlink/server/backend/liggghts_flows.hpp"
#include "scene_test_support.hpp"
#include "test_support.hpp"

namespace demlink::server {
namespace {

const std::string kBox = R"({"name": "box", "simulation_box": {"time_step": 5e-6, "end_time": 0.01,
    "bounds": {"lower": {"x": 0, "y": 0, "z": 0}, "upper": {"x": 0.1, "y": 0.1, "z": 0.1}}}})";
const std::string kBeads = R"({"name": "beads", "material": {"density": 2500, "youngs_modulus": 5e6,
    "poisson_ratio": 0.3, "restitution": 0.5, "sliding_friction": 0.5}})";

bool has(const std::string& text, const std::string& part) { return text.find(part) != std::string::npos; }

/// Mean of r^3 over the classes [m^3].
double meanCube(const std::vector<LiggghtsSizeClass>& classes) {
  double sum = 0.0;
  double total = 0.0;
  for (const LiggghtsSizeClass& c : classes) {
    sum += c.number_fraction * c.radius * c.radius * c.radius;
    total += c.number_fraction;
  }
  EXPECT_NEAR(total, 1.0, 1e-12);
  return sum;
}

TEST(LiggghtsSizeClasses, KeepTheMeanParticleMass) {
  using core::SizeDistribution;
  const std::vector<SizeDistribution> continuous = {
      SizeDistribution::uniform(0.001, 0.002),
      SizeDistribution::linear(0.001, 0.002, 1.0, 3.0),
      SizeDistribution::normal(0.0015, 0.0003, 0.001, 0.002),
  };
  for (const SizeDistribution& sizes : continuous) {
    const std::vector<LiggghtsSizeClass> classes = liggghtsSizeClasses(sizes);
    ASSERT_EQ(classes.size(), static_cast<std::size_t>(kLiggghtsSizeClasses));
    EXPECT_NEAR(meanCube(classes), sizes.moment(3), 1e-9 * sizes.moment(3));
    for (const LiggghtsSizeClass& c : classes) {
      EXPECT_GE(c.radius, sizes.r_min);
      EXPECT_LE(c.radius, sizes.r_max);
    }
    EXPECT_TRUE(std::is_sorted(classes.begin(), classes.end(),
                               [](const auto& a, const auto& b) { return a.radius < b.radius; }));
  }
  // A linear pdf rising to the right puts more particles in the upper classes.
  const std::vector<LiggghtsSizeClass> rising = liggghtsSizeClasses(continuous[1]);
  EXPECT_GT(rising.back().number_fraction, 2.0 * rising.front().number_fraction);
  const std::vector<LiggghtsSizeClass> discrete = liggghtsSizeClasses(SizeDistribution::discrete({0.001, 0.002}, {1, 3}));
  ASSERT_EQ(discrete.size(), 2u);
  EXPECT_DOUBLE_EQ(discrete[1].number_fraction, 0.75);
  EXPECT_EQ(liggghtsSizeClasses(SizeDistribution::fixed(0.001)).size(), 1u);
}

std::string sourceWith(const std::string& region, const std::string& extra = {}) {
  return R"({"name": "rain", "particle_source": {"material": "beads", "sizes": {"uniform": {"r_min": 0.001, "r_max": 0.0015}},
      )" + region + R"(, "rate_kg_per_s": 0.01)" + extra + "}}";
}

/// The source commands of a scene with `source`, or the InputError as "field = value: reason".
std::vector<std::string> commandsOf(const std::string& source) {
  TranslatedScene translated = translateScene(test::sceneOf({kBox, kBeads, source}), {});
  translated.world.initialize();
  try {
    return liggghtsSourceCommands(translated.world);
  } catch (const core::InputError& error) {
    return {std::string("refused: ") + error.what()};
  }
}

TEST(LiggghtsSourceCommands, BoxSourceInsertsAtOurRate) {
  const std::vector<std::string> commands =
      commandsOf(sourceWith(R"("box": {"lower": {"x": 0.01, "y": 0.02, "z": 0.07}, "upper": {"x": 0.05, "y": 0.06, "z": 0.09}})",
                            R"(, "stop_time": 0.5, "velocity": {"z": -0.5}, "start_time": 0.1)"));
  ASSERT_EQ(commands.size(), static_cast<std::size_t>(kLiggghtsSizeClasses) + 3) << commands[0];
  EXPECT_TRUE(has(commands[0], "particletemplate/sphere") && has(commands[0], "atom_type 1 density constant 2500"))
      << commands[0];
  EXPECT_TRUE(has(commands[kLiggghtsSizeClasses], "particledistribution/discrete/numberbased"));
  EXPECT_TRUE(has(commands[kLiggghtsSizeClasses + 1], "region demlink_source0_region block 0.01000000000000000") &&
              has(commands[kLiggghtsSizeClasses + 1], "0.08999999999999999"))
      << commands[kLiggghtsSizeClasses + 1];
  const std::string& insert = commands.back();
  EXPECT_TRUE(has(insert, "fix demlink_source0 all insert/rate/region")) << insert;
  EXPECT_TRUE(has(insert, "massrate 0.01 ") && has(insert, "mass 0.004") && has(insert, "start 20000") &&
              has(insert, "vel constant 0 0 -0.5") && has(insert, "all_in yes"))
      << insert;
}

TEST(LiggghtsSourceCommands, ThickDiscIsACylinder) {
  const std::vector<std::string> commands = commandsOf(
      sourceWith(R"("disc": {"centre": {"x": 0.05, "y": 0.04, "z": 0.08}, "normal": {"z": 1}, "radius": 0.02, "thickness": 0.004})"));
  const auto region = std::find_if(commands.begin(), commands.end(), [](const auto& c) { return c.starts_with("region"); });
  ASSERT_NE(region, commands.end()) << commands[0];
  EXPECT_TRUE(has(*region, "cylinder z 0.050000000000000003 0.040000000000000001 0.02 0.078")) << *region;
}

TEST(LiggghtsSourceCommands, UnmappableSourcesRefusedNamingTheField) {
  const std::string thin =
      commandsOf(sourceWith(R"("disc": {"centre": {"x": 0.05, "y": 0.05, "z": 0.08}, "radius": 0.02})"))[0];
  EXPECT_TRUE(has(thin, "refused: particle_source rain.disc.thickness")) << thin;
  const std::string tilted = commandsOf(
      sourceWith(R"("disc": {"centre": {"x": 0.05, "y": 0.05, "z": 0.05}, "normal": {"x": 1, "z": 1}, "radius": 0.02, "thickness": 0.004})"))[0];
  EXPECT_TRUE(has(tilted, "refused: particle_source rain.disc.normal")) << tilted;
  const std::string rotated = commandsOf(sourceWith(
      R"("box": {"centre": {"x": 0.05, "y": 0.05, "z": 0.05}, "half_extents": {"x": 0.01, "y": 0.01, "z": 0.01},
          "orientation": {"w": 0.9238795, "z": 0.3826834}})"))[0];
  EXPECT_TRUE(has(rotated, "refused: particle_source rain.box.orientation")) << rotated;
}

TEST(LiggghtsStride, EverySampleFallsOnAHandOver) {
  TranslatedScene translated = translateScene(
      test::sceneOf({kBox, kBeads,
                     R"({"name": "a", "region_sensor": {"region": {"sphere": {"radius": 0.01}}, "sample_every_steps": 60}})",
                     R"({"name": "b", "particle_sink": {"region": {"sphere": {"radius": 0.01}}, "sample_every_steps": 40}})"}),
      {});
  translated.world.initialize();
  EXPECT_EQ(liggghtsStride(translated.world, 0), 20u);
  EXPECT_EQ(liggghtsStride(translated.world, 1000), 20u);
  EXPECT_EQ(liggghtsStride(translated.world, 90), 10u);
}

}  // namespace
}  // namespace demlink::server
