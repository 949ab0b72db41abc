#pragma once
/// What a program reports for --version: the project version (CMakeLists.txt) and the git
/// revision it was built from.
#include <string>
#include <string_view>

namespace demlink::cli {

/// The project version, e.g. "0.1.0".
std::string_view projectVersion();

/// `git describe --always --dirty` at build time, or "unknown" when built without git.
std::string_view gitRevision();

/// "<program> <version> (git <revision>)", the line --version prints.
inline std::string versionLine(std::string_view program) {
  std::string line(program);
  line.append(" ").append(projectVersion()).append(" (git ").append(gitRevision()).append(")");
  return line;
}

}  // namespace demlink::cli
