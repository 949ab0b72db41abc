# Compiler warnings, sanitizers and CPU tuning applied to every DEMLink target
# through the interface target demlink_build_flags.
add_library(demlink_build_flags INTERFACE)
target_compile_options(demlink_build_flags INTERFACE
  -Wall -Wextra -Wpedantic -Wshadow -Wconversion -Wno-sign-conversion
  -Wnon-virtual-dtor -Wold-style-cast -Woverloaded-virtual -Wnull-dereference)
if(DEMLINK_WARNINGS_AS_ERRORS)
  target_compile_options(demlink_build_flags INTERFACE -Werror)
endif()
if(DEMLINK_SANITIZE)
  target_compile_options(demlink_build_flags INTERFACE
    -fsanitize=address,undefined -fno-omit-frame-pointer -fno-sanitize-recover=all
    # GCC 12's flow analysis misfires under the sanitizers' instrumentation (e.g.
    # copying a disengaged std::optional of Eigen vectors); the release build keeps
    # the warning.
    $<$<CXX_COMPILER_ID:GNU>:-Wno-maybe-uninitialized>)
  target_link_options(demlink_build_flags INTERFACE -fsanitize=address,undefined)
endif()
if(DEMLINK_FUZZ)
  if(NOT CMAKE_CXX_COMPILER_ID STREQUAL "Clang")
    message(FATAL_ERROR "DEMLINK_FUZZ needs clang (libFuzzer), not ${CMAKE_CXX_COMPILER_ID}")
  endif()
  # Coverage instrumentation for our code; the fuzz executables add libFuzzer's main.
  target_compile_options(demlink_build_flags INTERFACE
    -fsanitize=fuzzer-no-link,address,undefined -fno-omit-frame-pointer -fno-sanitize-recover=all)
  target_link_options(demlink_build_flags INTERFACE -fsanitize=address,undefined)
endif()
if(DEMLINK_NATIVE)
  target_compile_options(demlink_build_flags INTERFACE -march=native)
endif()
