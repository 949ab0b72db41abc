#pragma once
/// Frames of the co-simulation protocol: one protobuf message prefixed by its length as a
/// base-128 varint (the protobuf "delimited" convention), so a client in any language with a
/// protobuf library needs no custom framing (docs/protocol.md).
///
/// The decoder is incremental (bytes arrive in arbitrary pieces from a socket) and never
/// trusts the length: a prefix longer than 10 bytes or above the cap is an error before any
/// payload is buffered, so garbage or hostile bytes cannot make it allocate or wait forever.
#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>

#include <google/protobuf/message_lite.h>

namespace demlink::wire {

/// Default largest accepted payload [bytes] (64 MiB).
inline constexpr std::size_t kDefaultMaxFrameBytes = 64u << 20;

/// The frame (length prefix + payload) of one message.
[[nodiscard]] std::string encodeFrame(const google::protobuf::MessageLite& message);
/// Appends the frame of `message` to `out`.
void appendFrame(const google::protobuf::MessageLite& message, std::string& out);

/// Why the decoder stopped.
enum class FrameError : std::uint8_t {
  None,
  BadLength,      ///< the varint length prefix is malformed (more than 10 bytes / 64 bits)
  TooLarge,       ///< the announced length exceeds the cap
};

class FrameDecoder {
 public:
  explicit FrameDecoder(std::size_t maxFrameBytes = kDefaultMaxFrameBytes) : max_(maxFrameBytes) {}

  /// Appends received bytes. After an error, further bytes are ignored.
  void feed(std::string_view bytes);
  /// The next complete payload, if one is buffered (nullopt: need more bytes, or error()).
  [[nodiscard]] std::optional<std::string> next();
  [[nodiscard]] FrameError error() const { return error_; }
  /// Human-readable reason for error(), e.g. "frame of 70000000 bytes exceeds the cap of 67108864".
  [[nodiscard]] const std::string& errorMessage() const { return error_message_; }
  /// Bytes received but not yet returned as a frame (a truncated frame at EOF) [bytes].
  [[nodiscard]] std::size_t pendingBytes() const { return buffer_.size() - offset_; }
  [[nodiscard]] std::size_t maxFrameBytes() const { return max_; }
  /// Changes the cap for the frames not yet returned (e.g. larger once a peer is trusted).
  void setMaxFrameBytes(std::size_t maxFrameBytes) { max_ = maxFrameBytes; }

 private:
  std::string buffer_;
  std::size_t offset_ = 0;  ///< start of the unread part of buffer_
  std::size_t max_;
  FrameError error_ = FrameError::None;
  std::string error_message_;
};

/// Parses a payload into `message`; false if the bytes are not a valid message of that type.
[[nodiscard]] bool parsePayload(std::string_view payload, google::protobuf::MessageLite& message);

}  // namespace demlink::wire
