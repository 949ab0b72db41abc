/// Clump templates and clump lattices in scene files: placement (centre of mass at
/// the lattice points, seeded orientations), the example scene, and every rejected
/// field named by its path.
#include <gtest/gtest.h>

#include <set>
#include <sstream>

#include "demlink/core/base/input_error.hpp"
#include "demlink/core/base/random.hpp"
#include "demlink/core/output/vtk_writer.hpp"
#include "demlink/server/scene/scene_loader.hpp"
#include "demlink/server/scene/scene_translator.hpp"
#include "test_support.hpp"
#include "scene_test_support.hpp"

namespace demlink::server {
namespace {

constexpr const char* kBox = R"({"name": "box", "simulation_box": {"end_time": 0.1}})";
constexpr const char* kGlass = R"({"name": "glass", "material": {}})";
constexpr const char* kPair = R"({"name": "pair", "clump_template": {"spheres": [
    {"offset": {"x": -0.001}, "radius": 0.001}, {"offset": {"x": 0.001}, "radius": 0.001}]}})";

using test::sceneOf;

std::string lattice(const std::string& extra) {
  return R"({"name": "grains", "particle_lattice": {"material": "glass", "clump_template": "pair",
             "origin": {"z": 0.01}, "spacing": 0.005, "counts": {"nx": 3, "ny": 2, "nz": 1})" +
         extra + "}}";
}

std::string errorField(const v1::Scene& scene) {
  try {
    (void)translateScene(scene, {});
  } catch (const core::InputError& error) {
    return error.field();
  }
  return "(no error)";
}

TEST(TranslateClumps, LatticePlacesSeededClumpsAtItsPoints) {
  const TranslatedScene t = translateScene(sceneOf({kBox, kGlass, kPair, lattice(R"(, "orientation_seed": "9")")}), {});
  ASSERT_EQ(t.world.clumps().size(), 6u);
  ASSERT_EQ(t.world.particles().size(), 12u);
  std::set<std::uint64_t> ids;
  core::Random rng(9);
  for (std::size_t k = 0; k < t.world.clumps().size(); ++k) {
    const core::ClumpBody& body = t.world.clumps()[k];
    const core::Vec3 point(0.005 * static_cast<double>(k % 3), 0.005 * static_cast<double>(k / 3), 0.01);
    EXPECT_LT((body.position - point).norm(), 1e-15);
    const auto& x = t.world.particles().position;
    // The template's frame is turned by the k-th draw of the orientation generator:
    // its x axis (the pair axis) goes to orientation * x.
    const core::Quat drawn = core::uniformRotation(rng);
    const core::Vec3 axis = (x[body.member_slots[1]] - x[body.member_slots[0]]).normalized();
    EXPECT_LT((axis - drawn * core::Vec3::UnitX()).norm(), 1e-12);
    EXPECT_LT(((x[body.member_slots[0]] + x[body.member_slots[1]]) / 2.0 - point).norm(), 1e-12);
    EXPECT_NEAR((x[body.member_slots[1]] - x[body.member_slots[0]]).norm(), 0.002, 1e-15);
    ids.insert(body.id);
  }
  EXPECT_EQ(ids.size(), 6u);
  // Orientations differ between clumps and are reproduced by the same seed only.
  const TranslatedScene same = translateScene(sceneOf({kBox, kGlass, kPair, lattice(R"(, "orientation_seed": "9")")}), {});
  const TranslatedScene other = translateScene(sceneOf({kBox, kGlass, kPair, lattice(R"(, "orientation_seed": "10")")}), {});
  EXPECT_EQ(t.world.clumps()[0].orientation.coeffs(), same.world.clumps()[0].orientation.coeffs());
  EXPECT_GT((t.world.clumps()[0].orientation.coeffs() - other.world.clumps()[0].orientation.coeffs()).norm(), 1e-3);
  EXPECT_GT((t.world.clumps()[0].orientation.coeffs() - t.world.clumps()[1].orientation.coeffs()).norm(), 1e-3);
}

TEST(TranslateClumps, VtkClumpIdColumnNamesEachMembersClump) {
  TranslatedScene t = translateScene(sceneOf({kBox, kGlass, kPair, lattice("")}), {});
  core::ParticleSpec free;
  free.radius = 0.001;
  free.position = core::Vec3(0.0, 0.0, 0.05);
  t.world.addParticle(free);
  const test::ScratchDir dir;
  const std::filesystem::path file = dir.path() / "p.vtp";
  core::writeParticlesVtp(file.string(), t.world.particles(), core::VtkEncoding::Ascii);
  const std::string xml = test::readText(file);
  const std::size_t start = xml.find('>', xml.find("Name=\"clump_id\"")) + 1;
  std::istringstream values(xml.substr(start, xml.find("</DataArray>", start) - start));
  std::vector<std::uint64_t> ids;
  for (std::uint64_t id = 0; values >> id;) ids.push_back(id);
  ASSERT_EQ(ids.size(), t.world.particles().size());
  for (const core::ClumpBody& body : t.world.clumps()) {
    for (const std::uint32_t slot : body.member_slots) EXPECT_EQ(ids[slot], body.id);
  }
  EXPECT_EQ(ids.back(), 0u) << "a free sphere has clump_id 0";
}

TEST(TranslateClumps, ExampleSceneHasClumps) {
  const std::filesystem::path file = std::filesystem::path(DEMLINK_EXAMPLES_DIR) / "scenes" / "clump_pile.json";
  const TranslatedScene t = translateScene(loadSceneFile(file.string()), file.parent_path());
  EXPECT_EQ(t.world.clumpTemplates().size(), 1u);
  EXPECT_EQ(t.world.clumps().size(), 200u);
  EXPECT_EQ(t.world.particles().size(), 600u);
}

TEST(TranslateClumps, BadFieldsAreNamed) {
  EXPECT_EQ(errorField(sceneOf({kBox, kGlass, R"({"name": "t", "clump_template": {}})"})),
            "components[2].clump_template.spheres");
  EXPECT_EQ(errorField(sceneOf({kBox, kGlass,
                                R"({"name": "t", "clump_template": {"spheres": [{"radius": 0.001}, {"radius": -1}]}})"})),
            "components[2].clump_template.spheres[1].radius");
  EXPECT_EQ(errorField(sceneOf({kBox, kGlass, kPair,
                                R"({"name": "grains", "particle_lattice": {"material": "glass", "clump_template": "pear",
                                    "spacing": 0.005, "counts": {"nx": 1, "ny": 1, "nz": 1}}})"})),
            "components[3].particle_lattice.clump_template");
  EXPECT_EQ(errorField(sceneOf({kBox, kGlass, kPair, lattice(R"(, "radius": 0.001)")})),
            "components[3].particle_lattice.radius");
  EXPECT_EQ(errorField(sceneOf({kBox, kGlass, kPair, lattice(R"(, "radius_max": 0.001)")})),
            "components[3].particle_lattice.radius_max");
  EXPECT_EQ(errorField(sceneOf({kBox, kGlass, kPair, lattice(R"(, "jitter": 0.0006)")})),
            "components[3].particle_lattice.spacing");
  EXPECT_EQ(errorField(sceneOf({kBox, kGlass, kPair,
                                R"({"name": "grains", "particle_lattice": {"material": "steel", "clump_template": "pair",
                                    "spacing": 0.005, "counts": {"nx": 1, "ny": 1, "nz": 1}}})"})),
            "components[3].particle_lattice.material");
  EXPECT_EQ(errorField(sceneOf({kBox, kGlass, kPair,
                                R"({"name": "grains", "particle_lattice": {"material": "glass", "clump_template": "pair",
                                    "spacing": 0.005}})"})),
            "components[3].particle_lattice.counts");
}

}  // namespace
}  // namespace demlink::server
