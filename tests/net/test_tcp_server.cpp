/// TcpServer against a scripted SessionHandler over real loopback sockets: the Hello check,
/// every transport fault answered with the right Error and a closed connection while the
/// server keeps serving, handler exceptions, many connections, the poll timer and stop().
#include <gtest/gtest.h>

#include <memory>
#include <string>
#include <vector>

#include "demlink/core/base/input_error.hpp"
#include "fake_session_handler.hpp"

namespace demlink::server::test {
namespace {

v1::ClientMessage dataMessage(std::uint32_t component, std::uint64_t step) {
  v1::ClientMessage message;
  message.mutable_data()->set_component_id(component);
  message.mutable_data()->set_step(step);
  return message;
}

TEST(TcpServer, HelloIsWelcomedAndPackagesAreEchoed) {
  RunningServer server;
  TestClient client(server.port());
  const std::optional<v1::ServerMessage> welcome = client.hello();
  ASSERT_TRUE(welcome.has_value());
  EXPECT_TRUE(welcome->has_welcome());
  client.send(dataMessage(3, 40));
  const std::optional<v1::ServerMessage> echo = client.receive();
  ASSERT_TRUE(echo.has_value());
  EXPECT_EQ(echo->data().component_id(), 3u);
  EXPECT_EQ(echo->data().step(), 40u);
}

TEST(TcpServer, WrongProtocolVersionIsRefused) {
  RunningServer server;
  TestClient client(server.port());
  client.sendHello("old", "", 7);
  expectRefused(client, v1::Error::PROTOCOL_VERSION, "protocol version 7");
  EXPECT_EQ(server.handler().count("connected"), 0u) << "refused before the handler";
  expectStillServing(server);
}

TEST(TcpServer, AccessTokenIsChecked) {
  TcpServerOptions options;
  options.access_token = "s3cret";
  RunningServer server(options);
  {
    TestClient wrong(server.port());
    wrong.sendHello("intruder", "guess");
    expectRefused(wrong, v1::Error::ACCESS_DENIED, "wrong access token");
  }
  {
    TestClient missing(server.port());
    missing.sendHello("forgetful");
    expectRefused(missing, v1::Error::ACCESS_DENIED, "requires an access token");
  }
  EXPECT_EQ(server.handler().count("connected"), 0u);
  TestClient right(server.port());
  const std::optional<v1::ServerMessage> welcome = right.hello("friend", "s3cret");
  ASSERT_TRUE(welcome.has_value());
  EXPECT_TRUE(welcome->has_welcome());
}

TEST(TcpServer, MessageBeforeHelloIsOutOfOrder) {
  RunningServer server;
  TestClient client(server.port());
  client.send(dataMessage(1, 0));
  expectRefused(client, v1::Error::OUT_OF_ORDER, "got data");
  EXPECT_EQ(server.handler().count("received"), 0u);
  expectStillServing(server);
}

TEST(TcpServer, MalformedLengthPrefixIsBadFrame) {
  RunningServer server;
  TestClient client(server.port());
  client.sendRaw(std::string(12, '\xff'));
  expectRefused(client, v1::Error::BAD_FRAME, "varint");
  expectStillServing(server);
}

TEST(TcpServer, PayloadThatIsNotAClientMessageIsBadFrame) {
  RunningServer server;
  TestClient client(server.port());
  ASSERT_TRUE(client.hello().has_value());
  client.sendRaw(std::string("\x03\xff\xff\xff", 4));  // field number 0 is never valid protobuf
  expectRefused(client, v1::Error::BAD_FRAME, "payload of 3 bytes");
  // A welcomed connection that dies is reported to the handler, with the reason.
  EXPECT_NE(server.handler().waitForCall("disconnected").find("bad frame"), std::string::npos);
  expectStillServing(server);
}

TEST(TcpServer, EmptyClientMessageIsBadFrame) {
  RunningServer server;
  TestClient client(server.port());
  client.sendRaw(std::string("\x00", 1));
  expectRefused(client, v1::Error::BAD_FRAME, "sets none of");
  expectStillServing(server);
}

TEST(TcpServer, TruncatedFrameThenEofIsReported) {
  RunningServer server;
  TestClient client(server.port());
  ASSERT_TRUE(client.hello().has_value());
  client.sendRaw(std::string("\x64", 1) + std::string(10, 'z'));  // 100 announced, 10 sent
  client.shutdownSend();
  expectRefused(client, v1::Error::BAD_FRAME, "11 bytes of an unfinished frame");
  EXPECT_NE(server.handler().waitForCall("disconnected").find("11 bytes of an unfinished frame pending"),
            std::string::npos);
  expectStillServing(server);
}

TEST(TcpServer, OversizedFrameIsRefused) {
  TcpServerOptions options;
  options.max_frame_bytes = 1024;
  RunningServer server(options);
  TestClient client(server.port());
  ASSERT_TRUE(client.hello().has_value());
  client.sendRaw("\x80\x80\x40");  // 2^20 = 1048576 bytes announced
  expectRefused(client, v1::Error::FRAME_TOO_LARGE, "frame of 1048576 bytes exceeds the cap of 1024");
  expectStillServing(server);
}

TEST(TcpServer, CleanEofIsReportedToTheHandler) {
  RunningServer server;
  {
    TestClient client(server.port());
    ASSERT_TRUE(client.hello().has_value());
  }
  EXPECT_EQ(server.handler().waitForCall("disconnected"), "disconnected 1: client closed the connection");
}

TEST(TcpServer, HandlerExceptionBecomesInternalErrorAndServerSurvives) {
  RunningServer server;
  {
    TestClient client(server.port());
    client.sendHello("throw");
    expectRefused(client, v1::Error::INTERNAL, "scripted failure in connected");
  }
  {
    TestClient client(server.port());
    ASSERT_TRUE(client.hello().has_value());
    v1::ClientMessage declare;
    declare.mutable_declare()->mutable_component()->set_name("throw");
    client.send(declare);
    expectRefused(client, v1::Error::INTERNAL, "scripted failure in received");
  }
  expectStillServing(server);
}

TEST(TcpServer, ByeWithCloseAfterIsAnsweredThenClosed) {
  RunningServer server;
  TestClient client(server.port());
  ASSERT_TRUE(client.hello().has_value());
  v1::ClientMessage bye;
  bye.mutable_bye()->set_reason("done");
  client.send(bye);
  const std::optional<v1::ServerMessage> finished = client.receive();
  ASSERT_TRUE(finished.has_value());
  EXPECT_EQ(finished->finished().reason(), "bye");
  EXPECT_TRUE(client.waitForClose());
}

TEST(TcpServer, SixteenConcurrentConnectionsEachGetTheirOwnAnswers) {
  RunningServer server;
  constexpr std::uint32_t kClients = 16;
  constexpr std::uint64_t kRounds = 10;
  std::vector<std::unique_ptr<TestClient>> clients;
  for (std::uint32_t k = 0; k < kClients; ++k) {
    clients.push_back(std::make_unique<TestClient>(server.port()));
    clients.back()->sendHello("client " + std::to_string(k));
  }
  for (const auto& client : clients) {
    const std::optional<v1::ServerMessage> welcome = client->receive();
    ASSERT_TRUE(welcome.has_value() && welcome->has_welcome());
  }
  for (std::uint64_t round = 0; round < kRounds; ++round) {
    // All send before any reads: the server interleaves connections.
    for (std::uint32_t k = 0; k < kClients; ++k) clients[k]->send(dataMessage(k, round));
    for (std::uint32_t k = 0; k < kClients; ++k) {
      const std::optional<v1::ServerMessage> echo = clients[k]->receive();
      ASSERT_TRUE(echo.has_value()) << "client " << k << " round " << round;
      EXPECT_EQ(echo->data().component_id(), k);
      EXPECT_EQ(echo->data().step(), round);
    }
  }
  EXPECT_EQ(server.handler().count("connected"), kClients);
  EXPECT_EQ(server.handler().count("received"), kClients * kRounds);
}

TEST(TcpServer, PollRunsWhenTheDeadlinePasses) {
  RunningServer server;
  TestClient client(server.port());
  ASSERT_TRUE(client.hello("poll").has_value());  // the fake schedules a poll 100 ms later
  const std::optional<v1::ServerMessage> polled = client.receive();
  ASSERT_TRUE(polled.has_value()) << "poll() never ran";
  EXPECT_EQ(polled->finished().reason(), "poll");
  EXPECT_TRUE(server.handler().polledLateEnough()) << "poll ran before nextDeadline()";
}

TEST(TcpServer, StopDeliversPendingMessagesAndReturns) {
  TcpServerOptions options;
  options.close_grace = std::chrono::milliseconds(300);  // the clients read only after run() returned
  RunningServer server(options);
  TestClient first(server.port());
  TestClient second(server.port());
  ASSERT_TRUE(first.hello().has_value());
  ASSERT_TRUE(second.hello().has_value());
  EXPECT_TRUE(server.stop("SIGINT")) << "run() did not return";
  for (TestClient* client : {&first, &second}) {
    const std::optional<v1::ServerMessage> last = client->receive();
    ASSERT_TRUE(last.has_value()) << "the shutdown message was lost";
    EXPECT_EQ(last->finished().reason(), "SIGINT");
    EXPECT_TRUE(client->waitForClose());
  }
  EXPECT_EQ(server.handler().count("shutdown SIGINT"), 1u);
  EXPECT_EQ(server.handler().count("disconnected"), 2u);
}

TEST(TcpServer, StopWhenEndsTheServerAfterTheSessionEnds) {
  TcpServerOptions options;
  options.close_grace = std::chrono::milliseconds(300);  // the client never hangs up by itself
  RunningServer server(options, /*stopAfterBye=*/true);
  TestClient client(server.port());
  ASSERT_TRUE(client.hello().has_value());
  v1::ClientMessage bye;
  bye.mutable_bye();
  client.send(bye);
  const std::optional<v1::ServerMessage> finished = client.receive();
  ASSERT_TRUE(finished.has_value());
  EXPECT_EQ(finished->finished().reason(), "bye");
  EXPECT_TRUE(server.waitForReturn()) << "run() must return by itself once stop_when holds";
  EXPECT_EQ(server.handler().count("shutdown"), 0u) << "--once is not a signal";
}

TEST(TcpServer, BindingAnInvalidAddressNamesIt) {
  FakeSessionHandler handler;
  TcpServerOptions options;
  options.listen_address = "999.1.2.3";
  try {
    const TcpServer server(handler, options);
    FAIL() << "expected an error";
  } catch (const demlink::core::InputError& error) {
    EXPECT_NE(std::string(error.what()).find("999.1.2.3"), std::string::npos) << error.what();
  }
}

}  // namespace
}  // namespace demlink::server::test
