#!/usr/bin/env bash
# Builds the protobuf runtime for the win64 cross build (scripts/build_win64.sh) from
# Debian's own source package, the same version as the host's protoc, so the code that
# protoc generates matches the runtime it is linked with. Only libprotobuf is built
# (static, no tests, no protoc): the client's generated code and its reflection need the
# full runtime, not just protobuf-lite.
#   scripts/win64_protobuf.sh [PREFIX]   (default build/third_party/protobuf-win64)
# The result is cached: a second run with the same version only checks the stamp.
# Fetching the source needs a deb-src entry: scripts/lib/ensure_deb_src.sh adds one for
# bookworm when none is configured.
set -euo pipefail
cd "$(dirname "$0")/.."
root=$PWD
prefix=$(realpath -m "${1:-build/third_party/protobuf-win64}")
work=$root/build/third_party
toolchain=$root/cmake/mingw-w64-x86_64.cmake

version=$(dpkg-query -W -f='${source:Version}' libprotobuf-dev 2>/dev/null || true)
if [[ -z "$version" ]]; then
  echo "win64_protobuf: libprotobuf-dev is not installed (scripts/install_deps.sh)" >&2
  exit 1
fi
if [[ -f "$prefix/demlink-stamp" && "$(cat "$prefix/demlink-stamp")" == "$version" ]]; then
  echo "win64_protobuf: protobuf $version for win64 already in $prefix"
  exit 0
fi

upstream=${version#*:}
upstream=${upstream%-*}
source_dir=$work/src/protobuf-$upstream
if [[ ! -f "$source_dir/CMakeLists.txt" ]]; then
  scripts/lib/ensure_deb_src.sh
  rm -rf "$work/src"
  mkdir -p "$work/src"
  (cd "$work/src" && apt-get source -qq "protobuf=$version")
fi

build_dir=$work/protobuf-win64-build
cmake -S "$source_dir" -B "$build_dir" -G Ninja -DCMAKE_TOOLCHAIN_FILE="$toolchain" -DCMAKE_BUILD_TYPE=Release \
  -Dprotobuf_BUILD_TESTS=OFF -Dprotobuf_BUILD_PROTOC_BINARIES=OFF -Dprotobuf_BUILD_SHARED_LIBS=OFF \
  -Dprotobuf_WITH_ZLIB=OFF -Dprotobuf_MSVC_STATIC_RUNTIME=OFF > "$build_dir.log" 2>&1 || {
  cat "$build_dir.log" >&2
  exit 1
}
cmake --build "$build_dir" --target libprotobuf

# The prefix: the headers from the source tree, the one archive.
rm -rf "$prefix"
mkdir -p "$prefix/lib" "$prefix/include"
(cd "$source_dir/src" && find google \( -name '*.h' -o -name '*.inc' \) -print0 | xargs -0 cp --parents -t "$prefix/include")
cp "$build_dir/libprotobuf.a" "$prefix/lib/libprotobuf.a"
echo "$version" > "$prefix/demlink-stamp"
echo "win64_protobuf: protobuf $version for win64 in $prefix"
