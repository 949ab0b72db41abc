#include "demlink/wire/frame_codec.hpp"

#include <limits>

namespace demlink::wire {
namespace {

void appendVarint(std::uint64_t value, std::string& out) {
  while (value >= 0x80) {
    out.push_back(static_cast<char>((value & 0x7F) | 0x80));
    value >>= 7;
  }
  out.push_back(static_cast<char>(value));
}

}  // namespace

void appendFrame(const google::protobuf::MessageLite& message, std::string& out) {
  const std::size_t size = message.ByteSizeLong();
  appendVarint(size, out);
  const std::size_t start = out.size();
  out.resize(start + size);
  message.SerializeWithCachedSizesToArray(reinterpret_cast<std::uint8_t*>(out.data() + start));
}

std::string encodeFrame(const google::protobuf::MessageLite& message) {
  std::string out;
  appendFrame(message, out);
  return out;
}

void FrameDecoder::feed(std::string_view bytes) {
  if (error_ != FrameError::None) return;
  // Drop consumed bytes before growing, so a long session does not keep its history.
  if (offset_ > 0 && offset_ == buffer_.size()) {
    buffer_.clear();
    offset_ = 0;
  } else if (offset_ > 4096 && offset_ * 2 > buffer_.size()) {
    buffer_.erase(0, offset_);
    offset_ = 0;
  }
  buffer_.append(bytes);
}

std::optional<std::string> FrameDecoder::next() {
  if (error_ != FrameError::None) return std::nullopt;
  std::uint64_t length = 0;
  std::size_t pos = offset_;
  for (int shift = 0;; shift += 7) {
    if (pos == buffer_.size()) return std::nullopt;  // prefix incomplete
    if (shift >= 64 || pos - offset_ >= 10) {
      error_ = FrameError::BadLength;
      error_message_ = "malformed varint length prefix (more than 10 bytes)";
      return std::nullopt;
    }
    const auto byte = static_cast<std::uint8_t>(buffer_[pos++]);
    length |= static_cast<std::uint64_t>(byte & 0x7F) << shift;
    if ((byte & 0x80) == 0) break;
  }
  if (length > max_) {
    error_ = FrameError::TooLarge;
    error_message_ = "frame of " + std::to_string(length) + " bytes exceeds the cap of " + std::to_string(max_) +
                     " bytes";
    return std::nullopt;
  }
  if (buffer_.size() - pos < length) return std::nullopt;  // payload incomplete
  std::string payload = buffer_.substr(pos, static_cast<std::size_t>(length));
  offset_ = pos + static_cast<std::size_t>(length);
  return payload;
}

bool parsePayload(std::string_view payload, google::protobuf::MessageLite& message) {
  if (payload.size() > static_cast<std::size_t>(std::numeric_limits<int>::max())) return false;
  return message.ParseFromArray(payload.data(), static_cast<int>(payload.size()));
}

}  // namespace demlink::wire
