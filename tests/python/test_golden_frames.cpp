// Golden frames shared by the C++ wire codec and the Python client.
//
// Why: docs/protocol.md promises that any protobuf library plus a varint length prefix
// speaks our protocol. tests/python/golden/frames.hex holds the exact bytes of two
// client frames (a Hello with a one-byte prefix, a RigidBody DataPackage with a
// two-byte prefix); the Python client's test checks its own encoder and protoc
// --encode against the same file, so the three agree byte for byte.
#include <gtest/gtest.h>

#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <string_view>
#include <vector>

#include <google/protobuf/text_format.h>

#include "demlink/v1/protocol.pb.h"
#include "demlink/wire/frame_codec.hpp"

namespace {

const std::string kGoldenDir = DEMLINK_GOLDEN_DIR;

std::string readFile(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  EXPECT_TRUE(in.good()) << "cannot open " << path;
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

/// name -> frame bytes, from frames.hex ("<name> <hex>" lines, '#' comments).
std::map<std::string, std::string> goldenFrames() {
  std::map<std::string, std::string> frames;
  std::istringstream lines(readFile(kGoldenDir + "/frames.hex"));
  std::string line;
  while (std::getline(lines, line)) {
    if (line.empty() || line[0] == '#') continue;
    std::istringstream fields(line);
    std::string name;
    std::string hex;
    fields >> name >> hex;
    std::string bytes;
    for (std::size_t i = 0; i + 1 < hex.size(); i += 2) {
      bytes.push_back(static_cast<char>(std::stoi(hex.substr(i, 2), nullptr, 16)));
    }
    frames[name] = bytes;
  }
  return frames;
}

demlink::v1::ClientMessage messageOf(const std::string& name) {
  demlink::v1::ClientMessage message;
  EXPECT_TRUE(google::protobuf::TextFormat::ParseFromString(readFile(kGoldenDir + "/" + name + ".txtpb"), &message))
      << name << ".txtpb is not a valid ClientMessage";
  return message;
}

std::string hexOf(const std::string& bytes) {
  static constexpr char kDigits[] = "0123456789abcdef";
  std::string hex;
  for (const char c : bytes) {
    const auto byte = static_cast<unsigned char>(c);
    hex.push_back(kDigits[byte >> 4]);
    hex.push_back(kDigits[byte & 0x0F]);
  }
  return hex;
}

TEST(GoldenFrames, EncodeFrameProducesTheGoldenBytes) {
  const auto frames = goldenFrames();
  ASSERT_EQ(frames.size(), 2u);
  for (const auto& [name, bytes] : frames) {
    EXPECT_EQ(hexOf(demlink::wire::encodeFrame(messageOf(name))), hexOf(bytes)) << name;
  }
}

TEST(GoldenFrames, LengthPrefixIsOneByteBelow128AndTwoAbove) {
  const auto frames = goldenFrames();
  const std::string& hello = frames.at("hello");
  EXPECT_EQ(static_cast<std::size_t>(static_cast<unsigned char>(hello[0])), hello.size() - 1);
  const std::string& data = frames.at("rigid_body_data");
  const std::size_t length = (static_cast<std::size_t>(static_cast<unsigned char>(data[0])) & 0x7Fu) |
                             (static_cast<std::size_t>(static_cast<unsigned char>(data[1])) << 7);
  EXPECT_GT(length, 127u);
  EXPECT_EQ(length, data.size() - 2);
}

TEST(GoldenFrames, DecoderSplitsTheGoldenStreamFedByteByByte) {
  const auto frames = goldenFrames();
  const std::string stream = frames.at("hello") + frames.at("rigid_body_data");
  demlink::wire::FrameDecoder decoder;
  std::vector<std::string> payloads;
  for (const char c : stream) {
    decoder.feed(std::string_view(&c, 1));
    while (auto payload = decoder.next()) payloads.push_back(*payload);
  }
  ASSERT_EQ(decoder.error(), demlink::wire::FrameError::None) << decoder.errorMessage();
  ASSERT_EQ(payloads.size(), 2u);
  EXPECT_EQ(decoder.pendingBytes(), 0u);
  demlink::v1::ClientMessage hello;
  ASSERT_TRUE(demlink::wire::parsePayload(payloads[0], hello));
  EXPECT_EQ(hello.hello().client_name(), "golden-client");
  demlink::v1::ClientMessage data;
  ASSERT_TRUE(demlink::wire::parsePayload(payloads[1], data));
  EXPECT_EQ(data.data().step(), 1000u);
  EXPECT_DOUBLE_EQ(data.data().rigid_body_input().angular_velocity().z(), -3.0);
}

}  // namespace
