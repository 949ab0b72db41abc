/// TcpServer limits against hostile or broken peers over loopback: the small frame cap and
/// the timeout before Hello, the cap on connections awaiting Hello, and the bounded output
/// queue of a client that stops reading. Each ends the peer with a named Error, keeps the
/// server serving others and, where memory is the point, bounds the process's peak RSS.
#include <gtest/gtest.h>

#include <fstream>
#include <memory>
#include <string>
#include <thread>
#include <vector>

#include "fake_session_handler.hpp"

namespace demlink::server::test {
namespace {

/// Peak resident memory of this process [bytes] (VmHWM).
std::size_t peakResidentBytes() {
  std::ifstream status("/proc/self/status");
  std::string line;
  while (std::getline(status, line)) {
    if (line.starts_with("VmHWM:")) return std::stoull(line.substr(6)) * 1024u;
  }
  return 0;
}

/// Restarts the peak at the current resident size (Linux: "5" > clear_refs).
void resetPeakResident() { std::ofstream("/proc/self/clear_refs") << "5"; }

TEST(TcpServerLimits, LargeFramesAreRefusedBeforeHelloAndAcceptedAfter) {
  RunningServer server;
  {
    TestClient stranger(server.port());
    stranger.sendRaw("\x80\x80\x40");  // 2^20 bytes announced before Hello
    expectRefused(stranger, v1::Error::FRAME_TOO_LARGE,
                  "frame of 1048576 bytes exceeds the cap of 65536 bytes allowed before Hello", "frame");
  }
  TestClient client(server.port());
  ASSERT_TRUE(client.hello().has_value());
  v1::ClientMessage large;
  large.mutable_data()->set_component_id(1);
  large.mutable_data()->mutable_particle_view()->mutable_positions()->Resize(1u << 18, 2.0f);  // 1 MiB
  client.send(large);
  const std::optional<v1::ServerMessage> echo = client.receive(10000ms);
  ASSERT_TRUE(echo.has_value() && echo->has_data()) << "after Hello the full cap applies";
  EXPECT_EQ(echo->data().particle_view().positions_size(), 1 << 18);
}

/// Ten strangers announce 60 MiB frames and send 16 MiB of them: nothing is buffered
/// (without the cap before Hello the server would hold 160 MiB).
TEST(TcpServerLimits, UnauthenticatedLargeFramesDoNotGrowTheServer) {
  RunningServer server;
  resetPeakResident();
  const std::size_t before = peakResidentBytes();
  const std::string payload(16u << 20, 'x');
  std::vector<std::thread> strangers;
  for (int k = 0; k < 10; ++k) {
    strangers.emplace_back([&server, &payload] {
      asio::io_context io;
      asio::ip::tcp::socket socket(io);
      socket.connect(asio::ip::tcp::endpoint(asio::ip::make_address("127.0.0.1"), server.port()));
      asio::error_code error;
      asio::write(socket, asio::buffer(std::string("\x80\x80\x80\x1e", 4)), error);  // 60 MiB announced
      asio::write(socket, asio::buffer(payload), error);  // refused or drained: an error is fine
    });
  }
  for (std::thread& stranger : strangers) stranger.join();
  const std::size_t growth = peakResidentBytes() - before;
  EXPECT_LT(growth, 64u << 20) << "peak RSS grew by " << growth << " bytes";
  expectStillServing(server);
}

TEST(TcpServerLimits, ConnectionsWithoutHelloAreClosedAfterTheHelloTimeout) {
  TcpServerOptions options;
  options.hello_timeout = 300ms;
  RunningServer server(options);
  TestClient silent(server.port());
  TestClient slow(server.port());
  slow.sendRaw("\x1b\x0a");  // the first two bytes of a Hello frame, then nothing
  TestClient welcomed(server.port());
  ASSERT_TRUE(welcomed.hello().has_value());
  expectRefused(silent, v1::Error::TIMEOUT, "no Hello within 300 ms", "hello");
  expectRefused(slow, v1::Error::TIMEOUT, "no Hello within 300 ms", "hello");
  EXPECT_EQ(server.handler().count("disconnected"), 0u) << "the welcomed connection stays";
  v1::ClientMessage package;
  package.mutable_data()->set_component_id(3);
  welcomed.send(package);
  const std::optional<v1::ServerMessage> echo = welcomed.receive();
  ASSERT_TRUE(echo.has_value() && echo->has_data());
  expectStillServing(server);
}

TEST(TcpServerLimits, ConnectionsAwaitingHelloAreCapped) {
  TcpServerOptions options;
  options.max_unwelcomed = 3;
  RunningServer server(options);
  std::vector<std::unique_ptr<TestClient>> waiting;
  for (int k = 0; k < 3; ++k) waiting.push_back(std::make_unique<TestClient>(server.port()));
  TestClient extra(server.port());
  expectRefused(extra, v1::Error::SERVER_BUSY, "too many connections awaiting Hello (3)", "connection");
  ASSERT_TRUE(waiting[0]->hello().has_value()) << "the waiting ones are still served";
  expectStillServing(server);  // one slot is free again
}

/// A client sends 300 packages whose answers are 1 MiB each and reads nothing: the server
/// stops taking its input once 2 MiB wait for it, serves others meanwhile, and delivers
/// every answer in order once the client reads again.
TEST(TcpServerLimits, AClientThatStopsReadingIsHeldBackWithBoundedMemory) {
  TcpServerOptions options;
  options.max_queued_bytes = 2u << 20;
  RunningServer server(options);
  TestClient reader(server.port());
  ASSERT_TRUE(reader.hello().has_value());
  resetPeakResident();
  const std::size_t before = peakResidentBytes();
  constexpr int kPackages = 300;
  std::string burst;
  for (int k = 0; k < kPackages; ++k) {
    v1::ClientMessage package;
    package.mutable_data()->set_component_id(kLargeAnswerComponent);
    package.mutable_data()->set_step(static_cast<std::uint64_t>(k));
    wire::appendFrame(package, burst);
  }
  reader.sendRaw(burst);
  std::this_thread::sleep_for(1500ms);  // time to answer all 300 if nothing held them back
  expectStillServing(server);
  const std::size_t answered = server.handler().count("received 1");
  EXPECT_LT(answered, 60u) << "answers queued beyond the cap plus the socket buffers";
  const std::size_t growth = peakResidentBytes() - before;
  EXPECT_LT(growth, 100u << 20) << "peak RSS grew by " << growth << " bytes";
  for (int k = 0; k < kPackages; ++k) {
    const std::optional<v1::ServerMessage> answer = reader.receive(10000ms);
    ASSERT_TRUE(answer.has_value() && answer->has_data()) << "answer " << k;
    EXPECT_EQ(answer->data().step(), static_cast<std::uint64_t>(k));
  }
}

}  // namespace
}  // namespace demlink::server::test
