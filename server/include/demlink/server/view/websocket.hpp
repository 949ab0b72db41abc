#pragma once
/// The WebSocket protocol (RFC 6455) as the view uses it: the opening handshake, server
/// frames (unmasked, unfragmented) and the client's small masked control and text frames.
/// Framing is separate from sockets so that tests can check it byte by byte.
#include <array>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>

#include "demlink/server/view/http_request.hpp"

namespace demlink::server {

/// Largest message a client may send [B]: the view's requests are a few words of text.
inline constexpr std::size_t kMaxClientMessageBytes = 1024;

enum class WebSocketOpcode : std::uint8_t {
  kContinuation = 0x0,
  kText = 0x1,
  kBinary = 0x2,
  kClose = 0x8,
  kPing = 0x9,
  kPong = 0xA,
};

/// Sec-WebSocket-Accept for a client's Sec-WebSocket-Key: base64(SHA-1(key + the RFC's GUID)).
[[nodiscard]] std::string websocketAcceptKey(std::string_view clientKey);

/// Why `request` is not a valid WebSocket opening handshake (RFC 6455 section 4.2.1:
/// GET, Upgrade: websocket, Connection lists Upgrade, a 16-byte base64 key, version 13),
/// or nullopt when it is.
[[nodiscard]] std::optional<std::string> websocketHandshakeError(const HttpRequest& request);

/// The server's "101 Switching Protocols" response to a valid handshake.
[[nodiscard]] std::string websocketHandshakeResponse(const HttpRequest& request);

/// The header of one unmasked, final server frame carrying `payloadBytes` (2, 4 or 10
/// bytes long); the payload follows it unchanged.
struct FrameHeader {
  std::array<std::uint8_t, 10> bytes{};
  std::size_t size = 0;
};
[[nodiscard]] FrameHeader encodeServerFrameHeader(WebSocketOpcode opcode, std::uint64_t payloadBytes);

/// One complete message from the client (unmasked payload).
struct ClientMessage {
  WebSocketOpcode opcode = WebSocketOpcode::kText;
  std::string payload;
};

/// Reads client frames. Refuses, with the close code RFC 6455 section 7.4.1 gives, an
/// unmasked frame (1002), reserved bits or opcodes (1002), fragmented messages (1003: the
/// view's messages are small) and payloads over kMaxClientMessageBytes (1009).
class WebSocketFrameParser {
 public:
  /// Appends bytes; call next() until it returns nullopt to take the messages they complete.
  void feed(std::string_view bytes);
  /// The next complete message, or nullopt (then check failed()).
  [[nodiscard]] std::optional<ClientMessage> next();

  [[nodiscard]] bool failed() const { return close_code_ != 0; }
  /// On failure: the close code to send and why.
  [[nodiscard]] std::uint16_t closeCode() const { return close_code_; }
  [[nodiscard]] const std::string& failure() const { return failure_; }

 private:
  std::optional<ClientMessage> fail(std::uint16_t code, std::string why);

  std::string buffer_;
  std::uint16_t close_code_ = 0;
  std::string failure_;
};

/// A masked client frame (tests and test clients): FIN set, the given mask key.
[[nodiscard]] std::string encodeMaskedClientFrame(WebSocketOpcode opcode, std::string_view payload,
                                                  std::array<std::uint8_t, 4> mask);

}  // namespace demlink::server
