#pragma once
/// Text from outside (client names, Bye reasons, names and values in error messages) as
/// it may appear in a log line or an error: one line, no terminal control sequences, and
/// bounded, so a client can neither forge log lines ("\n[12:00:00] error: ...", ANSI
/// escapes) nor make the server write megabytes per message.
#include <cstddef>
#include <string>
#include <string_view>

namespace demlink::core {

/// Bytes of outside text a log line or error message shows [bytes].
inline constexpr std::size_t kLogTextMaxBytes = 200;

/// `text` escaped and truncated: bytes below 0x20, 0x7f and above are written \n, \r,
/// \t or \xHH, a backslash as \\; after `maxBytes` bytes of `text` the rest becomes
/// "...(N bytes)" with N the full length.
[[nodiscard]] std::string logText(std::string_view text, std::size_t maxBytes = kLogTextMaxBytes);

/// logText in double quotes: the form error values take.
[[nodiscard]] std::string quotedLogText(std::string_view text, std::size_t maxBytes = kLogTextMaxBytes);

}  // namespace demlink::core
