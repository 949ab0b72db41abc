/// Faults over TCP with the real host: a client that hangs up mid-interval, a client that
/// stops answering, NaN in a rigid body's input, garbage bytes on a stray socket. In every
/// case the partner learns why (Error with the documented code) and that the simulation
/// ended (Finished), the outputs are flushed, and the server goes on serving: a fresh
/// simulation with new clients completes afterwards. The surviving partner is a raw
/// protocol client (test_client.hpp) so the test sees every message, including the
/// Finished that follows a fatal Error.
#include <gtest/gtest.h>
#include <unistd.h>

#include <atomic>
#include <cmath>
#include <filesystem>
#include <functional>
#include <limits>
#include <thread>

#include "integration_support.hpp"
#include "test_client.hpp"

namespace demlink::integration {
namespace {

using server::test::TestClient;

constexpr double kDt = 1e-5;  // [s]

/// Scratch output root for one test, removed when it passes.
class Root {
 public:
  explicit Root(const std::string& name)
      : path_(std::filesystem::temp_directory_path() / ("demlink_e2e_" + name + "_" + std::to_string(::getpid()))) {
    std::filesystem::remove_all(path_);
  }
  ~Root() {
    if (!::testing::Test::HasFailure()) std::filesystem::remove_all(path_);
  }
  Root(const Root&) = delete;
  Root& operator=(const Root&) = delete;
  [[nodiscard]] const std::filesystem::path& path() const { return path_; }

 private:
  std::filesystem::path path_;
};

/// The raw partner: box exchanged every step, a material, a floor and a small bed.
/// `expected` counts every component of the simulation (the partner's included).
std::vector<std::string> partnerScene(int expected, double endTime, const std::string& coupling = "") {
  return {R"({"name": "box", "communication_interval": 1e-5, "simulation_box": {"time_step": 1e-5, "end_time": )" +
              std::to_string(endTime) + R"(, "coupling": {"expected_count": )" + std::to_string(expected) +
              (coupling.empty() ? "" : ", " + coupling) + "}}}",
          R"({"name": "glass", "material": {"density": 2500, "youngs_modulus": 5e6}})",
          R"({"name": "floor", "plane": {"normal": {"z": 1}, "material": "glass"}})",
          R"({"name": "bed", "particle_lattice": {"material": "glass", "radius": 0.002, "spacing": 0.0042,
              "origin": {"x": 0.0, "y": 0.0, "z": 0.002}, "counts": {"nx": 3, "ny": 3, "nz": 1}}})"};
}

/// What the raw partner saw after its Compiled: the last answered step, every Error, Finished.
struct PartnerLog {
  std::uint64_t last_step = 0;
  std::vector<v1::Error> errors;
  std::optional<v1::Finished> finished;
  std::string problem;  ///< a protocol surprise or a timeout
};

/// Hello + Declare of `components` on a raw client; returns Compiled (nullopt: problem).
std::optional<v1::Compiled> rawDeclare(TestClient& client, const std::vector<std::string>& components) {
  const std::optional<v1::ServerMessage> welcome = client.hello("raw partner");
  if (!welcome || !welcome->has_welcome()) return std::nullopt;
  for (const std::string& json : components) {
    v1::ClientMessage declare;
    *declare.mutable_declare()->mutable_component() = declarationOf(json);
    client.send(declare);
  }
  const std::optional<v1::ServerMessage> compiled = client.receive();
  if (!compiled || !compiled->has_compiled()) return std::nullopt;
  return compiled->compiled();
}

/// Exchanges the box (id 1, every step) until Finished; every wait bounded by kTimeout.
PartnerLog rawExchangeUntilFinished(TestClient& client, std::uint32_t box) {
  PartnerLog log;
  bool awaiting = false;
  for (int messages = 0; messages < 1000000; ++messages) {
    if (!awaiting) {
      v1::ClientMessage package;
      package.mutable_data()->set_component_id(box);
      package.mutable_data()->set_step(log.last_step);
      client.send(package);
      awaiting = true;
    }
    const std::optional<v1::ServerMessage> m = client.receive();
    if (!m) {
      log.problem = "no message within the timeout (or the connection closed) at step " + std::to_string(log.last_step);
      return log;
    }
    if (m->has_data()) {
      log.last_step = m->data().step();
      awaiting = false;
    } else if (m->has_error()) {
      log.errors.push_back(m->error());
    } else if (m->has_finished()) {
      log.finished = m->finished();
      return log;
    }
  }
  log.problem = "no Finished";
  return log;
}

std::uint32_t idOf(const v1::Compiled& compiled, const std::string& name) {
  for (const v1::CompiledComponent& c : compiled.all_components()) {
    if (c.name() == name) return c.id();
  }
  return 0;
}

/// A new simulation with a new client completes on the same server ("the server goes on").
void expectFreshSimulationCompletes(std::uint16_t port, std::uint32_t simulationNumber) {
  client::Connection connection;
  connect(connection, port, "fresh");
  EXPECT_EQ(connection.welcome().simulation_number(), simulationNumber);
  client::Session session(connection);
  auto& box = session.add<client::SimulationBox>("box");
  box.setTimeStep(kDt).setEndTime(20 * kDt).setExpectedCount(2).setCommunicationInterval(5 * kDt);
  session.add<client::Material>("steel").setDensity(7800.0).setYoungsModulus(2e8);
  session.declare();
  session.waitCompiled();
  int answers = 0;
  while (session.exchange()) ++answers;
  EXPECT_EQ(answers, 4);
  EXPECT_EQ(session.finishedInfo().reason(), "end time reached");
  EXPECT_EQ(session.finishedInfo().step(), 20u);
  connection.close();
}

/// A sensor on its own connection (the partner's bed), every 2 steps.
void addProbe(client::Session& session) {
  session.add<client::RegionSensor>("probe").setSphere({0.004, 0.004, 0.002}, 0.01).setCommunicationInterval(2 * kDt);
}

TEST(FaultsOverTcp, PeerHangingUpMidIntervalEndsTheSimulationForThePartner) {
  Root root("hangup");
  InProcessServer server(hostOptions(root.path()));
  TestClient partner(server.port());
  client::Connection connection;
  connect(connection, server.port(), "quitter");
  client::Session quitter(connection);
  addProbe(quitter);
  quitter.declare();  // before the partner's box, so the compile waits for nobody
  PartnerLog log;
  std::thread partnerThread([&] {
    const std::optional<v1::Compiled> compiled = rawDeclare(partner, partnerScene(5, 1.0));
    if (!compiled) {
      log.problem = "no Compiled";
      return;
    }
    log = rawExchangeUntilFinished(partner, idOf(*compiled, "box"));
  });
  std::string failure;
  try {
    quitter.waitCompiled();
    for (int k = 0; k < 5 && failure.empty(); ++k) {
      if (!quitter.exchange()) failure = "the simulation finished early";
    }
    quitter.send(quitter.component(0));  // the package of the next interval is in flight...
    connection.close();                  // ...and the client hangs up before its answer
  } catch (const std::exception& error) {
    failure = error.what();
  }
  partnerThread.join();
  ASSERT_EQ(failure, "");
  ASSERT_EQ(log.problem, "");
  ASSERT_EQ(log.errors.size(), 1u);
  EXPECT_EQ(log.errors[0].code(), v1::Error::PEER_DISCONNECTED) << log.errors[0].DebugString();
  EXPECT_NE(log.errors[0].message().find("quitter"), std::string::npos) << log.errors[0].message();
  ASSERT_TRUE(log.finished.has_value());
  EXPECT_GE(log.last_step, 10u);
  EXPECT_LE(log.last_step, 12u) << "the world waits at the quitter's next due step";
  const std::filesystem::path out = log.finished->output_directory();
  EXPECT_TRUE(std::filesystem::exists(out / "checkpoint_final.bin"));
  ASSERT_TRUE(std::filesystem::exists(out / "run_log.csv"));
  EXPECT_NE(fileBytes(out / "run_log.csv").find("finish_reason"), std::string::npos);
  EXPECT_TRUE(partner.waitForClose()) << "Finished closes the partner's connection";
  expectFreshSimulationCompletes(server.port(), 2);
}

TEST(FaultsOverTcp, SilentClientTimesOutAndTheServerGoesOn) {
  Root root("silent");
  InProcessServer server(hostOptions(root.path()));
  TestClient partner(server.port());
  client::Connection connection;
  connect(connection, server.port(), "sleeper");
  client::Session sleeper(connection);
  addProbe(sleeper);
  sleeper.declare();
  PartnerLog log;
  std::thread partnerThread([&] {
    const std::optional<v1::Compiled> compiled = rawDeclare(partner, partnerScene(5, 1.0, R"("client_timeout": 0.5)"));
    if (!compiled) {
      log.problem = "no Compiled";
      return;
    }
    log = rawExchangeUntilFinished(partner, idOf(*compiled, "box"));
  });
  v1::Error::Code sleeperCode = v1::Error::CODE_UNSPECIFIED;
  const auto begin = std::chrono::steady_clock::now();
  try {
    sleeper.waitCompiled();
    (void)connection.receive();  // never sends its package: the next message is the verdict
  } catch (const client::ServerError& error) {
    sleeperCode = error.code();
  } catch (const std::exception& error) {
    ADD_FAILURE() << error.what();
  }
  partnerThread.join();
  const double waited = std::chrono::duration<double>(std::chrono::steady_clock::now() - begin).count();  // [s]
  EXPECT_EQ(sleeperCode, v1::Error::TIMEOUT);
  EXPECT_GE(waited, 0.5) << "not before the declared client_timeout";
  ASSERT_EQ(log.problem, "");
  ASSERT_EQ(log.errors.size(), 1u);
  EXPECT_EQ(log.errors[0].code(), v1::Error::TIMEOUT) << log.errors[0].DebugString();
  EXPECT_NE(log.errors[0].message().find("probe"), std::string::npos) << log.errors[0].message();
  ASSERT_TRUE(log.finished.has_value());
  EXPECT_EQ(log.last_step, 0u) << "the world waited at step 0 for the sleeper's first package";
  EXPECT_TRUE(std::filesystem::exists(std::filesystem::path(log.finished->output_directory()) / "checkpoint_final.bin"));
  connection.close();
  expectFreshSimulationCompletes(server.port(), 2);
}

TEST(FaultsOverTcp, NanInRigidBodyInputIsInvalidInputNamingTheField) {
  Root root("nan");
  InProcessServer server(hostOptions(root.path()));
  client::Connection connection;
  connect(connection, server.port(), "nan body");
  client::Session session(connection);
  session.add<client::SimulationBox>("box").setTimeStep(kDt).setEndTime(1.0).setExpectedCount(3);
  session.add<client::Material>("glass").setDensity(2500.0).setYoungsModulus(5e6);
  auto& body = session.add<client::RigidBody>("blade");
  body.setBox({0.01, 0.01, 0.01}).setMaterial("glass").setCommunicationInterval(2 * kDt);
  session.declare();
  session.waitCompiled();
  ASSERT_TRUE(session.exchange());
  body.setPose({0.0, std::numeric_limits<double>::quiet_NaN(), 0.0}, {});
  try {
    (void)session.exchange();
    ADD_FAILURE() << "a NaN position was accepted";
  } catch (const client::ServerError& error) {
    EXPECT_EQ(error.code(), v1::Error::INVALID_INPUT);
    EXPECT_EQ(error.field(), "rigid_body_input.position.y");
    EXPECT_TRUE(error.fatal());
  }
  // The Finished that follows the fatal error still reaches the library client: it says
  // where the flushed results are.
  ASSERT_TRUE(session.finished());
  EXPECT_TRUE(std::filesystem::exists(std::filesystem::path(session.finishedInfo().output_directory()) /
                                      "checkpoint_final.bin"));
  EXPECT_FALSE(connection.isOpen());
  connection.close();
  expectFreshSimulationCompletes(server.port(), 2);
}

/// Runs box + bed for `steps` (box every step); calls `midway` once at step `at` before
/// going on. Returns the final checkpoint's bytes.
std::string runSmallSimulation(std::uint16_t port, std::uint64_t steps, std::uint64_t at,
                               const std::function<void()>& midway) {
  client::Connection connection;
  connect(connection, port, "steady");
  client::Session session(connection);
  for (const std::string& json : partnerScene(4, static_cast<double>(steps) * kDt)) {
    session.add<Declared>(declarationOf(json));
  }
  session.declare();
  session.waitCompiled();
  while (session.exchange()) {
    if (session.currentStep() == at) midway();
  }
  EXPECT_EQ(session.finishedInfo().reason(), "end time reached");
  connection.close();
  return fileBytes(std::filesystem::path(session.finishedInfo().output_directory()) / "checkpoint_final.bin");
}

TEST(FaultsOverTcp, GarbageOnAStraySocketDoesNotDisturbARunningSimulation) {
  Root root("garbage");
  InProcessServer server(hostOptions(root.path()));
  int stray = 0;
  const std::string disturbed = runSmallSimulation(server.port(), 400, 100, [&] {
    TestClient varint(server.port());  // a length prefix that never ends
    varint.sendRaw(std::string(12, '\xff'));
    const std::optional<v1::ServerMessage> answer = varint.receive();
    EXPECT_TRUE(answer && answer->has_error() && answer->error().code() == v1::Error::BAD_FRAME)
        << (answer ? answer->DebugString() : "nothing");
    EXPECT_TRUE(varint.waitForClose());
    TestClient junk(server.port());  // a well-framed payload that is no ClientMessage
    junk.sendRaw(std::string("\x05\xff\xfe\xfd\xfc\xfb", 6));
    const std::optional<v1::ServerMessage> junkAnswer = junk.receive();
    EXPECT_TRUE(junkAnswer && junkAnswer->has_error()) << (junkAnswer ? junkAnswer->DebugString() : "nothing");
    EXPECT_TRUE(junk.waitForClose());
    ++stray;
  });
  EXPECT_EQ(stray, 1);
  const std::string calm = runSmallSimulation(server.port(), 400, 100, [] {});
  EXPECT_GT(disturbed.size(), 100u);
  EXPECT_TRUE(disturbed == calm) << "the stray bytes changed the running simulation";
}

}  // namespace
}  // namespace demlink::integration
