#pragma once
/// The two JSON spellings the view's text messages need: strings (escaped) and numbers
/// (shortest round trip; never NaN or infinity, which JSON lacks).
#include <spdlog/fmt/fmt.h>

#include <cmath>
#include <string>
#include <string_view>

namespace demlink::server {

[[nodiscard]] inline std::string jsonString(std::string_view text) {
  std::string out = "\"";
  for (const char c : text) {
    if (c == '"' || c == '\\') {
      out += '\\';
      out += c;
    } else if (static_cast<unsigned char>(c) < 0x20) {
      out += fmt::format("\\u{:04x}", static_cast<unsigned>(static_cast<unsigned char>(c)));
    } else {
      out += c;
    }
  }
  return out + "\"";
}

[[nodiscard]] inline std::string jsonNumber(double value) {
  if (!std::isfinite(value)) return "0";
  return fmt::format("{}", value);
}

}  // namespace demlink::server
