/// Declarations completed by DeclarationsDone (no expected count, no quiet period, no end
/// time), and run-time inputs of region sensors, particle sources and sinks, over TCP with
/// the C++ client and the real co-simulation host.
#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <string>

#include "integration_support.hpp"

namespace demlink::integration {
namespace {

constexpr double kDt = 1.0e-5;  // [s]

std::filesystem::path freshRoot(const std::string& name) {
  const std::filesystem::path root =
      std::filesystem::temp_directory_path() / ("demlink_e2e_" + name + "_" + std::to_string(::getpid()));
  std::filesystem::remove_all(root);
  return root;
}

/// A box without expected count or end time, exchanged every `intervalSteps` steps, in zero
/// gravity (declared particles stay where they are).
client::SimulationBox& addBox(client::Session& session, int intervalSteps) {
  auto& box = session.add<client::SimulationBox>("box");
  box.setTimeStep(kDt).setInitialGravity({0.0, 0.0, 0.0});
  box.setRestitutionTolerance(0.1);  // these tests check inputs, not contact accuracy
  box.setCommunicationInterval(intervalSteps * kDt);
  return box;
}

void addParticle(client::Session& session, const std::string& name, const client::Vec3& position) {
  session.add<client::SingleParticle>(name).setMaterial("glass").setPosition(position).setDiameter(0.01);
}

// Two connections, neither gives a count, the quiet period is far away: the compile waits
// for both DeclarationsDone. A repeated identical Declare is ignored, a different one under
// the same name is refused (not fatal). Without an end time the run ends with the Byes.
TEST(DeclarationsDoneOverTcp, CompilesWhenEveryConnectionIsDoneAndEndsWithTheByes) {
  const std::filesystem::path root = freshRoot("done");
  server::CosimOptions options = hostOptions(root);
  options.quiet_period_s = 1000.0;
  options.assembly_timeout_s = 1000.0;
  InProcessServer server(options);

  client::Connection connA, connB;
  connect(connA, server.port(), "a");
  connect(connB, server.port(), "b");  // both joined: "every connection" counts b
  client::Session a(connA);
  addBox(a, 10);
  a.add<client::Material>("glass").setDensity(2500.0).setYoungsModulus(5e6);
  addParticle(a, "ball", {0.0, 0.0, 0.0});
  a.declarationsDone();
  a.declarationsDone();  // idempotent: sends nothing more
  EXPECT_TRUE(a.declarationsDoneSent());
  // A round trip on A after its DeclarationsDone (a refused Declare), so the server has
  // surely handled it before B declares: had it compiled the set then, B would receive
  // Compiled (and OUT_OF_ORDER for its Declare) instead of the refusal below.
  v1::ClientMessage clash;
  *clash.mutable_declare()->mutable_component() = a.find("ball")->declaration();
  clash.mutable_declare()->mutable_component()->mutable_single_particle()->set_diameter(0.02);
  connA.send(clash);
  try {
    (void)connA.receive();
    ADD_FAILURE() << "expected DUPLICATE_NAME for a";
  } catch (const client::ServerError& e) {
    EXPECT_EQ(e.code(), v1::Error::DUPLICATE_NAME);
  }

  client::Session b(connB);
  auto& probe = b.add<client::RegionSensor>("probe");
  probe.setSphere({0.0, 0.0, 0.0}, 0.02).setCommunicationInterval(10 * kDt);
  b.declare();
  v1::ClientMessage repeat;
  *repeat.mutable_declare()->mutable_component() = probe.declaration();
  connB.send(repeat);  // the same declaration again: ignored
  v1::ClientMessage other = repeat;
  other.mutable_declare()->mutable_component()->mutable_region_sensor()->mutable_region()->mutable_sphere()->set_radius(0.5);
  connB.send(other);   // same name, other content: DUPLICATE_NAME, not fatal
  try {
    (void)connB.receive();
    ADD_FAILURE() << "expected DUPLICATE_NAME";
  } catch (const client::ServerError& e) {
    EXPECT_EQ(e.code(), v1::Error::DUPLICATE_NAME);
  }
  b.declarationsDone();

  ASSERT_NO_THROW(a.waitCompiled());
  ASSERT_NO_THROW(b.waitCompiled());
  EXPECT_EQ(a.endStep(), 0u) << "no end time: until every client said Bye";
  EXPECT_EQ(a.compiled().all_components_size(), 4);
  EXPECT_EQ(probe.count(), 1u);

  // One interval with both connections (split form: one thread).
  a.send(*a.find("box"));
  b.send(probe);
  ASSERT_TRUE(a.receive(*a.find("box")));
  ASSERT_TRUE(b.receive(probe));
  EXPECT_EQ(probe.outputStep(), 10u);
  EXPECT_EQ(probe.count(), 1u);

  a.sendBye("tool finished");
  EXPECT_EQ(b.finish("tool finished").step(), 10u);
  EXPECT_EQ(a.waitFinished().reason(), "said Bye");
  server.stop();
  EXPECT_EQ(server.host().simulationsFinished(), 1u);
  if (!::testing::Test::HasFailure()) std::filesystem::remove_all(root);
}

// A source switched off inserts nothing and resumes at its rate (no burst); a region sensor
// moved and enlarged counts the particles of its new place; a sink switched off removes
// nothing where it would, and removes once switched on.
TEST(RuntimeInputsOverTcp, SourceSinkAndSensorChangesTakeEffectAtTheNextPackage) {
  const std::filesystem::path root = freshRoot("runtime_inputs");
  InProcessServer server(hostOptions(root));
  client::Connection connection;
  connect(connection, server.port(), "runtime");
  client::Session s(connection);
  constexpr int kSteps = 10;
  constexpr double kRate = 100000.0;  // [1/s]: 10 particles per interval of 10 steps
  auto& box = addBox(s, kSteps);
  s.add<client::Material>("glass").setDensity(2500.0).setYoungsModulus(5e6);
  addParticle(s, "a", {0.0, 0.0, 0.0});
  addParticle(s, "b", {0.1, 0.0, 0.0});
  addParticle(s, "c", {0.1, 0.05, 0.0});
  auto& probe = s.add<client::RegionSensor>("probe");
  probe.setSphere({0.0, 0.0, 0.0}, 0.02).setCommunicationInterval(kSteps * kDt);
  auto& feed = s.add<client::ParticleSource>("feed");
  feed.setMaterial("glass").setRadius(0.002).setBox({0.0, 0.5, 0.0}, {0.05, 0.05, 0.05}).setRateParticles(kRate);
  feed.setCommunicationInterval(kSteps * kDt);
  auto& drain = s.add<client::ParticleSink>("drain");
  drain.setBox({0.0, -0.5, 0.0}, {0.05, 0.05, 0.05}).setCommunicationInterval(kSteps * kDt);
  s.declarationsDone();
  ASSERT_NO_THROW(s.waitCompiled());

  const auto exchange = [&] { ASSERT_TRUE(s.exchange()); };
  for (int k = 0; k < 3; ++k) exchange();
  // Requested = rate x time: 30 by step 30 (within one particle for the floor of rounding).
  const std::uint64_t onTotal = feed.insertedTotal().count;
  EXPECT_NEAR(static_cast<double>(onTotal), kRate * 30 * kDt, 1.0);
  EXPECT_EQ(probe.count(), 1u);

  // Sent with the packages at step 30: off, moved over b and c, the sink over a but off.
  feed.setEnabled(false);
  probe.moveTo({0.1, 0.025, 0.0});
  probe.resizeSphere(0.04);
  drain.moveTo({0.0, 0.0, 0.0});
  drain.setEnabled(false);
  for (int k = 0; k < 3; ++k) {
    exchange();
    EXPECT_EQ(feed.insertedInterval().count, 0u) << "interval " << k;
    EXPECT_EQ(feed.insertedTotal().count, onTotal);
    EXPECT_EQ(probe.count(), 2u) << "b and c are in the moved sphere, a is not";
    EXPECT_EQ(drain.removedTotal().count, 0u) << "an off sink removes nothing";
  }
  EXPECT_EQ(box.particleCount(), 3u + onTotal);

  // Sent at step 60: both on again.
  feed.setEnabled(true);
  drain.setEnabled(true);
  exchange();
  EXPECT_EQ(drain.removedTotal().count, 1u) << "particle a is removed once the sink is on";
  // The request kept its value while off: the next interval asks for 10 more, not 40.
  EXPECT_NEAR(static_cast<double>(feed.insertedInterval().count), kRate * kSteps * kDt, 1.0);
  EXPECT_EQ(box.particleCount(), 3u - 1u + feed.insertedTotal().count);

  // A rate change applies to the time that follows.
  feed.changeRate(2.0 * kRate);
  exchange();
  EXPECT_NEAR(static_cast<double>(feed.insertedInterval().count), 2.0 * kRate * kSteps * kDt, 1.0);

  EXPECT_EQ(s.finish("done").reason(), "said Bye");
  server.stop();
  if (!::testing::Test::HasFailure()) std::filesystem::remove_all(root);
}

// Bad run-time inputs are INVALID_INPUT naming the field: a box size for a sphere, a mass
// rate for a count-rate source.
TEST(RuntimeInputsOverTcp, InputsOfTheWrongShapeOrUnitAreRefused) {
  const std::filesystem::path root = freshRoot("runtime_refused");
  InProcessServer server(hostOptions(root));
  for (const std::string bad : {"region_sensor_input.size", "particle_source_input.rate_kg_per_s"}) {
    client::Connection connection;
    connect(connection, server.port(), "refused");
    client::Session s(connection);
    addBox(s, 10);
    s.add<client::Material>("glass");
    auto& probe = s.add<client::RegionSensor>("probe");
    probe.setSphere({0.0, 0.0, 0.0}, 0.02).setCommunicationInterval(10 * kDt);
    auto& feed = s.add<client::ParticleSource>("feed");
    feed.setMaterial("glass").setRadius(0.002).setBox({0.0, 0.5, 0.0}, {0.05, 0.05, 0.05}).setRateParticles(1.0);
    feed.setCommunicationInterval(10 * kDt);
    s.declarationsDone();
    ASSERT_NO_THROW(s.waitCompiled());
    if (bad == "region_sensor_input.size") {
      probe.resizeBox({0.1, 0.1, 0.1});
    } else {
      feed.message().clear_rate_particles_per_s();  // the client then asks in kg/s
      feed.message().set_rate_kg_per_s(1.0);
      feed.changeRate(1.0);
    }
    try {
      s.exchange();
      ADD_FAILURE() << bad << ": expected INVALID_INPUT";
    } catch (const client::ServerError& e) {
      EXPECT_EQ(e.code(), v1::Error::INVALID_INPUT) << e.what();
      EXPECT_EQ(e.field(), bad) << e.what();
    }
  }
  server.stop();
  if (!::testing::Test::HasFailure()) std::filesystem::remove_all(root);
}

}  // namespace
}  // namespace demlink::integration
