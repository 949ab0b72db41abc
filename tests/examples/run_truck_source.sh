#!/usr/bin/env bash
# The truck's `source` scenario end to end: a real demlink-server (`--port 0 --once`, a
# ground-only scene) and demlink-truck as child processes, then truck_csv_check on the
# truck's CSV.
#
# Why a script: ctest runs one command; the truck needs a live server whose port is only
# known once it listens. Every wait is bounded (`timeout`, polling loops), and the trap
# kills the server by its pid on any exit, so a bug fails the test instead of hanging it.
#
# Usage: run_truck_source.sh SERVER_EXE TRUCK_EXE CHECK_EXE SCENE_FILE
set -euo pipefail
# Sanitizer builds run several times slower: their tests set DEMLINK_TEST_TIME_SCALE.
scale=${DEMLINK_TEST_TIME_SCALE:-1}
if (($# != 4)); then
  echo "usage: $0 SERVER_EXE TRUCK_EXE CHECK_EXE SCENE_FILE" >&2
  exit 2
fi
server_exe=$(realpath "$1")
truck_exe=$(realpath "$2")
check_exe=$(realpath "$3")
scene=$(realpath "$4")
load_target=300

workdir=$(mktemp -d "${TMPDIR:-/tmp}/demlink_truck.XXXXXX")
server_pid=""
source "$(dirname "$0")/../../scripts/lib/child_server.sh"
cleanup() {
  stop_server "$server_pid"
  rm -rf "$workdir"
}
trap cleanup EXIT

(cd "$workdir" && exec timeout --kill-after=5 $((90 * scale)) "$server_exe" --port 0 --once --scene "$scene" --output server_out) \
  >"$workdir/server.log" 2>&1 &
server_pid=$!
if ! port=$(wait_for_server_port "$workdir/server.log" "$server_pid"); then
  echo "run_truck_source: the server did not listen within 10 s:" >&2
  cat "$workdir/server.log" >&2
  exit 1
fi

truck_status=0
timeout --kill-after=5 $((60 * scale)) "$truck_exe" --port "$port" --scenario source --output "$workdir/truck" \
  --load-target "$load_target" --source-rate 400 --body-mass 1000 --drive-time 1.5 || truck_status=$?

# --once: the server exits by itself; 20 s at most (else the trap stops it).
server_status=0
wait_for_server_exit "$server_pid" 20 || server_status=$?
if ((server_status == 124)); then
  echo "run_truck_source: the server did not exit within 20 s after the truck" >&2
fi
echo "---- server output ----"
tail -n 25 "$workdir/server.log"
echo "-----------------------"
if ((truck_status != 0 || server_status != 0)); then
  echo "run_truck_source: FAILED (truck exit $truck_status, server exit $server_status)" >&2
  exit 1
fi
"$check_exe" "$workdir/truck/truck.csv" "$load_target"
