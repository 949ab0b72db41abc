#pragma once
/// A blocking co-simulation client for transport tests: real sockets on 127.0.0.1, every
/// wait bounded by a timeout so a server bug fails the test instead of hanging it.
///
/// Blocking calls in Asio have no timeouts, so each read is an async_read_some run with
/// io_context::run_until(deadline) and cancelled when the deadline passes.
#include "demlink/server/net/asio.hpp"

#include <array>
#include <chrono>
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>

#include "demlink/v1/protocol.pb.h"
#include "demlink/wire/frame_codec.hpp"

namespace demlink::server::test {

using namespace std::chrono_literals;
using TestClock = std::chrono::steady_clock;

/// Longest a test waits for anything the server should do promptly.
inline constexpr std::chrono::milliseconds kTimeout{3000};

class TestClient {
 public:
  explicit TestClient(std::uint16_t port) : socket_(io_) {
    socket_.connect(asio::ip::tcp::endpoint(asio::ip::make_address("127.0.0.1"), port));
    socket_.set_option(asio::ip::tcp::no_delay(true));
  }

  void sendRaw(std::string_view bytes) { asio::write(socket_, asio::buffer(bytes.data(), bytes.size())); }
  void send(const v1::ClientMessage& message) { sendRaw(wire::encodeFrame(message)); }
  void sendHello(const std::string& name = "test", const std::string& token = "",
                 std::uint32_t version = v1::PROTOCOL_VERSION_CURRENT) {
    v1::ClientMessage message;
    message.mutable_hello()->set_protocol_version(version);
    message.mutable_hello()->set_client_name(name);
    message.mutable_hello()->set_access_token(token);
    send(message);
  }
  /// Hello, then the server's first answer.
  std::optional<v1::ServerMessage> hello(const std::string& name = "test", const std::string& token = "") {
    sendHello(name, token);
    return receive();
  }
  /// Hangs up (the server sees EOF).
  void close() { socket_.close(); }
  /// No more bytes from this client (the server sees EOF; reading still works).
  void shutdownSend() { socket_.shutdown(asio::ip::tcp::socket::shutdown_send); }

  /// The next message; nullopt on timeout, on EOF, or on bytes that do not parse.
  std::optional<v1::ServerMessage> receive(std::chrono::milliseconds timeout = kTimeout) {
    const TestClock::time_point deadline = TestClock::now() + timeout;
    for (;;) {
      if (std::optional<std::string> payload = decoder_.next()) {
        v1::ServerMessage message;
        if (!wire::parsePayload(*payload, message)) return std::nullopt;
        return message;
      }
      if (decoder_.error() != wire::FrameError::None || readSome(deadline) != Read::Data) return std::nullopt;
    }
  }

  /// True if the server closes the connection within the timeout (messages still
  /// arriving before that are discarded).
  bool waitForClose(std::chrono::milliseconds timeout = kTimeout) {
    const TestClock::time_point deadline = TestClock::now() + timeout;
    for (;;) {
      const Read result = readSome(deadline);
      if (result == Read::Closed) return true;
      if (result == Read::Timeout) return false;
    }
  }

 private:
  enum class Read { Data, Closed, Timeout };

  Read readSome(TestClock::time_point deadline) {
    std::optional<asio::error_code> outcome;
    std::size_t received = 0;
    socket_.async_read_some(asio::buffer(buffer_), [&](const asio::error_code& error, std::size_t bytes) {
      outcome = error;
      received = bytes;
    });
    io_.restart();
    io_.run_until(deadline);
    if (!outcome) {
      socket_.cancel();
      io_.restart();
      io_.run();  // completes the cancelled read (or one that finished just in time)
    }
    if (!outcome || *outcome == asio::error::operation_aborted) return Read::Timeout;
    if (*outcome) return Read::Closed;  // EOF or reset
    decoder_.feed(std::string_view(buffer_.data(), received));
    return Read::Data;
  }

  asio::io_context io_;
  asio::ip::tcp::socket socket_;
  wire::FrameDecoder decoder_;
  std::array<char, 64 * 1024> buffer_{};
};

}  // namespace demlink::server::test
