/// The name rule (contract in names.hpp).
#include "demlink/core/base/names.hpp"

#include "demlink/core/base/input_error.hpp"
#include "demlink/core/base/log_text.hpp"

namespace demlink::core {

std::string nameProblem(std::string_view name) {
  if (name.empty()) return "a name is required";
  if (name.size() > kMaxNameLength) {
    return "a name has at most " + std::to_string(kMaxNameLength) + " characters (this one " +
           std::to_string(name.size()) + ")";
  }
  for (const char c : name) {
    if (c < ' ' || c > '~' || c == '"' || c == '\\' || c == '/') {
      return "a name holds only printable ASCII characters other than '\"', '\\' and '/'";
    }
  }
  if (name.front() == ' ' || name.back() == ' ') return "a name neither starts nor ends with a space";
  if (name == "." || name == "..") return "a name is not \".\" or \"..\" (names become file names)";
  return {};
}

void requireValidName(const std::string& field, std::string_view name) {
  if (std::string problem = nameProblem(name); !problem.empty()) {
    throw InputError(field, quotedLogText(name, 64), problem);
  }
}

}  // namespace demlink::core
