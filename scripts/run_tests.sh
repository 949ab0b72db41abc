#!/usr/bin/env bash
# Builds DEMLink (scripts/build.sh) and runs every test. This is the README's test
# command and what CI runs (.ci/run). Warnings are errors in this build.
#   scripts/run_tests.sh           release build, all tests
#   scripts/run_tests.sh --asan    AddressSanitizer + UBSan build, all tests
# The release run then fuzzes the frame decoder and the co-simulation host for a
# bounded time (scripts/run_fuzz.sh; DEMLINK_FUZZ_SECONDS per target, default 30 here);
# any crash fails the run.
set -euo pipefail
cd "$(dirname "$0")/.."
preset=release
if [[ "${1:-}" == "--asan" ]]; then preset=asan; fi

scripts/install_deps.sh
scripts/build.sh "$preset"
ctest --preset "$preset"
if [[ "$preset" == release ]]; then
  DEMLINK_FUZZ_SECONDS="${DEMLINK_FUZZ_SECONDS:-30}" scripts/run_fuzz.sh
fi
