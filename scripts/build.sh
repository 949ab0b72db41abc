#!/usr/bin/env bash
# Configures and builds DEMLink with one CMake preset (default release; warnings are
# errors). The one build step shared by CI (scripts/run_tests.sh) and the container images
# (docker/Dockerfile.*), so what CI tests is what the images contain. Expects the
# packages of scripts/install_deps.sh to be installed.
#   scripts/build.sh            release build in build/release
#   scripts/build.sh asan       AddressSanitizer + UBSan build in build/asan
set -euo pipefail
cd "$(dirname "$0")/.."
preset=${1:-release}
cmake --preset "$preset" -G Ninja
cmake --build --preset "$preset"
