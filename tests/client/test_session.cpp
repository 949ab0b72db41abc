/// C++ client library against the scripted fake server: declare/compile/exchange order
/// with two components of different intervals, Error propagation, timeouts, refused
/// connections.
#include <gtest/gtest.h>

#include <chrono>
#include <thread>

#include "demlink/client/client.hpp"
#include "fake_server.hpp"

namespace demlink::client {
namespace {

using demlink::testing::FakeServer;
using demlink::testing::MiniScheduler;

ConnectOptions quickOptions() {
  ConnectOptions options;
  options.client_name = "session-test";
  options.timeout = std::chrono::milliseconds(3000);
  return options;
}

// A body every 2 steps and a sensor every 3 steps on one connection: the client must send
// exactly the due components at each step, return at 2, 3, 4, 6, 8, 9, 10, 12, and show
// each component's outputs for ITS latest interval.
TEST(ClientSession, TwoIntervalsSendExactlyTheDueComponents) {
  std::vector<std::string> log;
  FakeServer server;
  MiniScheduler scheduler;
  scheduler.expectedComponents = 2;
  scheduler.log = &log;
  server.start(scheduler);

  Connection connection;
  const v1::Welcome& welcome = connection.connect("127.0.0.1", server.port(), quickOptions());
  EXPECT_EQ(welcome.server_name(), "fake-server");
  Session session(connection);
  auto& body = session.add<RigidBody>("bucket");
  body.setBox({1.0, 1.0, 0.5}).setMaterial("steel").setInitialPose({0.0, 0.0, 1.0});
  body.setCommunicationInterval(2e-3);
  auto& sensor = session.add<RegionSensor>("fill");
  sensor.setBox({0.0, 0.0, 1.0}, {1.0, 1.0, 0.5}).attachTo("bucket");
  sensor.setCommunicationInterval(3e-3);
  session.declare();
  session.waitCompiled();

  EXPECT_EQ(body.id(), 1U);
  EXPECT_EQ(sensor.id(), 2U);
  EXPECT_EQ(body.intervalSteps(), 2U);
  EXPECT_EQ(sensor.intervalSteps(), 3U);
  EXPECT_EQ(session.report().text(), "fake compile report");
  EXPECT_EQ(body.outputStep(), 0U);  // initial outputs from Compiled
  // The step-0 sensor output has no centre of mass or mean velocity (an empty region's):
  // zeros, never NaN.
  for (const Vec3& v : {sensor.centreOfMass(), sensor.meanVelocity()}) {
    EXPECT_EQ(v.x, 0.0);
    EXPECT_EQ(v.y, 0.0);
    EXPECT_EQ(v.z, 0.0);
  }
  EXPECT_EQ(session.due().size(), 2U);

  std::vector<std::uint64_t> returnedAt;
  while (session.currentStep() < 12) {
    body.setPose({0.0, 0.0, 1.0 + 0.01 * static_cast<double>(session.currentStep())}, {1.0, 0.0, 0.0, 0.0});
    ASSERT_TRUE(session.exchange());
    returnedAt.push_back(session.currentStep());
    const std::uint64_t step = session.currentStep();
    // The body's answer ends at every even step; the sensor's only at multiples of 3.
    EXPECT_EQ(body.outputStep(), step - step % 2);
    EXPECT_EQ(sensor.outputStep(), step - step % 3);
    if (step % 2 == 0) {
      EXPECT_DOUBLE_EQ(body.meanForce().x, static_cast<double>(step));
      // The fake server echoes the pose the client sent for the interval's start.
      EXPECT_NEAR(body.position().z, 1.0 + 0.01 * static_cast<double>(step - 2), 1e-12);
    }
    if (step % 3 == 0) {
      EXPECT_EQ(sensor.count(), step * 10 + 2);
      EXPECT_EQ(sensor.bondsIntact(), step * 100 + 7);
      EXPECT_EQ(sensor.bondsBroken(), step * 100 + 3);
    }
  }
  const std::vector<std::uint64_t> expectedSteps{2, 3, 4, 6, 8, 9, 10, 12};
  EXPECT_EQ(returnedAt, expectedSteps);

  const v1::Finished& finished = session.finish("test done");
  EXPECT_EQ(finished.reason(), "client said Bye");
  EXPECT_TRUE(session.finished());
  EXPECT_FALSE(session.exchange());
  EXPECT_EQ(server.finish(), "");

  // Nothing is sent at step 12: finish() says Bye instead.
  const std::vector<std::string> expectedLog{"0:bucket", "0:fill", "2:bucket", "3:fill", "4:bucket",
                                             "6:bucket", "6:fill", "8:bucket", "9:fill", "10:bucket"};
  EXPECT_EQ(log, expectedLog);
}

// The compiler's refusal reaches the caller as ServerError with code, component and field.
TEST(ClientSession, ServerErrorCarriesCodeComponentAndField) {
  FakeServer server;
  MiniScheduler scheduler;
  scheduler.expectedComponents = 1;
  server.start(scheduler);

  Connection connection;
  connection.connect("127.0.0.1", server.port(), quickOptions());
  Session session(connection);
  session.add<SimulationBox>("box").setTimeStep(1e-3);  // end time missing
  session.declare();
  try {
    session.waitCompiled();
    FAIL() << "waitCompiled() must throw";
  } catch (const ServerError& e) {
    EXPECT_EQ(e.code(), v1::Error::INVALID_DECLARATION);
    EXPECT_EQ(e.component(), "box");
    EXPECT_EQ(e.field(), "simulation_box.end_time");
    EXPECT_TRUE(e.fatal());
    EXPECT_NE(std::string(e.what()).find("INVALID_DECLARATION"), std::string::npos);
  }
  EXPECT_FALSE(connection.isOpen());
  EXPECT_EQ(server.finish(), "");
}

// A server that accepts the declaration and then says nothing: waitCompiled() gives up
// after the client's timeout instead of hanging.
TEST(ClientSession, SilentServerIsATimeout) {
  FakeServer server;
  server.start([](FakeServer& s) {
    auto& peer = s.acceptHello();
    (void)peer.expect("Declare");
    std::this_thread::sleep_for(std::chrono::milliseconds(800));
  });
  Connection connection;
  ConnectOptions options = quickOptions();
  options.timeout = std::chrono::milliseconds(200);
  connection.connect("127.0.0.1", server.port(), options);
  Session session(connection);
  session.add<Material>("gravel").setDatabaseName("gravel");
  session.declare();
  EXPECT_THROW(session.waitCompiled(), TimeoutError);
  EXPECT_FALSE(connection.isOpen());
  EXPECT_EQ(server.finish(), "");
}

// Nobody listens: ConnectionError naming the address.
TEST(ClientSession, RefusedConnectionIsAConnectionError) {
  std::uint16_t port = 0;
  {
    FakeServer closed;  // bind an ephemeral port, then release it
    port = closed.port();
  }
  Connection connection;
  try {
    connection.connect("127.0.0.1", port, quickOptions());
    FAIL() << "connect must throw";
  } catch (const ConnectionError& e) {
    EXPECT_NE(std::string(e.what()).find("127.0.0.1:" + std::to_string(port)), std::string::npos);
  }
}

// Misuse is a StateError, not undefined behaviour: exchange before compile, add after.
TEST(ClientSession, CallsOutOfOrderAreStateErrors) {
  FakeServer server;
  MiniScheduler scheduler;
  scheduler.expectedComponents = 1;
  server.start(scheduler);
  Connection connection;
  connection.connect("127.0.0.1", server.port(), quickOptions());
  Session session(connection);
  auto& view = session.add<ParticleView>("view");
  view.setCommunicationInterval(1e-3);
  EXPECT_THROW(session.exchange(), StateError);
  session.declare();
  session.waitCompiled();
  EXPECT_THROW(session.add<Material>("late"), StateError);
  ASSERT_TRUE(session.exchange());
  EXPECT_EQ(view.positions().size(), 2U);
  EXPECT_FLOAT_EQ(static_cast<float>(view.positions()[1].z), 1.0F);  // step 1 encoded
  session.finish();
  EXPECT_EQ(server.finish(), "");
}

}  // namespace
}  // namespace demlink::client
