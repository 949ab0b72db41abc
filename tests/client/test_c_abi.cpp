/// The C ABI against the scripted fake server: the generic package layout both ways, the
/// typed helpers' receive-then-send order, status codes and messages, and the Modelica
/// call sequence program.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include "demlink/demlink_c.h"
#include "fake_server_process.hpp"

namespace {

using demlink::testing::FakeServerProcess;
using demlink::testing::readLines;

constexpr int kInvalidDeclaration = 8;  // demlink.v1.Error.INVALID_DECLARATION

std::string logFile(const char* name) { return ::testing::TempDir() + "demlink_c_abi_" + name + ".log"; }

bool contains(const std::vector<std::string>& lines, const std::string& prefix, const std::string& text) {
  for (const auto& l : lines) {
    if (l.rfind(prefix, 0) == 0 && l.find(text) != std::string::npos) return true;
  }
  return false;
}

struct ClientGuard {
  dl_client* client = dl_client_create();
  ~ClientGuard() { dl_client_destroy(client); }
};
/// Bye, Finished, the fake server's exit; then its log.
std::vector<std::string> finishAndReadLog(dl_client* client, FakeServerProcess& server, const std::string& log) {
  EXPECT_EQ(dl_finish(client, "done"), DL_OK);
  EXPECT_EQ(dl_wait_finished(client), DL_OK) << dl_last_error(client);
  EXPECT_EQ(server.wait(), 0);
  return readLines(log);
}

struct PackageGuard {
  dl_package* package = dl_package_create();
  ~PackageGuard() { dl_package_destroy(package); }
};

std::vector<long long> ints(dl_package* p) {
  int n = 0;
  EXPECT_EQ(dl_get_ints(p, nullptr, 0, &n), DL_OK);
  std::vector<long long> out(static_cast<std::size_t>(n));
  EXPECT_EQ(dl_get_ints(p, out.data(), n, &n), DL_OK);
  return out;
}
std::vector<double> reals(dl_package* p) {
  int n = 0;
  EXPECT_EQ(dl_get_reals(p, nullptr, 0, &n), DL_OK);
  std::vector<double> out(static_cast<std::size_t>(n));
  EXPECT_EQ(dl_get_reals(p, out.data(), n, &n), DL_OK);
  return out;
}
/// Sends one generic package: dl_set_data, then dl_send_package.
void sendGeneric(dl_client* client, dl_package* package, const std::vector<long long>& ints,
                 const std::vector<double>& reals, const std::vector<const char*>& texts) {
  ASSERT_EQ(dl_set_data(package, ints.data(), static_cast<int>(ints.size()), reals.data(),
                        static_cast<int>(reals.size()), texts.data(), static_cast<int>(texts.size())),
            DL_OK);
  ASSERT_EQ(dl_send_package(client, package), DL_OK) << dl_last_error(client);
}
std::vector<std::string> strings(dl_package* p) {
  int n = 0;
  EXPECT_EQ(dl_get_strings(p, nullptr, 0, &n), DL_OK);
  std::vector<const char*> raw(static_cast<std::size_t>(n));
  EXPECT_EQ(dl_get_strings(p, raw.data(), n, &n), DL_OK);
  return {raw.begin(), raw.end()};
}

// Declare a rigid body and a region sensor with generic packages, send inputs, receive
// outputs: every documented index must land in the right protobuf field and back.
TEST(ClientCAbi, GenericPackagesFollowTheDocumentedLayout) {
  const std::string log = logFile("generic");
  FakeServerProcess server(1, 2, log);
  ASSERT_NE(server.port(), 0);

  ClientGuard c;
  PackageGuard pkg;
  ASSERT_EQ(dl_connect_to_host(c.client, "127.0.0.1", server.port(), "generic", nullptr), DL_OK) << dl_last_error(c.client);

  const char* bodyStrings[] = {"rigid_body", "bucket", "steel", ""};
  const long long bodyInts[] = {1, 2};  // box geometry, LAGGED
  const double bodyReals[] = {0.002, 0.1, 0.2, 0.3, 1.0, 2.0, 3.0, 1.0, 0.0, 0.0, 0.0, 0.8, 0.6, 0.4};
  ASSERT_EQ(dl_set_data(pkg.package, bodyInts, 2, bodyReals, 14, bodyStrings, 4), DL_OK);
  ASSERT_EQ(dl_send_package(c.client, pkg.package), DL_OK) << dl_last_error(c.client);

  const char* sensorStrings[] = {"region_sensor", "fill", "bucket"};
  const long long sensorInts[] = {1};  // sphere
  const double sensorReals[] = {0.001, 0.0, 0.0, 0.25, 0.4};
  ASSERT_EQ(dl_set_data(pkg.package, sensorInts, 1, sensorReals, 5, sensorStrings, 3), DL_OK);
  ASSERT_EQ(dl_send_package(c.client, pkg.package), DL_OK) << dl_last_error(c.client);

  // Initial outputs without waiting, once compiled.
  ASSERT_EQ(dl_wait_compiled(c.client), DL_OK) << dl_last_error(c.client);
  long long steps = 0;
  ASSERT_EQ(dl_component_interval_steps(c.client, 0, &steps), DL_OK);
  EXPECT_EQ(steps, 2);
  ASSERT_EQ(dl_get_outputs(c.client, 1, pkg.package), DL_OK);
  EXPECT_EQ(strings(pkg.package), (std::vector<std::string>{"region_sensor", "fill"}));
  // handle, step 0, count = 0*10 + id 2, bonds intact and broken = 0*100 + 7, + 3
  EXPECT_EQ(ints(pkg.package), (std::vector<long long>{1, 0, 2, 7, 3}));
  // Sent without centre of mass and mean velocity (as an empty region is): zeros, not NaN.
  EXPECT_EQ(reals(pkg.package), (std::vector<double>{0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0}));

  // Inputs at step 0: the body's 13 reals, the sensor's empty package.
  const long long bodyHandle[] = {0};
  const double input[] = {0.5, -0.5, 2.0, 0.0, 1.0, 0.0, 0.0, 0.1, 0.2, 0.3, 0.0, 0.0, 1.5};
  ASSERT_EQ(dl_set_data(pkg.package, bodyHandle, 1, input, 13, nullptr, 0), DL_OK);
  ASSERT_EQ(dl_send_package(c.client, pkg.package), DL_OK) << dl_last_error(c.client);
  const long long sensorHandle[] = {1};
  ASSERT_EQ(dl_set_data(pkg.package, sensorHandle, 1, nullptr, 0, nullptr, 0), DL_OK);
  ASSERT_EQ(dl_send_package(c.client, pkg.package), DL_OK) << dl_last_error(c.client);

  // The sensor (1 step) answers first, at step 1; the body at step 2 needs the sensor's
  // step-1 package, so the generic caller sends it before receiving again.
  ASSERT_EQ(dl_recv_package(c.client, pkg.package), DL_OK) << dl_last_error(c.client);
  EXPECT_EQ(strings(pkg.package), (std::vector<std::string>{"region_sensor", "fill"}));
  EXPECT_EQ(ints(pkg.package), (std::vector<long long>{1, 1, 12, 107, 103}));
  EXPECT_EQ(reals(pkg.package), (std::vector<double>{0.25, 1.0, 0.0, 1.0, 0.0, -1.0, 0.0}));
  ASSERT_EQ(dl_set_data(pkg.package, sensorHandle, 1, nullptr, 0, nullptr, 0), DL_OK);
  ASSERT_EQ(dl_send_package(c.client, pkg.package), DL_OK) << dl_last_error(c.client);

  ASSERT_EQ(dl_recv_package(c.client, pkg.package), DL_OK) << dl_last_error(c.client);
  EXPECT_EQ(strings(pkg.package), (std::vector<std::string>{"rigid_body", "bucket"}));
  EXPECT_EQ(ints(pkg.package), (std::vector<long long>{0, 2}));
  const std::vector<double> expected{2.0, 1.0, 2.0,  3.0, 4.0, 5.0,   6.0, 7.0, 8.0, 9.0,
                                     10.0, 2.5, 0.5, -0.5, 2.0, 0.0, 1.0, 0.0, 0.0};
  EXPECT_EQ(reals(pkg.package), expected);

  // A too small output array: the prefix is copied and the status says so.
  double two[2] = {0.0, 0.0};
  int count = 0;
  EXPECT_EQ(dl_get_reals(pkg.package, two, 2, &count), DL_ERR_CAPACITY);
  EXPECT_EQ(count, 19);
  EXPECT_EQ(two[1], 1.0);

  EXPECT_EQ(dl_finish(c.client, "done"), DL_OK);
  EXPECT_EQ(dl_wait_finished(c.client), DL_OK) << dl_last_error(c.client);
  EXPECT_STREQ(dl_finished_reason(c.client), "client said Bye");
  ASSERT_EQ(server.wait(), 0);

  // What the server received, field by field (protobuf's text form of each declaration).
  const auto lines = readLines(log);
  EXPECT_TRUE(contains(lines, "DECL bucket", "communication_interval: 0.002"));
  EXPECT_TRUE(contains(lines, "DECL bucket", "material: \"steel\""));
  EXPECT_TRUE(contains(lines, "DECL bucket", "motion: LAGGED"));
  EXPECT_TRUE(contains(lines, "DECL bucket", "reference_point { x: 0.1 y: 0.2 z: 0.3 }"));
  EXPECT_TRUE(contains(lines, "DECL bucket", "position { x: 1 y: 2 z: 3 }"));
  EXPECT_TRUE(contains(lines, "DECL bucket", "box { size { x: 0.8 y: 0.6 z: 0.4 } }"));
  EXPECT_TRUE(contains(lines, "DECL fill", "sphere { centre { z: 0.25 } radius: 0.4 }"));
  EXPECT_TRUE(contains(lines, "DECL fill", "attached_to: \"bucket\""));
  EXPECT_TRUE(contains(lines, "DECL fill", "sample_interval: 0.001"));  // filled from the interval
  EXPECT_TRUE(contains(lines, "0:bucket", ""));
}

// Typed helpers in the receive-first order: each exchange returns the interval that just
// ended (initial outputs at the first call) and then sends; two components with intervals 1
// and 2 steps.
TEST(ClientCAbi, TypedHelpersReceiveThenSend) {
  const std::string logPath = logFile("typed");
  FakeServerProcess server(1, 2, logPath);
  ASSERT_NE(server.port(), 0);

  ClientGuard c;
  ASSERT_EQ(dl_set_exchange_order(c.client, DL_ORDER_RECEIVE_FIRST), DL_OK);
  ASSERT_EQ(dl_connect_to_host(c.client, "127.0.0.1", server.port(), "typed", ""), DL_OK) << dl_last_error(c.client);
  int body = -1;
  int sensor = -1;
  const double size[3] = {1.0, 1.0, 1.0};
  const double pose[7] = {0.0, 0.0, 1.0, 1.0, 0.0, 0.0, 0.0};
  ASSERT_EQ(dl_declare_rigid_body_box(c.client, "body", 0.001, size, "steel", pose, 0, &body), DL_OK);
  const double centre[3] = {0.0, 0.0, 0.0};
  ASSERT_EQ(dl_declare_region_sensor_box(c.client, "sensor", 0.002, centre, size, "body", &sensor), DL_OK);
  EXPECT_EQ(body, 0);
  EXPECT_EQ(sensor, 1);

  for (int k = 0; k < 6; ++k) {
    double p[7] = {0.1 * k, 0.0, 1.0, 1.0, 0.0, 0.0, 0.0};
    const double twist[6] = {0.1, 0.0, 0.0, 0.0, 0.0, 0.0};
    double wrench[12] = {};
    ASSERT_EQ(dl_rigid_body_exchange(c.client, body, p, twist, wrench), DL_OK) << dl_last_error(c.client);
    EXPECT_EQ(wrench[0], static_cast<double>(k));  // mean force x encodes the step
    EXPECT_EQ(wrench[11], k + 0.5);
    if (k % 2 == 0) {
      int count = -1;
      double out[7];
      int bonds[2] = {-1, -1};
      ASSERT_EQ(dl_region_sensor_read_bonds(c.client, sensor, &count, out, bonds), DL_OK) << dl_last_error(c.client);
      EXPECT_EQ(count, k * 10 + 2);
      EXPECT_EQ(out[0], 0.25 * k);
      EXPECT_EQ(bonds[0], k * 100 + 7);
      EXPECT_EQ(bonds[1], k * 100 + 3);
    }
  }
  EXPECT_EQ(dl_finish(c.client, nullptr), DL_OK);
  ASSERT_EQ(server.wait(), 0);
  std::vector<std::string> log;
  for (const auto& line : readLines(logPath)) {
    if (line.rfind("DECL", 0) != 0) log.push_back(line);
  }
  const std::vector<std::string> expectedLog{"0:body", "0:sensor", "1:body", "2:body", "2:sensor", "3:body",
                                             "4:body", "4:sensor", "5:body"};
  EXPECT_EQ(log, expectedLog);
}

// The split send-first order (two calls per sample): the first call sends the inputs at
// t_k and leaves the outputs as they were, the second returns the interval [t_k, t_k+1];
// the fake server's outputs encode the step the answered interval ended at. The sensor's
// interval is two steps: its answer arrives while the body steps on, so its second call
// keeps the outputs and its next sample's first call receives the interval that ended then.
TEST(ClientCAbi, TypedHelpersSendFirstSplitReturnTheIntervalThatBegins) {
  const std::string logPath = logFile("split");
  FakeServerProcess server(1, 2, logPath);
  ASSERT_NE(server.port(), 0);
  ClientGuard c;
  ASSERT_EQ(dl_set_exchange_order(c.client, DL_ORDER_SEND_FIRST_SPLIT), DL_OK);
  ASSERT_EQ(dl_connect_to_host(c.client, "127.0.0.1", server.port(), "split", ""), DL_OK) << dl_last_error(c.client);
  int body = -1;
  int sensor = -1;
  const double size[3] = {1.0, 1.0, 1.0};
  const double pose[7] = {0.0, 0.0, 1.0, 1.0, 0.0, 0.0, 0.0};
  ASSERT_EQ(dl_declare_rigid_body_box(c.client, "body", 0.001, size, "steel", pose, 0, &body), DL_OK);
  const double centre[3] = {0.0, 0.0, 0.0};
  ASSERT_EQ(dl_declare_region_sensor_box(c.client, "sensor", 0.002, centre, size, "body", &sensor), DL_OK);
  for (int k = 0; k < 6; ++k) {
    const double p[7] = {0.1 * k, 0.0, 1.0, 1.0, 0.0, 0.0, 0.0};
    const double twist[6] = {0.1, 0.0, 0.0, 0.0, 0.0, 0.0};
    double wrench[12] = {};
    int count = -1;
    double out[7] = {};
    ASSERT_EQ(dl_rigid_body_exchange(c.client, body, p, twist, wrench), DL_OK) << dl_last_error(c.client);
    if (k > 0) {
      EXPECT_EQ(wrench[0], static_cast<double>(k));  // unchanged: the previous sample's [k-1, k]
    }
    if (k % 2 == 0) {
      ASSERT_EQ(dl_region_sensor_read(c.client, sensor, &count, out), DL_OK) << dl_last_error(c.client);
      EXPECT_EQ(count, k * 10 + 2);  // [k - 2, k], received before sending (k = 0: the initial outputs)
    }
    ASSERT_EQ(dl_rigid_body_exchange(c.client, body, p, twist, wrench), DL_OK) << dl_last_error(c.client);
    EXPECT_EQ(wrench[0], static_cast<double>(k + 1));  // [k, k + 1]
    if (k % 2 == 0) {
      ASSERT_EQ(dl_region_sensor_read(c.client, sensor, &count, out), DL_OK) << dl_last_error(c.client);
      EXPECT_EQ(count, k * 10 + 2);  // [k, k + 2] ends after the world's next step: not yet
    }
  }
  EXPECT_EQ(dl_finish(c.client, nullptr), DL_OK);
  ASSERT_EQ(server.wait(), 0);
}

// The default one-call send-first order returns [t_k, t_k+1] from the same call.
TEST(ClientCAbi, TypedHelpersSendFirstByDefault) {
  const std::string logPath = logFile("send_first");
  FakeServerProcess server(1, 1, logPath);
  ASSERT_NE(server.port(), 0);
  ClientGuard c;
  ASSERT_EQ(dl_connect_to_host(c.client, "127.0.0.1", server.port(), "send_first", ""), DL_OK)
      << dl_last_error(c.client);
  int body = -1;
  const double size[3] = {1.0, 1.0, 1.0};
  const double pose[7] = {0.0, 0.0, 1.0, 1.0, 0.0, 0.0, 0.0};
  ASSERT_EQ(dl_declare_rigid_body_box(c.client, "body", 0.001, size, "steel", pose, 0, &body), DL_OK);
  const double twist[6] = {0.1, 0.0, 0.0, 0.0, 0.0, 0.0};
  for (int k = 0; k < 4; ++k) {
    double wrench[12] = {};
    ASSERT_EQ(dl_rigid_body_exchange(c.client, body, pose, twist, wrench), DL_OK) << dl_last_error(c.client);
    EXPECT_EQ(wrench[0], static_cast<double>(k + 1));  // [k, k + 1]
  }
  EXPECT_EQ(dl_set_exchange_order(c.client, 7), DL_ERR_ARGUMENT);
  EXPECT_EQ(dl_finish(c.client, nullptr), DL_OK);
  ASSERT_EQ(server.wait(), 0);
}

// A one-call send-first exchange would wait for its own answer, which needs the client's
// other component due at the same step: refused, naming the orders that handle it.
TEST(ClientCAbi, SendFirstRefusesASecondComponentDueAtTheSameStep) {
  const std::string logPath = logFile("send_first_two");
  FakeServerProcess server(1, 2, logPath);
  ASSERT_NE(server.port(), 0);
  ClientGuard c;
  ASSERT_EQ(dl_connect_to_host(c.client, "127.0.0.1", server.port(), "two", ""), DL_OK) << dl_last_error(c.client);
  int body = -1;
  int sensor = -1;
  const double size[3] = {1.0, 1.0, 1.0};
  const double pose[7] = {0.0, 0.0, 1.0, 1.0, 0.0, 0.0, 0.0};
  ASSERT_EQ(dl_declare_rigid_body_box(c.client, "body", 0.001, size, "steel", pose, 0, &body), DL_OK);
  const double centre[3] = {0.0, 0.0, 0.0};
  ASSERT_EQ(dl_declare_region_sensor_box(c.client, "sensor", 0.002, centre, size, "body", &sensor), DL_OK);
  const double twist[6] = {0.1, 0.0, 0.0, 0.0, 0.0, 0.0};
  double wrench[12] = {};
  EXPECT_EQ(dl_rigid_body_exchange(c.client, body, pose, twist, wrench), DL_ERR_STATE);
  EXPECT_NE(std::string(dl_last_error(c.client)).find("DL_ORDER_SEND_FIRST_SPLIT"), std::string::npos)
      << dl_last_error(c.client);
  int count = -1;
  double out[7] = {};
  EXPECT_EQ(dl_region_sensor_read(c.client, sensor, &count, out), DL_ERR_STATE);
  EXPECT_EQ(dl_finish(c.client, nullptr), DL_OK);
  (void)server.wait();
}

TEST(ClientCAbi, StatusCodesAndMessages) {
  // Refused connection.
  // A port nobody listens on: a finished fake server's.
  std::uint16_t port = 0;
  {
    FakeServerProcess closed(1, 1, logFile("closed"));
    port = closed.port();
    (void)closed.wait(std::chrono::milliseconds(0));  // killed: the port is free again
  }
  ClientGuard refused;
  EXPECT_EQ(dl_connect_to_host(refused.client, "127.0.0.1", port, "x", nullptr), DL_ERR_CONNECT);
  EXPECT_NE(std::string(dl_last_error(refused.client)).find("cannot connect"), std::string::npos);
  // Calls in the wrong state or with wrong handles.
  int handle = -1;
  EXPECT_EQ(dl_declare_particle_view(refused.client, "v", 0.001, 10, &handle), DL_ERR_STATE);
  EXPECT_NE(std::string(dl_last_error(refused.client)).find("not connected"), std::string::npos);
  PackageGuard pkg;
  EXPECT_EQ(dl_send_package(pkg.package, pkg.package), DL_ERR_ARGUMENT);  // a package is no client
  EXPECT_EQ(dl_send_package(refused.client, nullptr), DL_ERR_ARGUMENT);
  EXPECT_EQ(dl_set_data(refused.client, nullptr, 0, nullptr, 0, nullptr, 0), DL_ERR_ARGUMENT);
  EXPECT_EQ(dl_connect_to_host(refused.client, "127.0.0.1", 70000, "x", nullptr), DL_ERR_ARGUMENT);
  EXPECT_STREQ(dl_last_error(nullptr), "invalid client handle");

  // The server's Error: code, field and message reach the caller.
  FakeServerProcess server(1, 1, logFile("errors"));
  ClientGuard c;
  ASSERT_EQ(dl_set_timeout(c.client, 3.0), DL_OK);
  ASSERT_EQ(dl_connect_to_host(c.client, "127.0.0.1", server.port(), "errors", ""), DL_OK);
  int box = -1;
  ASSERT_EQ(dl_declare_simulation_box(c.client, "box", 0.0, 1e-3, 0.0, nullptr, nullptr, nullptr, 1, &box), DL_OK);
  EXPECT_EQ(dl_wait_compiled(c.client), DL_ERR_SERVER);
  EXPECT_EQ(dl_last_server_error_code(c.client), kInvalidDeclaration);
  EXPECT_STREQ(dl_last_server_error_field(c.client), "simulation_box.end_time");
  EXPECT_STREQ(dl_last_server_error_component(c.client), "box");
  EXPECT_NE(std::string(dl_last_error(c.client)).find("end_time must be > 0"), std::string::npos);
  EXPECT_EQ(server.wait(), 0);

  // An unknown kind in a generic declaration names the kinds that exist (the layout is
  // checked before anything is sent, so no server is needed).
  const char* bad[] = {"tracker", "t"};
  ASSERT_EQ(dl_set_data(pkg.package, nullptr, 0, nullptr, 0, bad, 2), DL_OK);
  EXPECT_EQ(dl_send_package(refused.client, pkg.package), DL_ERR_ARGUMENT);
  EXPECT_NE(std::string(dl_last_error(refused.client)).find("'tracker' has no generic layout"), std::string::npos);
}

// The optional simulation_box entries of the generic layout (VTK interval, restitution
// tolerance, threads, contact law, integrator, fidelity, impact speed, coarse graining,
// watchdog overlap limit, expected names, the frame motion input) reach the declaration;
// omitted ones stay unset.
TEST(ClientCAbi, GenericSimulationBoxCarriesOutputThreadsAndNames) {
  const std::string log = logFile("generic_box");
  FakeServerProcess server(1, 1, log);
  ASSERT_NE(server.port(), 0);
  ClientGuard c;
  PackageGuard pkg;
  ASSERT_EQ(dl_connect_to_host(c.client, "127.0.0.1", server.port(), "site", nullptr), DL_OK) << dl_last_error(c.client);
  const double nan = std::nan("");
  const char* boxStrings[] = {"simulation_box", "site", "site", "truck_body"};
  const long long boxInts[] = {0, 2, 2, 1, 3};
  const double boxReals[] = {0.001, 2e-4, 1.0, 0.0, 0.0, -9.81, -1.0, -2.0, -3.0, 4.0, 5.0, 6.0, 0.25, 0.05, 3.5, 2.0,
                             0.7, 0.5};
  ASSERT_EQ(dl_set_data(pkg.package, boxInts, 5, boxReals, 18, boxStrings, 4), DL_OK);
  ASSERT_EQ(dl_send_package(c.client, pkg.package), DL_OK) << dl_last_error(c.client);
  ASSERT_EQ(dl_wait_compiled(c.client), DL_OK) << dl_last_error(c.client);
  // The frame input: gravity unchanged (NaN), then a_f, Omega, alpha, origin.
  const long long handle[] = {0};
  const double frame[] = {nan, nan, nan, 1.5, 0.0, 0.0, 0.0, 0.0, 0.5, 0.0, 0.0, 0.1, 5.5, -3.5, 0.0};
  ASSERT_EQ(dl_set_data(pkg.package, handle, 1, frame, 15, nullptr, 0), DL_OK);
  ASSERT_EQ(dl_send_package(c.client, pkg.package), DL_OK) << dl_last_error(c.client);
  ASSERT_EQ(dl_recv_package(c.client, pkg.package), DL_OK) << dl_last_error(c.client);
  const auto lines = finishAndReadLog(c.client, server, log);
  EXPECT_TRUE(contains(lines, "DECL site", "output { vtk_interval: 0.25 }"));
  EXPECT_TRUE(contains(lines, "DECL site", "threads: 2"));
  EXPECT_TRUE(contains(lines, "DECL site", "restitution_tolerance: 0.05"));
  EXPECT_TRUE(contains(lines, "DECL site", "contact_model: LINEAR_SPRING_DASHPOT integrator: VELOCITY_VERLET"));
  EXPECT_TRUE(contains(lines, "DECL site", "max_impact_velocity: 3.5"));
  EXPECT_TRUE(contains(lines, "DECL site", "fidelity: VALIDATION coarse_graining: 2"));
  EXPECT_TRUE(contains(lines, "DECL site", "watchdog { max_overlap_fraction: 0.7 }"));
  EXPECT_TRUE(contains(lines, "DECL site", "modulus_scale: 0.5"));
  EXPECT_TRUE(contains(lines, "DECL site", "expected_names: \"site\" expected_names: \"truck_body\""));
  EXPECT_TRUE(contains(lines, "DECL site", "bounds { lower { x: -1 y: -2 z: -3 } upper { x: 4 y: 5 z: 6 } }"));

  // A negative VTK interval is refused by name before anything is sent.
  const double badReals[] = {0.001, 2e-4, 1.0, 0.0, 0.0, -9.81, -1.0, -2.0, -3.0, 4.0, 5.0, 6.0, -0.25};
  ClientGuard other;
  ASSERT_EQ(dl_set_data(pkg.package, boxInts, 2, badReals, 13, boxStrings, 4), DL_OK);
  EXPECT_EQ(dl_send_package(other.client, pkg.package), DL_ERR_ARGUMENT);
  EXPECT_NE(std::string(dl_last_error(other.client)).find("reals[12]"), std::string::npos);
  // An unknown contact law or fidelity is refused by its index.
  const long long badContact[] = {0, 2, 3};
  ASSERT_EQ(dl_set_data(pkg.package, badContact, 3, boxReals, 14, boxStrings, 4), DL_OK);
  EXPECT_EQ(dl_send_package(other.client, pkg.package), DL_ERR_ARGUMENT);
  EXPECT_NE(std::string(dl_last_error(other.client)).find("ints[2..3]: contactModel"), std::string::npos);
  const long long badFidelity[] = {0, 2, 0, 0, 4};
  ASSERT_EQ(dl_set_data(pkg.package, badFidelity, 5, boxReals, 14, boxStrings, 4), DL_OK);
  EXPECT_EQ(dl_send_package(other.client, pkg.package), DL_ERR_ARGUMENT);
  EXPECT_NE(std::string(dl_last_error(other.client)).find("ints[4] (fidelity)"), std::string::npos);
}

// The typed declarations of the shapes and files the first typed calls left to the generic
// layout: a CAD part (its STL's bytes sent), particles from a server file, oriented and
// attached sensor and sink boxes, a flow rectangle, a sink sphere.
TEST(ClientCAbi, TypedDeclarationsOfPartsFilesAndEveryRegionShape) {
  const std::string log = logFile("typed_shapes");
  const std::string stl = ::testing::TempDir() + "demlink_c_abi_part.stl";
  {
    std::FILE* f = std::fopen(stl.c_str(), "wb");
    ASSERT_NE(f, nullptr);
    std::fputs("solid part\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 0\nvertex 0 1 0\n"
               "endloop\nendfacet\nendsolid part\n", f);
    std::fclose(f);
  }
  FakeServerProcess server(1, 6, log);
  ASSERT_NE(server.port(), 0);
  ClientGuard c;
  ASSERT_EQ(dl_connect_to_host(c.client, "127.0.0.1", server.port(), "shapes", nullptr), DL_OK) << dl_last_error(c.client);
  const double centre[3] = {0.5, -0.5, 1.0};
  const double size[3] = {0.2, 0.3, 0.4};
  const double turned[4] = {0.0, 0.0, 0.0, 1.0};  // w x y z: half a turn about z
  const double normal[3] = {0.0, 0.0, 1.0};
  const double axis[3] = {0.0, 1.0, 0.0};
  const double pose[7] = {1.0, 2.0, 3.0, 1.0, 0.0, 0.0, 0.0};
  int handle = -1;
  ASSERT_EQ(dl_declare_cad_part(c.client, "part", 0.01, stl.c_str(), "steel", nullptr, pose, 2, &handle), DL_OK)
      << dl_last_error(c.client);
  EXPECT_EQ(handle, 0);
  ASSERT_EQ(dl_declare_particle_system(c.client, "bed", "bed.checkpoint", 1, &handle), DL_OK) << dl_last_error(c.client);
  ASSERT_EQ(dl_declare_region_sensor_box_oriented(c.client, "fill", 0.01, centre, size, turned, "part", &handle), DL_OK)
      << dl_last_error(c.client);
  ASSERT_EQ(dl_declare_flow_sensor_rectangle(c.client, "gate", 0.01, centre, normal, 0.6, 0.2, axis, nullptr, &handle),
            DL_OK)
      << dl_last_error(c.client);
  ASSERT_EQ(dl_declare_particle_sink_box_oriented(c.client, "drain", 0.01, centre, size, turned, "part", &handle),
            DL_OK)
      << dl_last_error(c.client);
  ASSERT_EQ(dl_declare_particle_sink_sphere(c.client, "hole", 0.01, centre, 0.25, "", &handle), DL_OK)
      << dl_last_error(c.client);
  EXPECT_EQ(handle, 5);
  // A CAD part whose file is missing is refused on the client, naming the path.
  EXPECT_EQ(dl_declare_cad_part(c.client, "ghost", 0.01, "/nonexistent.stl", "steel", nullptr, nullptr, 0, &handle),
            DL_ERR_ARGUMENT);
  EXPECT_NE(std::string(dl_last_error(c.client)).find("/nonexistent.stl"), std::string::npos);
  ASSERT_EQ(dl_wait_compiled(c.client), DL_OK) << dl_last_error(c.client);
  const auto lines = finishAndReadLog(c.client, server, log);
  EXPECT_TRUE(contains(lines, "DECL part", "stl_data: \"solid part\\n"));
  EXPECT_TRUE(contains(lines, "DECL part", "motion: LAGGED"));
  EXPECT_TRUE(contains(lines, "DECL bed", "bed.checkpoint"));
  EXPECT_TRUE(contains(lines, "DECL fill", "box { centre { x: 0.5 y: -0.5 z: 1 } orientation { z: 1 } size { x: 0.2 y: 0.3 z: 0.4 } }"));
  EXPECT_TRUE(contains(lines, "DECL fill", "attached_to: \"part\""));
  EXPECT_TRUE(contains(lines, "DECL gate", "normal { z: 1 } length_axis { y: 1 } length: 0.6 width: 0.2"));
  EXPECT_TRUE(contains(lines, "DECL drain", "box { centre { x: 0.5 y: -0.5 z: 1 } orientation { z: 1 } size { x: 0.2 y: 0.3 z: 0.4 } }"));
  EXPECT_TRUE(contains(lines, "DECL drain", "attached_to: \"part\""));
  EXPECT_TRUE(contains(lines, "DECL hole", "sphere { centre { x: 0.5 y: -0.5 z: 1 } radius: 0.25 }"));
  std::remove(stl.c_str());
}

// The source's generic layout as the Modelica ParticleSource fills it: a disc with discrete
// sizes (pairs from reals[20]) and a box with a truncated normal (mean, std at [18], [19]).
TEST(ClientCAbi, GenericClumpTemplateAndTheSourcesAndPitsThatUseIt) {
  const std::string log = logFile("generic_clump");
  FakeServerProcess server(1, 3, log);
  ASSERT_NE(server.port(), 0);
  ClientGuard c;
  PackageGuard pkg;
  ASSERT_EQ(dl_connect_to_host(c.client, "127.0.0.1", server.port(), "feed", nullptr), DL_OK) << dl_last_error(c.client);
  const double nan = std::nan("");
  const char* clumpStrings[] = {"clump_template", "pebble"};
  const double clumpReals[] = {0.0, -0.002, 0.0, 0.0, 0.003, 0.002, 0.0, 0.0, 0.0025};
  ASSERT_EQ(dl_set_data(pkg.package, nullptr, 0, clumpReals, 9, clumpStrings, 2), DL_OK);
  ASSERT_EQ(dl_send_package(c.client, pkg.package), DL_OK) << dl_last_error(c.client);
  const char* sourceStrings[] = {"particle_source", "chute", "glass", "", "pebble"};
  const long long sourceInts[] = {6, 0, 1};
  const double sourceReals[] = {0.0, 0.0, 0.0, 1.0, 0.1, 0.1, 0.1, 0.003, 0.005, 100.0, nan};
  ASSERT_EQ(dl_set_data(pkg.package, sourceInts, 3, sourceReals, 11, sourceStrings, 5), DL_OK);
  ASSERT_EQ(dl_send_package(c.client, pkg.package), DL_OK) << dl_last_error(c.client);
  const char* pitStrings[] = {"pit_generator", "pit", "glass", "", "pebble"};
  const long long pitInts[] = {7};
  const double pitReals[] = {0.0, -1.0, -1.0, -1.0, 1.0, 1.0, 0.0, 0.003, 0.005, 0.0};
  ASSERT_EQ(dl_set_data(pkg.package, pitInts, 1, pitReals, 10, pitStrings, 5), DL_OK);
  ASSERT_EQ(dl_send_package(c.client, pkg.package), DL_OK) << dl_last_error(c.client);
  ASSERT_EQ(dl_wait_compiled(c.client), DL_OK) << dl_last_error(c.client);
  EXPECT_EQ(dl_finish(c.client, "done"), DL_OK);
  ASSERT_EQ(server.wait(), 0);

  const auto lines = readLines(log);
  EXPECT_TRUE(contains(lines, "DECL pebble", "spheres { offset { x: -0.002 } radius: 0.003 }"));
  EXPECT_TRUE(contains(lines, "DECL pebble", "spheres { offset { x: 0.002 } radius: 0.0025 }"));
  EXPECT_TRUE(contains(lines, "DECL chute", "clump_template: \"pebble\""));
  EXPECT_TRUE(contains(lines, "DECL pit", "clump_template: \"pebble\""));

  // A sphere's four numbers are refused incomplete, by name.
  ClientGuard other;
  ASSERT_EQ(dl_set_data(pkg.package, nullptr, 0, clumpReals, 8, clumpStrings, 2), DL_OK);
  EXPECT_EQ(dl_send_package(other.client, pkg.package), DL_ERR_ARGUMENT);
  EXPECT_NE(std::string(dl_last_error(other.client)).find("clump_template: reals[1..]"), std::string::npos)
      << dl_last_error(other.client);
}

TEST(ClientCAbi, GenericParticleSourceCarriesDiscRegionAndSizeDistributions) {
  const std::string log = logFile("generic_source");
  FakeServerProcess server(1, 2, log);
  ASSERT_NE(server.port(), 0);
  ClientGuard c;
  PackageGuard pkg;
  ASSERT_EQ(dl_connect_to_host(c.client, "127.0.0.1", server.port(), "feed", nullptr), DL_OK) << dl_last_error(c.client);
  const double nan = std::nan("");
  const char* discStrings[] = {"particle_source", "hopper", "glass", ""};
  const long long discInts[] = {5, 1, 4};  // seed, disc, discrete
  const double discReals[] = {0.0, 0.0, 0.0, 0.5, 0.0, 0.0, 1.0, 0.003, 0.005, 100.0, nan, 0.0,   0.0, 0.0,
                              0.0, nan, 0.1, 0.02, 1.0, 1.0, 0.003, 1.0, 0.005, 3.0};
  ASSERT_EQ(dl_set_data(pkg.package, discInts, 3, discReals, 24, discStrings, 4), DL_OK);
  ASSERT_EQ(dl_send_package(c.client, pkg.package), DL_OK) << dl_last_error(c.client);
  const char* boxStrings[] = {"particle_source", "chute", "glass", ""};
  const long long boxInts[] = {6, 0, 3};  // seed, box, normal
  const double boxReals[] = {0.0, 0.0, 0.0, 1.0, 0.1, 0.1, 0.1, 0.003, 0.005, nan, 2.0, 0.0, 0.0, 0.0,
                             0.0, nan, 0.2, 0.0, 0.004, 0.001};
  ASSERT_EQ(dl_set_data(pkg.package, boxInts, 3, boxReals, 20, boxStrings, 4), DL_OK);
  ASSERT_EQ(dl_send_package(c.client, pkg.package), DL_OK) << dl_last_error(c.client);
  ASSERT_EQ(dl_wait_compiled(c.client), DL_OK) << dl_last_error(c.client);
  EXPECT_EQ(dl_finish(c.client, "done"), DL_OK);  // declared only (interval 0): nothing to exchange
  ASSERT_EQ(server.wait(), 0);

  const auto lines = readLines(log);
  EXPECT_TRUE(contains(lines, "DECL hopper", "disc { centre { z: 0.5 } normal { z: 1 } radius: 0.1 thickness: 0.02 }"));
  EXPECT_TRUE(contains(lines, "DECL hopper", "discrete { radii: 0.003 radii: 0.005 weights: 1 weights: 3 }"));
  EXPECT_TRUE(contains(lines, "DECL hopper", "rate_particles_per_s: 100"));
  EXPECT_TRUE(contains(lines, "DECL chute", "box { centre { z: 1 } half_extents { x: 0.1 y: 0.1 z: 0.1 }"));
  EXPECT_TRUE(contains(lines, "DECL chute", "normal { mean: 0.004 std: 0.001 r_min: 0.003 r_max: 0.005 }"));
  EXPECT_TRUE(contains(lines, "DECL chute", "rate_kg_per_s: 2"));

  // Discrete sizes must come in pairs; an unknown size kind is refused by name.
  ClientGuard other;
  ASSERT_EQ(dl_set_data(pkg.package, discInts, 3, discReals, 23, discStrings, 4), DL_OK);
  EXPECT_EQ(dl_send_package(other.client, pkg.package), DL_ERR_ARGUMENT);
  const long long badKind[] = {5, 1, 7};
  ASSERT_EQ(dl_set_data(pkg.package, badKind, 3, discReals, 24, discStrings, 4), DL_OK);
  EXPECT_EQ(dl_send_package(other.client, pkg.package), DL_ERR_ARGUMENT);
  EXPECT_NE(std::string(dl_last_error(other.client)).find("ints[2]"), std::string::npos) << dl_last_error(other.client);
}

// Moving regions in the generic layout: reals[11..13] (sink, region sensor) and [12..14]
// (flow sensor) are a constant velocity, as the Modelica models fill them; NaN there, or a
// NaN orientation or length axis, means "not given".
TEST(ClientCAbi, GenericRegionsCarryAConstantVelocity) {
  const std::string log = logFile("generic_velocity");
  FakeServerProcess server(1, 3, log);
  ASSERT_NE(server.port(), 0);
  ClientGuard c;
  PackageGuard pkg;
  ASSERT_EQ(dl_connect_to_host(c.client, "127.0.0.1", server.port(), "moving", nullptr), DL_OK) << dl_last_error(c.client);
  const double nan = std::nan("");
  // interval, centre, radius and two unused, orientation (none), velocity
  sendGeneric(c.client, pkg.package, {1}, {0.001, 0.1, 0.2, 0.3, 0.05, 0.0, 0.0, nan, nan, nan, nan, 0.5, 0.0, -0.25},
              {"region_sensor", "scan", ""});
  sendGeneric(c.client, pkg.package, {0}, {0.0, 0.0, 0.0, 1.0, 0.2, 0.2, 0.2, 1.0, 0.0, 0.0, 0.0, nan, nan, nan},
              {"particle_sink", "still", ""});
  // interval, centre, normal, radius and an unused value, length axis (none), velocity
  sendGeneric(c.client, pkg.package, {1}, {0.0, 0.0, 0.0, 0.5, 0.0, 0.0, 1.0, 0.3, 0.0, nan, nan, nan, 0.0, 0.0, 2.0},
              {"flow_sensor", "lift", ""});
  ASSERT_EQ(dl_wait_compiled(c.client), DL_OK) << dl_last_error(c.client);
  EXPECT_EQ(dl_finish(c.client, "done"), DL_OK);
  ASSERT_EQ(server.wait(), 0);

  const auto lines = readLines(log);
  EXPECT_TRUE(contains(lines, "DECL scan", "velocity { x: 0.5 z: -0.25 }"));
  EXPECT_FALSE(contains(lines, "DECL scan", "orientation"));
  EXPECT_TRUE(contains(lines, "DECL still", "particle_sink { region { box {"));
  EXPECT_FALSE(contains(lines, "DECL still", "velocity"));
  EXPECT_TRUE(contains(lines, "DECL lift", "velocity { z: 2 }"));
  EXPECT_FALSE(contains(lines, "DECL lift", "length_axis"));
}

// Parallel-bond regions in the generic layout: ints[1] selects the region as the Modelica
// ParallelBonds fills it (19 reals, the attached body at strings[2], the materials after it);
// without ints[1] reals[9..14] stay a box and the materials start at strings[2].
TEST(ClientCAbi, GenericParallelBondsCarryEveryRegionKind) {
  const std::string log = logFile("generic_bonds");
  FakeServerProcess server(1, 4, log);
  ASSERT_NE(server.port(), 0);
  ClientGuard c;
  PackageGuard pkg;
  ASSERT_EQ(dl_connect_to_host(c.client, "127.0.0.1", server.port(), "bonds", nullptr), DL_OK) << dl_last_error(c.client);
  const double nan = std::nan("");
  // interval, kn, ks, tensile, shear, gap, multiplier, create time, fraction, centre, size | radius, orientation
  const std::vector<double> sphereReals{0.0, 1e9, 2e9, 1e5, 2e5, 1e-3, nan, 0.0, nan, 0.1, 0.2, 0.3,
                                        0.05, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0};
  sendGeneric(c.client, pkg.package, {4, DL_REGION_SPHERE}, sphereReals,
              {"parallel_bonds", "lump", "bucket", "gravel", "sand"});
  const std::vector<double> boxReals{0.0, 1e9, 2e9, 1e5, 2e5, 1e-3, nan, 0.0, nan, 0.1, 0.2, 0.3,
                                     0.4, 0.5, 0.6, 0.0, 0.0, 0.0, 1.0};
  sendGeneric(c.client, pkg.package, {0, DL_REGION_BOX}, boxReals, {"parallel_bonds", "slab", "", ""});
  sendGeneric(c.client, pkg.package, {0, DL_REGION_EVERYWHERE}, boxReals, {"parallel_bonds", "all", "", "gravel"});
  sendGeneric(c.client, pkg.package, {0}, {boxReals.begin(), boxReals.begin() + 15}, {"parallel_bonds", "legacy", "gravel"});
  ASSERT_EQ(dl_wait_compiled(c.client), DL_OK) << dl_last_error(c.client);
  EXPECT_EQ(dl_finish(c.client, "done"), DL_OK);
  ASSERT_EQ(server.wait(), 0);

  const auto lines = readLines(log);
  EXPECT_TRUE(contains(lines, "DECL lump",
                       "region { sphere { centre { x: 0.1 y: 0.2 z: 0.3 } radius: 0.05 } attached_to: \"bucket\" } "
                       "materials: \"gravel\" materials: \"sand\""));
  EXPECT_TRUE(contains(lines, "DECL slab",
                       "region { box { centre { x: 0.1 y: 0.2 z: 0.3 } orientation { z: 1 } size { x: 0.4 y: 0.5 z: 0.6 } "
                       "} }"));
  EXPECT_TRUE(contains(lines, "DECL all", "parallel_bonds { materials: \"gravel\""));
  EXPECT_FALSE(contains(lines, "DECL all", "region"));
  EXPECT_TRUE(contains(lines, "DECL legacy",
                       "region { box { centre { x: 0.1 y: 0.2 z: 0.3 } orientation { w: 1 } size { x: 0.4 y: 0.5 z: 0.6 } } } "
                       "materials: \"gravel\""));

  // An unknown region kind, and a body to ride on without a region, are refused by name.
  ClientGuard other;
  const long long badKind[] = {0, 3};
  const char* boxStrings[] = {"parallel_bonds", "slab", "", ""};
  ASSERT_EQ(dl_set_data(pkg.package, badKind, 2, boxReals.data(), 19, boxStrings, 4), DL_OK);
  EXPECT_EQ(dl_send_package(other.client, pkg.package), DL_ERR_ARGUMENT);
  EXPECT_NE(std::string(dl_last_error(other.client)).find("ints[1] (region) = 3"), std::string::npos)
      << dl_last_error(other.client);
  const long long everywhereInts[] = {0, DL_REGION_EVERYWHERE};
  const char* sphereStrings[] = {"parallel_bonds", "lump", "bucket", "gravel", "sand"};
  ASSERT_EQ(dl_set_data(pkg.package, everywhereInts, 2, boxReals.data(), 19, sphereStrings, 5), DL_OK);
  EXPECT_EQ(dl_send_package(other.client, pkg.package), DL_ERR_ARGUMENT);
  EXPECT_NE(std::string(dl_last_error(other.client)).find("strings[2] (attached body) = \"bucket\""),
            std::string::npos)
      << dl_last_error(other.client);
  // The typed call refuses the same, naming the argument.
  const double properties[8] = {1e9, 2e9, 1e5, 2e5, 1e-3, nan, 0.0, nan};
  const double centre[3] = {0.0, 0.0, 0.0};
  int handle = -1;
  EXPECT_EQ(dl_declare_parallel_bonds_region(other.client, "odd", properties, 7, centre, nullptr, nullptr, 0.1, "",
                                             "", 0, &handle),
            DL_ERR_ARGUMENT);
  EXPECT_NE(std::string(dl_last_error(other.client)).find("regionKind = 7"), std::string::npos)
      << dl_last_error(other.client);
  EXPECT_EQ(dl_declare_parallel_bonds_region(other.client, "odd", properties, DL_REGION_EVERYWHERE, nullptr, nullptr,
                                             nullptr, 0.0, "bucket", "", 0, &handle),
            DL_ERR_ARGUMENT);
  EXPECT_NE(std::string(dl_last_error(other.client)).find("attachedTo = \"bucket\""), std::string::npos)
      << dl_last_error(other.client);
}

// The C program that makes the Modelica package's calls, against the fake scheduler with
// one connection per component.
TEST(ClientCAbi, ModelicaSequenceProgramRunsAgainstTheFakeServer) {
  const std::string logPath = logFile("modelica");
  FakeServerProcess server(5, 5, logPath);
  ASSERT_NE(server.port(), 0);
  const std::string command = std::string("timeout 20 ") + DEMLINK_MODELICA_SEQUENCE_EXE + " 127.0.0.1 " +
                              std::to_string(server.port()) + " 12 fake";
  EXPECT_EQ(std::system(command.c_str()), 0) << command;
  ASSERT_EQ(server.wait(), 0);
  std::size_t packages = 0;
  for (const auto& line : readLines(logPath)) packages += line.rfind("DECL", 0) == 0 ? 0U : 1U;
  // 12 samples of box, bucket and feeder (interval 2 steps) and 6 of the sensor (4 steps).
  EXPECT_EQ(packages, 12U * 3U + 6U);
}

}  // namespace
