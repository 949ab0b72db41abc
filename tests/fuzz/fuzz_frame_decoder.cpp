/// libFuzzer target: the frame decoder and ClientMessage parsing, i.e. everything the
/// server does with a client's bytes before the session handler sees them.
///
/// Input: byte 0 chooses the chunk size (1..64) the rest is fed in, as a socket would
/// deliver it. Checked: no crash or sanitizer report, no payload above the cap, errors
/// carry a message, and every parsed message survives an encode/decode round trip.
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <string>
#include <string_view>

#include "fuzz_seeds.hpp"

namespace {

constexpr std::size_t kCap = 4096;  // small, so TooLarge is reachable [bytes]

void check(bool condition) {
  if (!condition) std::abort();
}

void roundTrip(const demlink::v1::ClientMessage& message) {
  demlink::wire::FrameDecoder decoder(kCap * 4);  // re-encoding may grow (e.g. packed fields)
  decoder.feed(demlink::wire::encodeFrame(message));
  const std::optional<std::string> again = decoder.next();
  check(again.has_value());
  demlink::v1::ClientMessage reparsed;
  check(demlink::wire::parsePayload(*again, reparsed));
  check(reparsed.SerializeAsString() == message.SerializeAsString());
}

}  // namespace

extern "C" int LLVMFuzzerInitialize(int* /*argc*/, char*** /*argv*/) {
  using namespace demlink;
  fuzz::silenceProtobufLog();
  std::string frames;
  wire::appendFrame(fuzz::helloMessage("seed"), frames);
  wire::appendFrame(fuzz::dataMessage(2, 40), frames);
  wire::appendFrame(fuzz::byeMessage(), frames);
  v1::ClientMessage declare;
  declare.mutable_declare()->mutable_component()->set_name("box");
  declare.mutable_declare()->mutable_component()->mutable_simulation_box()->set_time_step(1e-5);
  std::string declareFrame = wire::encodeFrame(declare);
  fuzz::writeSeedsIfAsked({std::string(1, '\x00') + frames, std::string(1, '\x07') + frames,
                           std::string(1, '\x01') + declareFrame, std::string("\x02\x80\x80\x40", 4)});
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size == 0) return 0;
  const std::size_t chunk = 1 + data[0] % 64;
  const std::string_view bytes(reinterpret_cast<const char*>(data) + 1, size - 1);
  demlink::wire::FrameDecoder decoder(kCap);
  for (std::size_t position = 0; position < bytes.size(); position += chunk) {
    decoder.feed(bytes.substr(position, chunk));
    while (const std::optional<std::string> payload = decoder.next()) {
      check(payload->size() <= kCap);
      demlink::v1::ClientMessage message;
      if (demlink::wire::parsePayload(*payload, message)) roundTrip(message);
    }
    if (decoder.error() != demlink::wire::FrameError::None) {
      check(!decoder.errorMessage().empty());
      break;
    }
  }
  check(decoder.pendingBytes() <= bytes.size());
  return 0;
}
