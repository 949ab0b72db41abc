#pragma once
/// A shared library loaded by path and its exported functions: dlopen/dlsym, or
/// LoadLibrary/GetProcAddress in the win64 build of the test programs. Also names the FMI
/// platform folder and library suffix of the build (FMI 2.0, section 2.3).
#include <string>

#if defined(_WIN32)
#include <windows.h>
#else
#include <dlfcn.h>
#endif

namespace demlink::fmu {

#if defined(_WIN32)
inline constexpr const char* kFmiPlatform = "win64";
inline constexpr const char* kLibrarySuffix = ".dll";
#else
inline constexpr const char* kFmiPlatform = "linux64";
inline constexpr const char* kLibrarySuffix = ".so";
#endif

class SharedLibrary {
 public:
  explicit SharedLibrary(const std::string& path) {
#if defined(_WIN32)
    handle_ = LoadLibraryA(path.c_str());
    if (handle_ == nullptr) error_ = "LoadLibrary " + path + ": error " + std::to_string(GetLastError());
#else
    handle_ = dlopen(path.c_str(), RTLD_NOW | RTLD_LOCAL);
    if (handle_ == nullptr) error_ = std::string("dlopen: ") + dlerror();
#endif
  }
  SharedLibrary(const SharedLibrary&) = delete;
  SharedLibrary& operator=(const SharedLibrary&) = delete;
  /// Unloading is left to the process's exit: a library's threads may outlive a close.
  ~SharedLibrary() = default;

  [[nodiscard]] bool loaded() const { return handle_ != nullptr; }
  /// Why loading failed (empty when loaded).
  [[nodiscard]] const std::string& error() const { return error_; }

  /// The exported function `name` as F; nullptr when it is not exported.
  template <class F>
  [[nodiscard]] F function(const char* name) const {
#if defined(_WIN32)
    // Through void (*)(), the type GCC's -Wcast-function-type lets convert to any other.
    return reinterpret_cast<F>(reinterpret_cast<void (*)()>(GetProcAddress(handle_, name)));
#else
    return reinterpret_cast<F>(dlsym(handle_, name));
#endif
  }

 private:
#if defined(_WIN32)
  HMODULE handle_ = nullptr;
#else
  void* handle_ = nullptr;
#endif
  std::string error_;
};

}  // namespace demlink::fmu
