/// WebSocket handshake and framing (contract in websocket.hpp; RFC 6455 sections 4 and 5).
#include "demlink/server/view/websocket.hpp"

#include "demlink/server/view/sha1.hpp"

namespace demlink::server {
namespace {

/// RFC 6455 section 1.3: the GUID every server appends to the client's key.
constexpr std::string_view kHandshakeGuid = "258EAFA5-E914-47DA-95CA-C5AB0DC85B11";

std::size_t base64DecodedSize(std::string_view text) {
  if (text.size() % 4 != 0) return 0;
  for (std::size_t i = 0; i < text.size(); ++i) {
    const char c = text[i];
    const bool letter = (c >= 'A' && c <= 'Z') || (c >= 'a' && c <= 'z') || (c >= '0' && c <= '9') || c == '+' ||
                        c == '/';
    const bool padding = c == '=' && i + 2 >= text.size();
    if (!letter && !padding) return 0;
  }
  std::size_t size = text.size() / 4 * 3;
  if (text.ends_with("==")) return size - 2;
  if (text.ends_with("=")) return size - 1;
  return size;
}

}  // namespace

std::string websocketAcceptKey(std::string_view clientKey) {
  std::string joined(clientKey);
  joined += kHandshakeGuid;
  const std::array<std::uint8_t, 20> digest = sha1(joined);
  return base64Encode(digest);
}

std::optional<std::string> websocketHandshakeError(const HttpRequest& request) {
  if (request.method != "GET") return "a WebSocket handshake must be a GET";
  if (!request.headerListsToken("upgrade", "websocket")) return "missing \"Upgrade: websocket\"";
  if (!request.headerListsToken("connection", "upgrade")) return "missing \"Connection: Upgrade\"";
  const std::optional<std::string_view> version = request.header("sec-websocket-version");
  if (!version || *version != "13") return "Sec-WebSocket-Version must be 13";
  const std::optional<std::string_view> key = request.header("sec-websocket-key");
  if (!key || base64DecodedSize(*key) != 16) return "Sec-WebSocket-Key must be 16 bytes in base64";
  return std::nullopt;
}

std::string websocketHandshakeResponse(const HttpRequest& request) {
  const std::string key(request.header("sec-websocket-key").value_or(""));
  return "HTTP/1.1 101 Switching Protocols\r\nUpgrade: websocket\r\nConnection: Upgrade\r\n"
         "Sec-WebSocket-Accept: " +
         websocketAcceptKey(key) + "\r\n\r\n";
}

FrameHeader encodeServerFrameHeader(WebSocketOpcode opcode, std::uint64_t payloadBytes) {
  FrameHeader header;
  header.bytes[0] = static_cast<std::uint8_t>(0x80 | static_cast<std::uint8_t>(opcode));
  if (payloadBytes < 126) {
    header.bytes[1] = static_cast<std::uint8_t>(payloadBytes);
    header.size = 2;
  } else if (payloadBytes <= 0xFFFF) {
    header.bytes[1] = 126;
    header.bytes[2] = static_cast<std::uint8_t>(payloadBytes >> 8);
    header.bytes[3] = static_cast<std::uint8_t>(payloadBytes);
    header.size = 4;
  } else {
    header.bytes[1] = 127;
    for (std::size_t i = 0; i < 8; ++i) header.bytes[2 + i] = static_cast<std::uint8_t>(payloadBytes >> (56 - 8 * i));
    header.size = 10;
  }
  return header;
}

void WebSocketFrameParser::feed(std::string_view bytes) {
  if (failed()) return;
  buffer_.append(bytes);
}

std::optional<ClientMessage> WebSocketFrameParser::fail(std::uint16_t code, std::string why) {
  close_code_ = code;
  failure_ = std::move(why);
  buffer_.clear();
  return std::nullopt;
}

std::optional<ClientMessage> WebSocketFrameParser::next() {
  if (failed() || buffer_.size() < 2) return std::nullopt;
  const auto byte = [this](std::size_t i) { return static_cast<std::uint8_t>(buffer_[i]); };
  const bool fin = (byte(0) & 0x80) != 0;
  if ((byte(0) & 0x70) != 0) return fail(1002, "reserved bits set");
  const std::uint8_t opcode = byte(0) & 0x0F;
  const bool known = opcode <= 0x2 || (opcode >= 0x8 && opcode <= 0xA);
  if (!known) return fail(1002, "reserved opcode");
  if ((byte(1) & 0x80) == 0) return fail(1002, "client frames must be masked");
  if (!fin || opcode == 0x0) return fail(1003, "fragmented messages are not accepted");
  std::uint64_t length = byte(1) & 0x7F;
  std::size_t offset = 2;
  if (length == 126) {
    if (buffer_.size() < 4) return std::nullopt;
    length = (std::uint64_t{byte(2)} << 8) | byte(3);
    offset = 4;
  } else if (length == 127) {
    if (buffer_.size() < 10) return std::nullopt;
    length = 0;
    for (std::size_t i = 0; i < 8; ++i) length = (length << 8) | byte(2 + i);
    offset = 10;
  }
  if (length > kMaxClientMessageBytes) return fail(1009, "message over 1024 bytes");
  if (opcode >= 0x8 && length > 125) return fail(1002, "control frame over 125 bytes");
  if (buffer_.size() < offset + 4 + length) return std::nullopt;
  const std::size_t maskAt = offset;
  ClientMessage message;
  message.opcode = static_cast<WebSocketOpcode>(opcode);
  message.payload.resize(static_cast<std::size_t>(length));
  for (std::size_t i = 0; i < length; ++i) {
    message.payload[i] = static_cast<char>(byte(maskAt + 4 + i) ^ byte(maskAt + i % 4));
  }
  buffer_.erase(0, maskAt + 4 + static_cast<std::size_t>(length));
  return message;
}

std::string encodeMaskedClientFrame(WebSocketOpcode opcode, std::string_view payload,
                                    std::array<std::uint8_t, 4> mask) {
  std::string frame;
  frame += static_cast<char>(0x80 | static_cast<std::uint8_t>(opcode));
  if (payload.size() < 126) {
    frame += static_cast<char>(0x80 | payload.size());
  } else if (payload.size() <= 0xFFFF) {
    frame += static_cast<char>(0x80 | 126);
    frame += static_cast<char>((payload.size() >> 8) & 0xFF);
    frame += static_cast<char>(payload.size() & 0xFF);
  } else {
    frame += static_cast<char>(0x80 | 127);
    for (int shift = 56; shift >= 0; shift -= 8) frame += static_cast<char>((payload.size() >> shift) & 0xFF);
  }
  for (const std::uint8_t m : mask) frame += static_cast<char>(m);
  for (std::size_t i = 0; i < payload.size(); ++i) {
    frame += static_cast<char>(static_cast<std::uint8_t>(payload[i]) ^ mask[i % 4]);
  }
  return frame;
}

}  // namespace demlink::server
