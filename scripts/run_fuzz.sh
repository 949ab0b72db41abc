#!/usr/bin/env bash
# Builds the libFuzzer targets with clang in build/fuzz and runs each for a bounded time,
# starting from a seed corpus the fuzzers generate themselves (DEMLINK_FUZZ_WRITE_SEEDS).
# Exits non-zero if a target fails to build or any fuzzer finds a crash, a sanitizer
# report, a leak or an input that hangs; the input is kept as build/fuzz/artifacts/<target>-*.
#   scripts/run_fuzz.sh                        60 s per target
#   DEMLINK_FUZZ_SECONDS=600 scripts/run_fuzz.sh
#   scripts/run_fuzz.sh fuzz_frame_decoder     one target only
set -euo pipefail
cd "$(dirname "$0")/.."
seconds=${DEMLINK_FUZZ_SECONDS:-60}
build=build/fuzz

# -Werror stays with the gcc builds (scripts/run_tests.sh): clang's warning set differs, and
# this build exists to find crashes, not to gate style.
cmake -S . -B "$build" -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo \
  -DCMAKE_CXX_COMPILER=clang++ -DDEMLINK_FUZZ=ON -DDEMLINK_WARNINGS_AS_ERRORS=OFF >/dev/null

if (($# > 0)); then
  targets=("$@")
else
  targets=(fuzz_frame_decoder fuzz_cosim_host fuzz_scene_translator)
fi
cmake --build "$build" -j2 --target "${targets[@]}"

mkdir -p "$build/artifacts"
status=0
for target in "${targets[@]}"; do
  corpus="$build/corpus/$target"
  DEMLINK_FUZZ_WRITE_SEEDS="$corpus" "$build/tests/fuzz/$target"
  echo "run_fuzz: $target for ${seconds} s"
  # -timeout: one input running longer than this counts as a hang (a failure).
  if ! "$build/tests/fuzz/$target" -max_total_time="$seconds" -timeout=30 -print_final_stats=1 \
      -artifact_prefix="$build/artifacts/$target-" "$corpus"; then
    echo "run_fuzz: $target FAILED (see $build/artifacts/)" >&2
    status=1
  fi
done
exit "$status"
