/// Loads the win64 DLLs the way a Windows tool does (LoadLibrary by path) and calls the
/// functions that need no server: the FMU library's fmi2GetVersion and
/// fmi2GetTypesPlatform, and the C ABI's dl_version.
/// Usage: fmu_load_check FMU_DLL C_ABI_DLL VERSION. Prints one line; exit 0 when the
/// libraries load and answer "2.0", "default" and VERSION, 1 otherwise (the reason on stderr).
#include <cstdio>
#include <string>

#include "fmi2.h"
#include "shared_library.hpp"

namespace {

int failWith(const std::string& why) {
  std::fprintf(stderr, "fmu_load_check: %s\n", why.c_str());
  return 1;
}

using TextFunction = const char* (*)();

/// What `function` of `library` returns; empty when the library does not export it.
std::string callText(const demlink::fmu::SharedLibrary& library, const char* function) {
  const auto f = library.function<TextFunction>(function);
  return f == nullptr ? std::string() : std::string(f());
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 4) {
    std::fprintf(stderr, "usage: %s FMU_DLL C_ABI_DLL VERSION\n", argv[0]);
    return 2;
  }
  const demlink::fmu::SharedLibrary fmu(argv[1]);
  if (!fmu.loaded()) return failWith(fmu.error());
  const demlink::fmu::SharedLibrary cAbi(argv[2]);
  if (!cAbi.loaded()) return failWith(cAbi.error());
  const std::string version = callText(fmu, "fmi2GetVersion");
  const std::string platform = callText(fmu, "fmi2GetTypesPlatform");
  const std::string cVersion = callText(cAbi, "dl_version");
  std::printf("fmu_load_check: fmi2GetVersion %s, fmi2GetTypesPlatform %s, dl_version %s\n", version.c_str(),
              platform.c_str(), cVersion.c_str());
  if (version != fmi2Version) return failWith("fmi2GetVersion is not " + std::string(fmi2Version));
  if (platform != "default") return failWith("fmi2GetTypesPlatform is not default (fmi2TypesPlatform.h)");
  if (cVersion != argv[3]) return failWith("dl_version is not " + std::string(argv[3]));
  // The FMU library carries the C ABI inside but does not export it.
  if (fmu.function<TextFunction>("dl_version") != nullptr) return failWith("the FMU library exports dl_version");
  return 0;
}
