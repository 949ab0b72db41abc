/// The particle view lists particles by id, not by storage slot: the engine re-sorts slots
/// (by cell, and when it compacts removed particles), and a 3D view that showed other
/// particles after every re-sort would flicker. The test reverses the slots and expects the
/// same particles with the same positions and velocities.
#include <gtest/gtest.h>

#include <algorithm>
#include <map>
#include <numeric>
#include <vector>

#include "cosim_test_support.hpp"
#include "demlink/server/cosim/cosim_outputs.hpp"

namespace demlink::server::test {
namespace {

struct Listed {
  std::vector<float> position;
  std::vector<float> velocity;
  float radius = 0.0F;
};

std::map<std::uint64_t, Listed> byId(const v1::ParticleViewOutput& o) {
  std::map<std::uint64_t, Listed> out;
  for (int i = 0; i < o.ids_size(); ++i) {
    Listed& l = out[o.ids(i)];
    l.position.assign(o.positions().begin() + 3 * i, o.positions().begin() + 3 * i + 3);
    l.velocity.assign(o.velocities().begin() + 3 * i, o.velocities().begin() + 3 * i + 3);
    l.radius = o.radii(i);
  }
  return out;
}

TEST(CosimParticleView, DecimatedByIdTheSubsetSurvivesAReSortOfTheSlots) {
  CosimCompiler compiler(sceneOf({boxJson(1e-5, 1e-3),
                                  R"({"name": "glass", "material": {"density": 2500, "youngs_modulus": 5e6}})",
                                  R"({"name": "bed", "particle_lattice": {"material": "glass", "radius": 0.002,
                                      "spacing": 0.0042, "counts": {"nx": 5, "ny": 4, "nz": 3},
                                      "velocity": {"x": 0.1, "y": -0.2, "z": 0.3}}})",
                                  R"({"name": "view", "particle_view": {"max_count": 7}})"}));
  CompiledSimulation compiled = compiler.compile(".");
  core::World& world = compiled.scene->world;
  ASSERT_EQ(world.particles().size(), 60u);
  const std::size_t viewIndex = 3;
  ASSERT_EQ(compiled.components[viewIndex].kind, "particle_view");
  // Distinct velocities per particle, so a wrong slot shows.
  for (std::size_t i = 0; i < world.particles().size(); ++i) {
    world.particles().velocity[i] = core::Vec3(0.01 * static_cast<double>(world.particles().id[i]), -0.5, 0.25);
  }

  CosimOutputs outputs(compiled.components.size());
  const v1::ParticleViewOutput before =
      outputs.outputOf(viewIndex, compiled.components[viewIndex], world, {}).particle_view();
  // Largest id 60, at most 7 listed: stride ceil(60 / 7) = 9, ids 9, 18, ..., 54.
  EXPECT_EQ(before.total_count(), 60u);
  EXPECT_EQ(before.stride(), 9u);
  EXPECT_EQ(std::vector<std::uint64_t>(before.ids().begin(), before.ids().end()),
            (std::vector<std::uint64_t>{9, 18, 27, 36, 45, 54}));
  ASSERT_EQ(before.velocities_size(), 3 * before.ids_size());
  EXPECT_FLOAT_EQ(before.velocities(0), 0.09F);  // id 9

  std::vector<std::uint32_t> reversed(world.particles().size());
  std::iota(reversed.rbegin(), reversed.rend(), 0U);
  world.particles().permute(reversed);
  ASSERT_EQ(world.particles().id.front(), 60u) << "the slots are re-sorted";
  const v1::ParticleViewOutput after =
      outputs.outputOf(viewIndex, compiled.components[viewIndex], world, {}).particle_view();
  EXPECT_EQ(std::vector<std::uint64_t>(after.ids().begin(), after.ids().end()),
            std::vector<std::uint64_t>(before.ids().begin(), before.ids().end()));
  const auto a = byId(before);
  const auto b = byId(after);
  for (const auto& [id, listed] : a) {
    EXPECT_EQ(b.at(id).position, listed.position) << "id " << id;
    EXPECT_EQ(b.at(id).velocity, listed.velocity) << "id " << id;
    EXPECT_EQ(b.at(id).radius, listed.radius) << "id " << id;
  }
}

}  // namespace
}  // namespace demlink::server::test
