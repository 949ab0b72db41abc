#pragma once
/// The one rule for names a user or a client chooses (components, materials, client
/// names): they appear in file names, CSV headers, log lines and error messages, so they
/// are short and plain.
#include <cstddef>
#include <string>
#include <string_view>

namespace demlink::core {

/// Longest name [bytes].
inline constexpr std::size_t kMaxNameLength = 128;

/// Why `name` breaks the rule (empty: it does not). The rule: 1 to kMaxNameLength
/// printable ASCII characters (space to '~') other than '"', '\\' and '/', neither starting
/// nor ending with a space, and not "." or "..": a name is then also a safe file name
/// (sensor CSVs and output files are named after components).
[[nodiscard]] std::string nameProblem(std::string_view name);

/// Throws InputError naming `field` (the value escaped and truncated, log_text.hpp) when
/// `name` breaks the rule.
void requireValidName(const std::string& field, std::string_view name);

}  // namespace demlink::core
