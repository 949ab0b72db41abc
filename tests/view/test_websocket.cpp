// WebSocket handshake and framing against RFC 6455's own examples.
#include <gtest/gtest.h>

#include <string>

#include "demlink/server/view/websocket.hpp"

namespace demlink::server {
namespace {

HttpRequest handshake(const std::string& key, const std::string& version = "13") {
  HttpRequestParser parser;
  const std::string text = "GET /ws HTTP/1.1\r\nHost: h\r\nUpgrade: websocket\r\nConnection: Upgrade\r\n"
                           "Sec-WebSocket-Key: " + key + "\r\nSec-WebSocket-Version: " + version + "\r\n\r\n";
  EXPECT_EQ(parser.feed(text), HttpRequestParser::State::kComplete);
  return parser.request();
}

TEST(WebSocket, AcceptKeyOfTheRfcExample) {
  // RFC 6455 section 1.3.
  EXPECT_EQ(websocketAcceptKey("dGhlIHNhbXBsZSBub25jZQ=="), "s3pPLMBiTxaQ9kYGzzhZRbK+xOo=");
  const HttpRequest request = handshake("dGhlIHNhbXBsZSBub25jZQ==");
  EXPECT_FALSE(websocketHandshakeError(request).has_value());
  const std::string response = websocketHandshakeResponse(request);
  EXPECT_TRUE(response.starts_with("HTTP/1.1 101 Switching Protocols\r\n"));
  EXPECT_NE(response.find("Sec-WebSocket-Accept: s3pPLMBiTxaQ9kYGzzhZRbK+xOo=\r\n"), std::string::npos);
}

TEST(WebSocket, RefusesBadHandshakes) {
  EXPECT_TRUE(websocketHandshakeError(handshake("dGhlIHNhbXBsZSBub25jZQ==", "8")).has_value());
  EXPECT_TRUE(websocketHandshakeError(handshake("c2hvcnQ=")).has_value());  // 5 bytes, not 16
  EXPECT_TRUE(websocketHandshakeError(handshake("not base64 at all!!!!!!=")).has_value());
  HttpRequestParser parser;
  ASSERT_EQ(parser.feed("GET /ws HTTP/1.1\r\nSec-WebSocket-Key: dGhlIHNhbXBsZSBub25jZQ==\r\n"
                        "Sec-WebSocket-Version: 13\r\n\r\n"),
            HttpRequestParser::State::kComplete);
  EXPECT_TRUE(websocketHandshakeError(parser.request()).has_value());  // no Upgrade
}

TEST(WebSocket, ServerFrameHeaderLengths) {
  const FrameHeader small = encodeServerFrameHeader(WebSocketOpcode::kBinary, 125);
  ASSERT_EQ(small.size, 2u);
  EXPECT_EQ(small.bytes[0], 0x82);
  EXPECT_EQ(small.bytes[1], 125);
  const FrameHeader medium = encodeServerFrameHeader(WebSocketOpcode::kText, 126);
  ASSERT_EQ(medium.size, 4u);
  EXPECT_EQ(medium.bytes[0], 0x81);
  EXPECT_EQ(medium.bytes[1], 126);
  EXPECT_EQ(medium.bytes[2], 0);
  EXPECT_EQ(medium.bytes[3], 126);
  // RFC 6455 section 5.7: a 64 KiB binary message, "0x82 0x7F 0x0000000000010000".
  const FrameHeader large = encodeServerFrameHeader(WebSocketOpcode::kBinary, 65536);
  ASSERT_EQ(large.size, 10u);
  EXPECT_EQ(large.bytes[1], 127);
  const std::uint8_t expected[8] = {0, 0, 0, 0, 0, 1, 0, 0};
  for (std::size_t i = 0; i < 8; ++i) EXPECT_EQ(large.bytes[2 + i], expected[i]);
}

TEST(WebSocket, ReadsTheRfcMaskedHello) {
  // RFC 6455 section 5.7: a single-frame masked text message "Hello".
  const unsigned char bytes[] = {0x81, 0x85, 0x37, 0xfa, 0x21, 0x3d, 0x7f, 0x9f, 0x4d, 0x51, 0x58};
  WebSocketFrameParser parser;
  // Byte by byte: nothing until the last byte arrives.
  for (std::size_t i = 0; i < sizeof bytes; ++i) {
    EXPECT_FALSE(parser.next().has_value());
    parser.feed(std::string_view(reinterpret_cast<const char*>(bytes + i), 1));
  }
  const std::optional<ClientMessage> message = parser.next();
  ASSERT_TRUE(message.has_value());
  EXPECT_EQ(message->opcode, WebSocketOpcode::kText);
  EXPECT_EQ(message->payload, "Hello");
  EXPECT_FALSE(parser.failed());
}

TEST(WebSocket, RoundTripsTwoMessagesInOneRead) {
  const std::string payload(300, 'x');  // the 16-bit length form
  WebSocketFrameParser parser;
  parser.feed(encodeMaskedClientFrame(WebSocketOpcode::kText, "rate=5", {1, 2, 3, 4}) +
              encodeMaskedClientFrame(WebSocketOpcode::kText, payload, {9, 8, 7, 6}));
  EXPECT_EQ(parser.next().value().payload, "rate=5");
  EXPECT_EQ(parser.next().value().payload, payload);
  EXPECT_FALSE(parser.next().has_value());
}

TEST(WebSocket, RefusesWithTheRfcCloseCodes) {
  const unsigned char unmasked[] = {0x81, 0x05, 'H', 'e', 'l', 'l', 'o'};  // RFC 5.7's unmasked example
  WebSocketFrameParser a;
  a.feed(std::string_view(reinterpret_cast<const char*>(unmasked), sizeof unmasked));
  EXPECT_FALSE(a.next().has_value());
  EXPECT_EQ(a.closeCode(), 1002);

  WebSocketFrameParser b;  // first fragment of a fragmented message (FIN clear)
  std::string fragment = encodeMaskedClientFrame(WebSocketOpcode::kText, "Hel", {1, 1, 1, 1});
  fragment[0] = static_cast<char>(0x01);
  b.feed(fragment);
  EXPECT_FALSE(b.next().has_value());
  EXPECT_EQ(b.closeCode(), 1003);

  WebSocketFrameParser c;
  c.feed(encodeMaskedClientFrame(WebSocketOpcode::kBinary, std::string(kMaxClientMessageBytes + 1, 'a'), {1, 2, 3, 4}));
  EXPECT_FALSE(c.next().has_value());
  EXPECT_EQ(c.closeCode(), 1009);

  WebSocketFrameParser d;
  std::string reserved = encodeMaskedClientFrame(WebSocketOpcode::kText, "x", {1, 2, 3, 4});
  reserved[0] = static_cast<char>(0x83);  // opcode 3 is reserved
  d.feed(reserved);
  EXPECT_FALSE(d.next().has_value());
  EXPECT_EQ(d.closeCode(), 1002);
}

}  // namespace
}  // namespace demlink::server
