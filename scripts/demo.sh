#!/usr/bin/env bash
# Installs what is missing, builds DEMLink and runs the main demo: a headless
# deposition scene with progress output, VTK (ParaView) and CSV results.
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/install_deps.sh
cmake --preset release -G Ninja
cmake --build --preset release
out="${1:-out/deposition}"
./build/release/server/demlink-run examples/scenes/deposition_small.json --output "$out"
echo "Results in $out (open $out/particles.pvd in ParaView)."
