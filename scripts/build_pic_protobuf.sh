#!/usr/bin/env bash
# Builds the installed Debian protobuf's own source (`apt-get source`, same version as the
# headers and protoc the project compiles with) as a static, position-independent
# libprotobuf.a. Debian's libprotobuf.a is not PIC (its thread-local arena cache uses
# R_X86_64_TPOFF32), so it cannot go into a shared object; with this archive the FMU's
# library and libdemlink_c carry protobuf inside and need nothing but libc (docs/fmi.md,
# "Self-contained binaries"). Nothing is kept in the repository: the source is fetched
# into the work directory.
#   scripts/build_pic_protobuf.sh [PREFIX]     default build/pic-protobuf
# then configure with -DDEMLINK_PIC_PROTOBUF=PREFIX/lib/libprotobuf.a (scripts/build.sh
# and CMakePresets.json pass it when the file exists).
set -euo pipefail
cd "$(dirname "$0")/.."
prefix=$(realpath -m "${1:-build/pic-protobuf}")
if [[ -f $prefix/lib/libprotobuf.a ]]; then
  echo "PIC protobuf already at $prefix/lib/libprotobuf.a"
  exit 0
fi
version=$(dpkg-query -W -f='${Version}' libprotobuf-dev)
work=$prefix/src
mkdir -p "$work"
(cd "$work" && apt-get source --only-source "protobuf=$version" >/dev/null)
source_dir=$(find "$work" -maxdepth 1 -type d -name 'protobuf-*' | head -n 1)
cmake -S "$source_dir/cmake" -B "$work/build" -G Ninja -DCMAKE_BUILD_TYPE=Release \
  -DCMAKE_POSITION_INDEPENDENT_CODE=ON -DCMAKE_CXX_VISIBILITY_PRESET=hidden -DCMAKE_VISIBILITY_INLINES_HIDDEN=ON \
  -Dprotobuf_BUILD_TESTS=OFF -Dprotobuf_BUILD_PROTOC_BINARIES=OFF -Dprotobuf_BUILD_SHARED_LIBS=OFF \
  -Dprotobuf_WITH_ZLIB=OFF -DCMAKE_INSTALL_PREFIX="$prefix" \
  ${CMAKE_CXX_COMPILER_LAUNCHER:+-DCMAKE_CXX_COMPILER_LAUNCHER=$CMAKE_CXX_COMPILER_LAUNCHER}
cmake --build "$work/build" --target libprotobuf
mkdir -p "$prefix/lib"
cp "$work/build/libprotobuf.a" "$prefix/lib/libprotobuf.a"
echo "PIC protobuf: $prefix/lib/libprotobuf.a"
