/// Escaping of outside text (contract in log_text.hpp).
#include "demlink/core/log_text.hpp"

#include <cstdio>

namespace demlink::core {

std::string logText(std::string_view text, std::size_t maxBytes) {
  const std::string_view shown = text.substr(0, maxBytes);
  std::string out;
  out.reserve(shown.size() + 16);
  for (const char c : shown) {
    const auto byte = static_cast<unsigned char>(c);
    switch (c) {
      case '\n': out += "\\n"; break;
      case '\r': out += "\\r"; break;
      case '\t': out += "\\t"; break;
      case '\\': out += "\\\\"; break;
      default:
        if (byte < 0x20 || byte >= 0x7f) {
          char hex[8];
          std::snprintf(hex, sizeof hex, "\\x%02x", static_cast<unsigned>(byte));
          out += hex;
        } else {
          out += c;
        }
    }
  }
  if (shown.size() < text.size()) {
    out.append("...(");
    out.append(std::to_string(text.size()));
    out.append(" bytes)");
  }
  return out;
}

std::string quotedLogText(std::string_view text, std::size_t maxBytes) {
  std::string out(1, '"');
  out.append(logText(text, maxBytes));
  out.push_back('"');
  return out;
}

}  // namespace demlink::core
