/// The frame codec (proto/wire): round trips, arbitrary splitting, and refusing malformed
/// or oversized length prefixes before any payload is buffered.
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "demlink/v1/protocol.pb.h"
#include "demlink/wire/frame_codec.hpp"

namespace demlink::wire {
namespace {

std::vector<v1::ClientMessage> sampleMessages() {
  std::vector<v1::ClientMessage> messages(3);
  messages[0].mutable_hello()->set_protocol_version(1);
  messages[0].mutable_hello()->set_client_name("codec");
  messages[1].mutable_bye()->set_reason(std::string(300, 'x'));  // two-byte length prefix
  messages[2].mutable_data()->set_component_id(7);
  messages[2].mutable_data()->set_step(123456789);
  messages[2].mutable_data()->mutable_rigid_body_input()->mutable_position()->set_x(-1.25);
  return messages;
}

std::string concatenatedFrames(const std::vector<v1::ClientMessage>& messages) {
  std::string bytes;
  for (const v1::ClientMessage& message : messages) appendFrame(message, bytes);
  return bytes;
}

void expectSameMessages(const std::vector<std::string>& payloads, const std::vector<v1::ClientMessage>& messages) {
  ASSERT_EQ(payloads.size(), messages.size());
  for (std::size_t k = 0; k < payloads.size(); ++k) {
    v1::ClientMessage parsed;
    ASSERT_TRUE(parsePayload(payloads[k], parsed)) << "frame " << k;
    EXPECT_EQ(parsed.SerializeAsString(), messages[k].SerializeAsString()) << "frame " << k;
  }
}

TEST(FrameCodec, RoundTripOfSeveralFramesFedAtOnce) {
  const std::vector<v1::ClientMessage> messages = sampleMessages();
  FrameDecoder decoder;
  decoder.feed(concatenatedFrames(messages));
  std::vector<std::string> payloads;
  while (std::optional<std::string> payload = decoder.next()) payloads.push_back(*payload);
  expectSameMessages(payloads, messages);
  EXPECT_EQ(decoder.error(), FrameError::None);
  EXPECT_EQ(decoder.pendingBytes(), 0u);
}

TEST(FrameCodec, FramesSplitOneByteAtATime) {
  const std::vector<v1::ClientMessage> messages = sampleMessages();
  const std::string bytes = concatenatedFrames(messages);
  FrameDecoder decoder;
  std::vector<std::string> payloads;
  for (const char byte : bytes) {
    decoder.feed(std::string_view(&byte, 1));
    while (std::optional<std::string> payload = decoder.next()) payloads.push_back(*payload);
  }
  expectSameMessages(payloads, messages);
  EXPECT_EQ(decoder.pendingBytes(), 0u);
}

TEST(FrameCodec, VarintLongerThanTenBytesIsBadLength) {
  FrameDecoder decoder;
  decoder.feed(std::string(10, '\x80') + '\x01');
  EXPECT_FALSE(decoder.next().has_value());
  EXPECT_EQ(decoder.error(), FrameError::BadLength);
  EXPECT_NE(decoder.errorMessage().find("varint"), std::string::npos) << decoder.errorMessage();
  // A stuck decoder stays stuck: later valid frames are not decoded from a corrupt stream.
  v1::ClientMessage bye;
  bye.mutable_bye();
  decoder.feed(encodeFrame(bye));
  EXPECT_FALSE(decoder.next().has_value());
}

TEST(FrameCodec, TenByteVarintIsALengthNotAMalformedPrefix) {
  // 2^64 - 1 takes exactly ten bytes: well-formed, but above any cap.
  FrameDecoder decoder;
  decoder.feed(std::string(9, '\xff') + '\x01');
  EXPECT_FALSE(decoder.next().has_value());
  EXPECT_EQ(decoder.error(), FrameError::TooLarge);
}

TEST(FrameCodec, OversizedFrameIsRefusedBeforeItsPayloadIsBuffered) {
  FrameDecoder decoder(100);
  decoder.feed("\xe8\x07");  // 1000
  EXPECT_FALSE(decoder.next().has_value());
  EXPECT_EQ(decoder.error(), FrameError::TooLarge);
  EXPECT_NE(decoder.errorMessage().find("1000"), std::string::npos) << decoder.errorMessage();
  EXPECT_NE(decoder.errorMessage().find("100 bytes"), std::string::npos) << decoder.errorMessage();
  decoder.feed(std::string(5000, 'p'));
  EXPECT_LE(decoder.pendingBytes(), 2u) << "payload bytes after the error must not be kept";
}

TEST(FrameCodec, FrameExactlyAtTheCapIsAccepted) {
  v1::ClientMessage message;
  message.mutable_bye()->set_reason(std::string(50, 'r'));
  const std::string frame = encodeFrame(message);
  const std::size_t payloadSize = message.ByteSizeLong();
  FrameDecoder atCap(payloadSize);
  atCap.feed(frame);
  EXPECT_TRUE(atCap.next().has_value());
  FrameDecoder belowCap(payloadSize - 1);
  belowCap.feed(frame);
  EXPECT_FALSE(belowCap.next().has_value());
  EXPECT_EQ(belowCap.error(), FrameError::TooLarge);
}

TEST(FrameCodec, TruncatedFrameIsPendingNotAnError) {
  v1::ClientMessage message;
  message.mutable_bye()->set_reason(std::string(50, 'r'));
  const std::string frame = encodeFrame(message);
  FrameDecoder decoder;
  decoder.feed(std::string_view(frame).substr(0, 21));
  EXPECT_FALSE(decoder.next().has_value());
  EXPECT_EQ(decoder.error(), FrameError::None);
  EXPECT_EQ(decoder.pendingBytes(), 21u);
  decoder.feed(std::string_view(frame).substr(21));
  EXPECT_TRUE(decoder.next().has_value());
  EXPECT_EQ(decoder.pendingBytes(), 0u);
}

}  // namespace
}  // namespace demlink::wire
