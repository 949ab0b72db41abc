#!/usr/bin/env bash
# The README's first command: installs what is missing (Debian packages only), builds
# DEMLink and runs the main demo — the excavator-and-truck co-simulation, headless on this
# machine: demlink-server plus the two system-model clients (excavator: C++ client library;
# truck: C ABI) over loopback, with progress lines, VTK for ParaView, CSV, PNG plots and a
# summary (mass dug, delivered, peak cylinder force, mass balance) in one folder.
#   scripts/demo.sh [OUT_DIR] [CYCLES] [--view PORT]   (defaults: out/cosim_demo, 2, no view)
# --view PORT also serves a live 3D view in the browser and prints its address (docs/view.md).
# It also builds demlink-run (one more link over the same libraries), so the README's next
# command, a headless scene, runs right after:
#   build/release/server/demlink-run examples/scenes/deposition_small.json --output out/dep
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/install_deps.sh
# What the demo runs, and demlink-run (scripts/run_tests.sh builds the rest).
scripts/build.sh release demlink_server demlink-truck demlink_excavator demlink_run
exec scripts/demo_cosim.sh "$@"
