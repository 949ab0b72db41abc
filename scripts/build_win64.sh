#!/usr/bin/env bash
# Cross-builds the win64 client side (cmake/Win64Client.cmake) with Debian's mingw-w64:
# demlink_c.dll, the FMU library demlink_fmu.dll and the test programs fmu_master.exe and
# fmu_load_check.exe, each linked statically (only Windows system DLLs). Installs nothing:
# expects the packages of scripts/install_deps.sh. The protobuf runtime comes from
# scripts/win64_protobuf.sh (cached in build/third_party/protobuf-win64).
#   scripts/build_win64.sh [BUILD_DIR]   (default build/win64)
# The release build runs this into <build>/win64 when DEMLINK_WIN64 is on (cmake/Win64.cmake).
set -euo pipefail
cd "$(dirname "$0")/.."
build_dir=$(realpath -m "${1:-build/win64}")
prefix=$PWD/build/third_party/protobuf-win64

scripts/win64_protobuf.sh "$prefix"
if [[ ! -f "$build_dir/CMakeCache.txt" ]]; then
  cmake -S . -B "$build_dir" -G Ninja -DCMAKE_TOOLCHAIN_FILE="$PWD/cmake/mingw-w64-x86_64.cmake" \
    -DCMAKE_BUILD_TYPE=Release -DDEMLINK_WARNINGS_AS_ERRORS=ON \
    -DProtobuf_INCLUDE_DIR="$prefix/include" -DProtobuf_LIBRARY="$prefix/lib/libprotobuf.a" \
    -DProtobuf_PROTOC_EXECUTABLE="$(command -v protoc)"
fi
cmake --build "$build_dir"
