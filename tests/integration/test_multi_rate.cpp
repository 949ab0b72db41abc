/// Multi-rate exchange over TCP: components with intervals of 1, 3 and 7 steps on two
/// connections. Each client must get its answers exactly at the multiples of its own
/// interval, and the server must have received each component's packages exactly at the
/// multiples of its interval (read back from the host's session record), whatever the
/// interleaving of the two connections.
#include <gtest/gtest.h>
#include <unistd.h>

#include <map>
#include <thread>

#include "integration_support.hpp"

namespace demlink::integration {
namespace {

constexpr double kDt = 1e-5;           // [s]
constexpr std::uint64_t kEndStep = 63;  // three periods of lcm(1, 3, 7)

/// Steps of the answers each component of `session` received, until Finished.
std::map<std::string, std::vector<std::uint64_t>> runAndRecord(client::Session& session, std::string& failure) {
  std::map<std::string, std::vector<std::uint64_t>> steps;
  try {
    session.waitCompiled();
    while (session.exchange()) {
      for (std::size_t i = 0; i < session.size(); ++i) {
        const client::Component& c = session.component(i);
        if (!c.exchanged()) continue;
        std::vector<std::uint64_t>& seen = steps[c.name()];
        if (c.outputStep() > 0 && (seen.empty() || seen.back() != c.outputStep())) seen.push_back(c.outputStep());
      }
    }
  } catch (const std::exception& error) {
    failure = error.what();
  }
  return steps;
}

/// first, first + n, ... while <= last.
std::vector<std::uint64_t> multiples(std::uint64_t first, std::uint64_t n, std::uint64_t last) {
  std::vector<std::uint64_t> out;
  for (std::uint64_t s = first; s <= last; s += n) out.push_back(s);
  return out;
}

TEST(MultiRateOverTcp, AnswersAndInputsAreExactlyAtEachComponentsMultiples) {
  const std::filesystem::path root =
      std::filesystem::temp_directory_path() / ("demlink_e2e_multirate_" + std::to_string(::getpid()));
  std::filesystem::remove_all(root);
  server::CosimOptions options = hostOptions(root);
  options.record_file = root / "session.rec";
  std::filesystem::create_directories(root);
  InProcessServer server(options);

  client::Connection connA, connB;
  connect(connA, server.port(), "fast+slow");
  connect(connB, server.port(), "medium");
  client::Session a(connA), b(connB);
  auto& box = a.add<client::SimulationBox>("box");
  box.setTimeStep(kDt).setEndTime(static_cast<double>(kEndStep) * kDt).setExpectedCount(6);
  box.setCommunicationInterval(1 * kDt);
  a.add<client::Material>("glass").setDensity(2500.0).setYoungsModulus(5e6);
  a.add<client::Plane>("floor").setNormal({0.0, 0.0, 1.0}).setMaterial("glass");
  a.add<Declared>(declarationOf(R"({"name": "bed", "particle_lattice": {"material": "glass", "radius": 0.002,
      "spacing": 0.0042, "origin": {"x": 0.0, "y": 0.0, "z": 0.002}, "counts": {"nx": 3, "ny": 3, "nz": 1}}})"));
  auto& body = a.add<client::RigidBody>("paddle");
  body.setBox({0.004, 0.01, 0.01}).setMaterial("glass").setInitialPose({-0.01, 0.004, 0.006});
  body.setCommunicationInterval(7 * kDt);
  auto& sensor = b.add<client::RegionSensor>("probe");
  sensor.setSphere({0.004, 0.004, 0.002}, 0.01).setCommunicationInterval(3 * kDt);
  a.declare();
  b.declare();

  std::string failA, failB;
  std::map<std::string, std::vector<std::uint64_t>> stepsA, stepsB;
  std::thread ta([&] { stepsA = runAndRecord(a, failA); });
  std::thread tb([&] { stepsB = runAndRecord(b, failB); });
  ta.join();
  tb.join();
  connA.close();
  connB.close();
  server.stop();
  ASSERT_EQ(failA, "");
  ASSERT_EQ(failB, "");
  EXPECT_EQ(a.finishedInfo().reason(), "end time reached");
  EXPECT_EQ(box.intervalSteps(), 1u);
  EXPECT_EQ(body.intervalSteps(), 7u);
  EXPECT_EQ(sensor.intervalSteps(), 3u);
  EXPECT_EQ(stepsA["box"], multiples(1, 1, kEndStep));
  EXPECT_EQ(stepsA["paddle"], multiples(7, 7, kEndStep));
  EXPECT_EQ(stepsB["probe"], multiples(3, 3, kEndStep));

  // The server's side: the steps of the packages it received per component.
  std::map<std::uint32_t, std::vector<std::uint64_t>> received;
  for (const v1::SessionEvent& event : readRecord(options.record_file)) {
    if (event.kind() == v1::SessionEvent::RECEIVED && event.message().has_data()) {
      received[event.message().data().component_id()].push_back(event.message().data().step());
    }
  }
  EXPECT_EQ(received[box.id()], multiples(0, 1, kEndStep - 1));
  EXPECT_EQ(received[body.id()], multiples(0, 7, kEndStep - 1));
  EXPECT_EQ(received[sensor.id()], multiples(0, 3, kEndStep - 1));
  EXPECT_EQ(received.size(), 3u) << "only the three exchanged components send packages";
  if (!::testing::Test::HasFailure()) std::filesystem::remove_all(root);
}

}  // namespace
}  // namespace demlink::integration
