// Clump templates declared by a client: a particle_source naming one pours clumps, and a bad
// template is refused through the scene file's validation, naming the component and field.
// The template and the source are built with the C++ client's typed components, so the
// declarations are the ones that client sends.
#include <gtest/gtest.h>

#include "cosim_test_support.hpp"
#include "demlink/client/particle_components.hpp"
#include "demlink/core/particles/clump_template.hpp"

namespace demlink::server::test {
namespace {


TEST(CosimClumps, ClientDeclaredTemplateIsPouredAsClumps) {
  ScratchDir dir;
  CosimHarness h(dir.path());
  h.hello(1);
  h.declare(1, boxJson(2e-5, 0.02, R"("coupling": {"expected_count": 5})", 0.002));
  h.declare(1, R"({"name": "glass", "material": {"density": 2500, "youngs_modulus": 5e6}})");
  h.declare(1, R"({"name": "floor", "plane": {"normal": {"z": 1}, "material": "glass"}})");
  client::ClumpTemplate pebble("pebble");
  pebble.addSphere({-0.0012, 0.0, 0.0}, 0.0015).addSphere({0.0012, 0.0, 0.0}, 0.0012);
  h.declare(1, pebble.declaration());
  client::ParticleSource pour("pour");
  pour.setMaterial("glass").setClumpTemplate("pebble").setBox({0.0, 0.0, 0.02}, {0.02, 0.02, 0.01});
  pour.setRateParticles(2000).setSeed(3).setCommunicationInterval(0.002);
  h.declare(1, pour.declaration());
  ASSERT_TRUE(h.compiled(1)) << (h.errors(1).empty() ? "" : h.errors(1).front().message());
  std::size_t read = h.inbox(1).size();
  for (const char* name : {"box", "pour"}) h.sample(1, h.idOf(1, name), 0);
  while (read < h.inbox(1).size()) {
    const v1::ServerMessage m = h.inbox(1)[read++];
    if (m.has_data() && !h.finished(1)) h.sample(1, m.data().component_id(), m.data().step());
  }
  ASSERT_TRUE(h.finished(1));
  const v1::SourceSinkOutput source = h.lastData(1, h.idOf(1, "pour"))->particle_source();
  const v1::SimulationBoxOutput box = h.lastData(1, h.idOf(1, "box"))->simulation_box();
  // The engine's own template of the same spheres sets the mass of one clump.
  const core::ClumpTemplate shape("pebble", {{core::Vec3(-0.0012, 0, 0), 0.0015}, {core::Vec3(0.0012, 0, 0), 0.0012}});
  const double clumpMass = 2500.0 * shape.volume();
  ASSERT_GT(source.total().count(), 10u);
  EXPECT_NEAR(source.total().mass(), static_cast<double>(source.total().count()) * clumpMass, 1e-9 * source.total().mass());
  EXPECT_EQ(box.particle_count(), 2 * source.total().count());  // two member spheres per clump
  EXPECT_NEAR(box.total_mass(), source.total().mass(), 1e-9 * box.total_mass());
}

TEST(CosimClumps, BadClientTemplateIsRefusedNamingTheField) {
  ScratchDir dir;
  CosimHarness h(dir.path());
  h.hello(1);
  h.declare(1, boxJson(2e-5, 0.02, R"("coupling": {"expected_count": 4})", 0.002));
  h.declare(1, R"({"name": "glass", "material": {}})");
  client::ClumpTemplate pebble("pebble");
  pebble.addSphere({0.0, 0.0, 0.0}, 0.001).addSphere({0.001, 0.0, 0.0}, -0.002);
  h.declare(1, pebble.declaration());
  h.declare(1, R"({"name": "pour", "communication_interval": 0.002, "particle_source": {"material": "glass",
      "clump_template": "pebble", "box": {"lower": {"z": 0.01}, "upper": {"x": 0.02, "y": 0.02, "z": 0.03}},
      "rate_particles_per_s": 100}})");
  const std::vector<v1::Error> errors = h.errors(1);
  ASSERT_EQ(errors.size(), 1u);
  EXPECT_EQ(errors[0].code(), v1::Error::INVALID_DECLARATION);
  EXPECT_EQ(errors[0].component(), "pebble");
  EXPECT_EQ(errors[0].field(), "pebble.clump_template.spheres[1].radius");
}

}  // namespace
}  // namespace demlink::server::test
