# CMake toolchain for the win64 cross build of the client side (scripts/build_win64.sh):
# Debian's mingw-w64 with POSIX threads (std::thread, std::mutex through winpthreads).
# Every program and DLL links the C++ runtime, libgcc and winpthreads statically, so it
# needs only Windows system DLLs.
set(CMAKE_SYSTEM_NAME Windows)
set(CMAKE_SYSTEM_PROCESSOR x86_64)
set(DEMLINK_MINGW_TRIPLET x86_64-w64-mingw32)
set(CMAKE_C_COMPILER ${DEMLINK_MINGW_TRIPLET}-gcc-posix)
set(CMAKE_CXX_COMPILER ${DEMLINK_MINGW_TRIPLET}-g++-posix)
set(CMAKE_RC_COMPILER ${DEMLINK_MINGW_TRIPLET}-windres)

# Libraries and headers come from the mingw sysroot and the prefixes given on the command
# line (CMAKE_PREFIX_PATH), never from the host's /usr; programs (protoc) from the host.
set(CMAKE_FIND_ROOT_PATH /usr/${DEMLINK_MINGW_TRIPLET})
set(CMAKE_FIND_ROOT_PATH_MODE_PROGRAM NEVER)
set(CMAKE_FIND_ROOT_PATH_MODE_LIBRARY ONLY)
set(CMAKE_FIND_ROOT_PATH_MODE_INCLUDE ONLY)
set(CMAKE_FIND_ROOT_PATH_MODE_PACKAGE ONLY)

set(CMAKE_EXE_LINKER_FLAGS_INIT -static)
set(CMAKE_SHARED_LINKER_FLAGS_INIT -static)
set(CMAKE_MODULE_LINKER_FLAGS_INIT -static)
