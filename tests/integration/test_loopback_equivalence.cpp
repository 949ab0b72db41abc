/// The issue's headline test: three system-model components on three TCP connections to
/// the real server (a box blade pushing into a bed on a prescribed trajectory, a region
/// sensor riding on the blade, a source dropping particles) run many exchanges; the very
/// same declarations driven in-process by the engine-level coupling must end in a
/// byte-identical checkpoint. So the transport, the client library and the host add
/// nothing to the physics: no lost, reordered or re-rounded input on the way.
/// Also checks what each client reads: sensor mass vs count, source mass balance, the
/// wrench on the blade.
#include <gtest/gtest.h>

#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <sstream>
#include <thread>

#include "demlink/core/walls/coupled_motion.hpp"
#include "demlink/server/scene/scene_translator.hpp"
#include "integration_support.hpp"

namespace demlink::integration {
namespace {

constexpr double kDt = 1e-5;                 // [s]
constexpr std::uint64_t kInterval = 2;       // steps per exchange
constexpr std::uint64_t kExchanges = 10000;  // ~3 s in release, ~10 s under ASan
constexpr double kRadius = 0.002;            // every particle [m]
constexpr double kDensity = 2500.0;          // [kg/m^3]
constexpr double kSpeed = 0.1;               // blade push along +x [m/s]
constexpr double kTurnRate = 0.5;            // blade rotation about z [rad/s]
const core::Vec3 kStart(-0.006, 0.0147, 0.006);  // blade centre at t = 0 [m]

/// The blade's prescribed pose and twist at exchange k.
std::pair<core::RigidPose, core::RigidTwist> blade(std::uint64_t k) {
  const double t = static_cast<double>(k * kInterval) * kDt;
  core::RigidPose pose;
  pose.position = kStart + core::Vec3(kSpeed * t, 0.0, 0.0);
  pose.orientation = core::Quat(Eigen::AngleAxisd(kTurnRate * t, core::Vec3::UnitZ()));
  return {pose, core::RigidTwist{core::Vec3(kSpeed, 0.0, 0.0), core::Vec3(0.0, 0.0, kTurnRate)}};
}

client::Vec3 toClient(const core::Vec3& v) { return {v.x(), v.y(), v.z()}; }

/// Runs `body` and turns any exception into a failure message (for client threads).
template <class Body>
void guarded(std::string& failure, Body&& body) {
  try {
    body();
  } catch (const std::exception& error) {
    failure = error.what();
  }
}

TEST(LoopbackCoupling, ThreeClientsOverTcpMatchInProcessCouplingBitForBit) {
  const std::filesystem::path root =
      std::filesystem::temp_directory_path() / ("demlink_e2e_loopback_" + std::to_string(::getpid()));
  std::filesystem::remove_all(root);
  InProcessServer server(hostOptions(root));
  const double interval = static_cast<double>(kInterval) * kDt;  // [s]

  // (a) the blade's connection: box, material, floor, bed and the blade.
  client::Connection connA, connB, connC;
  connect(connA, server.port(), "blade");
  connect(connB, server.port(), "sensor");
  connect(connC, server.port(), "feeder");
  client::Session a(connA), b(connB), c(connC);
  auto& box = a.add<client::SimulationBox>("box");
  box.setTimeStep(kDt).setEndTime(static_cast<double>(kExchanges * kInterval) * kDt);
  box.setInitialGravity({0.0, 0.0, -9.81}).setExpectedCount(7);
  box.setCommunicationInterval(interval);
  a.add<client::Material>("glass").setDensity(kDensity).setYoungsModulus(5e6);
  a.add<client::Plane>("floor").setNormal({0.0, 0.0, 1.0}).setMaterial("glass");
  a.add<Declared>(declarationOf(R"({"name": "bed", "particle_lattice": {"material": "glass", "radius": 0.002,
      "spacing": 0.0042, "origin": {"x": 0.0, "y": 0.0, "z": 0.002}, "counts": {"nx": 6, "ny": 8, "nz": 2}}})"));
  auto& body = a.add<client::RigidBody>("blade");
  body.setBox({0.004, 0.03, 0.012}).setMaterial("glass").setInitialPose(toClient(kStart));
  body.setMotion(v1::RigidBody::PREDICTED);
  body.setCommunicationInterval(interval);
  // (b) a sensor in front of the blade, in the blade's frame.
  auto& sensor = b.add<client::RegionSensor>("scoop");
  sensor.setBox({0.006, 0.0, 0.0}, {0.008, 0.03, 0.012}).attachTo("blade");
  sensor.setCommunicationInterval(interval);
  // (c) a source dropping particles onto the bed.
  auto& source = c.add<client::ParticleSource>("feeder");
  source.setMaterial("glass").setRadius(kRadius).setBox({0.015, 0.015, 0.04}, {0.008, 0.008, 0.004});
  source.setRateParticles(500.0).setVelocity({0.0, 0.0, -0.5}).setSeed(3);
  source.setCommunicationInterval(interval);
  a.declare();
  b.declare();
  c.declare();

  const double particleMass = kDensity * 4.0 / 3.0 * M_PI * kRadius * kRadius * kRadius;  // [kg]
  std::string failA, failB, failC;
  double initialMass = 0.0, finalMass = 0.0, impulseX = 0.0;
  std::uint64_t initialCount = 0, finalCount = 0, bodyAnswers = 0, forcedIntervals = 0;
  std::thread ta([&] {
    guarded(failA, [&] {
      a.waitCompiled();
      initialMass = box.totalMass();
      initialCount = box.particleCount();
      for (std::uint64_t k = 0;; ++k) {
        const auto [pose, twist] = blade(k);
        body.setPose(toClient(pose.position),
                     {pose.orientation.w(), pose.orientation.x(), pose.orientation.y(), pose.orientation.z()});
        body.setVelocity(toClient(twist.linear), toClient(twist.angular));
        if (!a.exchange()) break;
        ++bodyAnswers;
        const client::Vec3 f = body.meanForce();
        impulseX += f.x * interval;
        if (f.x != 0.0 || f.y != 0.0 || f.z != 0.0) ++forcedIntervals;
      }
      finalMass = box.totalMass();
      finalCount = box.particleCount();
    });
  });
  std::uint64_t sensorAnswers = 0, sensorSawParticles = 0, sensorBad = 0;
  std::thread tb([&] {
    guarded(failB, [&] {
      b.waitCompiled();
      while (b.exchange()) {
        ++sensorAnswers;
        const double m = sensor.mass();
        const double expected = static_cast<double>(sensor.count()) * particleMass;
        if (m < 0.0 || std::abs(m - expected) > 1e-9 * std::max(m, particleMass)) ++sensorBad;
        if (sensor.count() > 0) ++sensorSawParticles;
      }
    });
  });
  std::uint64_t insertedSum = 0;
  double insertedMassSum = 0.0;
  client::CountAndMass insertedTotal;
  std::thread tc([&] {
    guarded(failC, [&] {
      c.waitCompiled();
      while (c.exchange()) {
        insertedSum += source.insertedInterval().count;
        insertedMassSum += source.insertedInterval().mass;
      }
      insertedTotal = source.insertedTotal();
    });
  });
  ta.join();
  tb.join();
  tc.join();
  ASSERT_EQ(failA, "");
  ASSERT_EQ(failB, "");
  ASSERT_EQ(failC, "");
  ASSERT_TRUE(a.finished());
  EXPECT_EQ(a.finishedInfo().reason(), "end time reached");
  EXPECT_EQ(a.finishedInfo().step(), kExchanges * kInterval);
  EXPECT_EQ(bodyAnswers, kExchanges);
  EXPECT_EQ(sensorAnswers, kExchanges);

  // What the clients read.
  EXPECT_EQ(sensorBad, 0u) << "sensor mass != count x particle mass (1e-9 relative)";
  EXPECT_GT(sensorSawParticles, 0u) << "the blade never pushed particles into its scoop";
  EXPECT_GT(insertedTotal.count, 0u);
  EXPECT_EQ(insertedSum, insertedTotal.count) << "interval insertions add up to the total";
  EXPECT_NEAR(insertedMassSum, insertedTotal.mass, 1e-9 * insertedTotal.mass);
  EXPECT_NEAR(insertedTotal.mass, static_cast<double>(insertedTotal.count) * particleMass, 1e-9 * insertedTotal.mass);
  EXPECT_EQ(finalCount, initialCount + insertedTotal.count) << "no sink: initial + inserted = final";
  EXPECT_NEAR(finalMass, initialMass + insertedTotal.mass, 1e-9 * finalMass);
  EXPECT_GT(forcedIntervals, 0u) << "the blade never touched a particle";
  EXPECT_LT(impulseX, 0.0) << "particles resist the push: net impulse on the blade along -x";

  // The reference: the same declarations, in the order the server compiled them, driven by
  // core::CoupledMotion with the same samples.
  std::map<std::string, v1::ComponentDeclaration> byName;
  for (client::Session* s : {&a, &b, &c}) {
    for (std::size_t i = 0; i < s->size(); ++i) byName[s->component(i).name()] = s->component(i).declaration();
  }
  std::vector<std::pair<std::uint32_t, std::string>> order;
  for (const v1::CompiledComponent& k : a.compiled().all_components()) order.emplace_back(k.id(), k.name());
  std::sort(order.begin(), order.end());
  ASSERT_EQ(order.size(), byName.size());
  v1::Scene scene;
  for (const auto& [id, name] : order) *scene.add_components() = byName.at(name);
  server::TranslatedScene translated = server::translateScene(scene, {}, server::SceneUse::Cosim);
  core::World& world = translated.world;
  world.initialize();
  ASSERT_EQ(world.meshes().size(), 1u);
  core::CoupledMotion motion(0, core::MotionMode::Predicted);
  for (std::uint64_t k = 0; k < kExchanges; ++k) {
    const auto [pose, twist] = blade(k);
    motion.beginInterval(world.mesh(motion.meshIndex()), world.settings().time_step, pose, twist, kInterval);
    for (std::uint64_t s = 0; s < kInterval; ++s) {
      world.step();
      motion.afterStep(world.meshes()[motion.meshIndex()], world.settings().time_step);
    }
    (void)motion.endInterval(world.mesh(motion.meshIndex()), world.settings().time_step);
  }
  std::ostringstream bytes;
  world.saveCheckpoint(bytes);
  const std::string live = fileBytes(std::filesystem::path(a.finishedInfo().output_directory()) / "checkpoint_final.bin");
  EXPECT_GT(live.size(), 1000u);
  EXPECT_TRUE(live == bytes.str()) << "final checkpoint over TCP differs from the in-process coupling";
  connA.close();
  connB.close();
  connC.close();
  server.stop();
  if (!::testing::Test::HasFailure()) std::filesystem::remove_all(root);
}

}  // namespace
}  // namespace demlink::integration
