#pragma once
/// Access-token comparison shared by every listener that takes the server's token (the
/// co-simulation port's Hello, the live view's WebSocket).
#include <string>

namespace demlink::server {

/// Compares tokens in time independent of where they differ, so the answer time does not
/// reveal how much of a guessed token was right.
[[nodiscard]] inline bool sameToken(const std::string& expected, const std::string& given) {
  unsigned difference = expected.size() == given.size() ? 0u : 1u;
  for (std::size_t k = 0; k < given.size(); ++k) {
    const char e = expected.empty() ? '\0' : expected[k % expected.size()];
    difference |= static_cast<unsigned>(static_cast<unsigned char>(e) ^ static_cast<unsigned char>(given[k]));
  }
  return difference == 0u;
}

}  // namespace demlink::server
