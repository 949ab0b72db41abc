#pragma once
/// SHA-1 (FIPS 180-4) and base64 (RFC 4648), the two digests the WebSocket opening
/// handshake needs (RFC 6455 section 4.2.2). SHA-1 serves no security purpose here:
/// the handshake only proves that the server understood the WebSocket request.
#include <array>
#include <cstdint>
#include <span>
#include <string>
#include <string_view>

namespace demlink::server {

/// The 20-byte SHA-1 digest of `message`.
[[nodiscard]] std::array<std::uint8_t, 20> sha1(std::string_view message);

/// Standard base64 with '=' padding.
[[nodiscard]] std::string base64Encode(std::span<const std::uint8_t> bytes);

}  // namespace demlink::server
