#!/usr/bin/env bash
# Configures and builds DEMLink with one CMake preset (default release; warnings are
# errors). The one build step shared by CI (scripts/run_tests.sh) and the container images
# (docker/Dockerfile.*), so what CI tests is what the images contain. Expects the
# packages of scripts/install_deps.sh to be installed.
#   scripts/build.sh            release build in build/release
#   scripts/build.sh asan       AddressSanitizer + UBSan build in build/asan
#   scripts/build.sh release demlink_server ...   only these targets (scripts/demo.sh)
set -euo pipefail
cd "$(dirname "$0")/.."
preset=${1:-release}
shift || true
# The self-contained C ABI and FMU libraries need a position-independent libprotobuf.a
# (docs/fmi.md, "Self-contained binaries"); without deb-src apt sources the build goes on
# with libraries that need the system's libprotobuf and libstdc++.
scripts/build_pic_protobuf.sh || echo "warning: no PIC protobuf: the C ABI and FMU libraries are not self-contained" >&2
cmake --preset "$preset" -G Ninja
if (($# > 0)); then
  cmake --build --preset "$preset" --target "$@"
else
  cmake --build --preset "$preset"
fi
