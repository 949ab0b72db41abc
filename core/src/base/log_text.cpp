/// Escaping of outside text (contract in log_text.hpp).
#include "demlink/core/base/log_text.hpp"

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

std::string quotedLogList(const std::vector<std::string>& names, std::size_t shown) {
  std::string out;
  for (std::size_t k = 0; k < names.size() && k < shown; ++k) {
    if (k > 0) out += ", ";
    out += quotedLogText(names[k]);
  }
  if (names.size() > shown) {
    out += " and " + std::to_string(names.size() - shown) + " more (" + std::to_string(names.size()) + " in all)";
  }
  return out;
}

std::string cutText(std::string_view text, std::size_t maxBytes) {
  if (text.size() <= maxBytes) return std::string(text);
  std::size_t end = maxBytes;
  // Never inside a multi-byte character: protobuf strings must be valid UTF-8.
  while (end > 0 && (static_cast<unsigned char>(text[end]) & 0xC0u) == 0x80u) --end;
  std::string out(text.substr(0, end));
  out.append("...(");
  out.append(std::to_string(text.size()));
  out.append(" bytes)");
  return out;
}

}  // namespace demlink::core
