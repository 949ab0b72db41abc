#!/usr/bin/env bash
# Builds DEMLink and runs every test. This is the README's test command and what
# CI runs (.ci/run). Warnings are errors in this build.
#   scripts/run_tests.sh           release build, all tests
#   scripts/run_tests.sh --asan    AddressSanitizer + UBSan build, all tests
set -euo pipefail
cd "$(dirname "$0")/.."
preset=release
if [[ "${1:-}" == "--asan" ]]; then preset=asan; fi

scripts/install_deps.sh
cmake --preset "$preset" -G Ninja
cmake --build --preset "$preset"
ctest --preset "$preset"
