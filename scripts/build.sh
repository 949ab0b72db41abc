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
cmake --preset "$preset" -G Ninja
if (($# > 0)); then
  cmake --build --preset "$preset" --target "$@"
else
  cmake --build --preset "$preset"
fi
