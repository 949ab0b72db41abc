#pragma once
/// Text from outside (client names, Bye reasons, names and values in error messages) as
/// it may appear in a log line or an error: one line, no terminal control sequences, and
/// bounded, so a client can neither forge log lines ("\n[12:00:00] error: ...", ANSI
/// escapes) nor make the server write megabytes per message.
#include <cstddef>
#include <string>
#include <string_view>
#include <vector>

namespace demlink::core {

/// Bytes of outside text a log line or error message shows [bytes].
inline constexpr std::size_t kLogTextMaxBytes = 200;

/// `text` escaped and truncated: bytes below 0x20, 0x7f and above are written \n, \r,
/// \t or \xHH, a backslash as \\; after `maxBytes` bytes of `text` the rest becomes
/// "...(N bytes)" with N the full length.
[[nodiscard]] std::string logText(std::string_view text, std::size_t maxBytes = kLogTextMaxBytes);

/// logText in double quotes: the form error values take.
[[nodiscard]] std::string quotedLogText(std::string_view text, std::size_t maxBytes = kLogTextMaxBytes);

/// Names in a message: the first `shown` of `names`, each quotedLogText, then "and N more
/// (M in all)", so a list of any length costs a few hundred bytes.
[[nodiscard]] std::string quotedLogList(const std::vector<std::string>& names, std::size_t shown = 5);

/// Longest message the server sends or logs in one Error [bytes]: a server-built message
/// (names cut by logText, lists by quotedLogList) stays far below it; longer ones are cut
/// there (at a UTF-8 boundary) as the last guard.
inline constexpr std::size_t kErrorMessageMaxBytes = 4096;

/// `text` cut to at most `maxBytes` bytes at a UTF-8 character boundary, with
/// "...(N bytes)" appended when cut (no escaping: for server-built text).
[[nodiscard]] std::string cutText(std::string_view text, std::size_t maxBytes = kErrorMessageMaxBytes);

}  // namespace demlink::core
