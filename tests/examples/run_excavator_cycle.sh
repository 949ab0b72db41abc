#!/usr/bin/env bash
# One dig-dump cycle of demlink-excavator against a real demlink-server (child process,
# --port 0 --once) on a small site scene, then check_excavator_run.py judges the CSV.
#
# Why a smaller scene: the full 6 m pit (4400 particles, 18 s to generate) takes minutes
# per cycle; this one keeps the site's pit depth and width but is 1.6 m long (the bucket is
# 1.2 m wide), with a 1/3 ms time step (70 % of the critical step). Every wait is bounded.
# usage: run_excavator_cycle.sh SERVER_EXE EXCAVATOR_EXE SCENE CHECKER WORKDIR
set -euo pipefail
# Sanitizer builds run several times slower: their tests set DEMLINK_TEST_TIME_SCALE.
scale=${DEMLINK_TEST_TIME_SCALE:-1}
server_exe=$1 excavator_exe=$2 scene=$3 checker=$4 work=$5
rm -rf "$work" && mkdir -p "$work"
timeout $((600 * scale)) "$server_exe" --port 0 --once --scene "$scene" --output "$work/server" --timeout $((60 * scale)) \
  >"$work/server.log" 2>&1 &
server_pid=$!
trap 'kill "$server_pid" 2>/dev/null || true' EXIT
source "$(dirname "$0")/../../scripts/lib/child_server.sh"
if ! port=$(wait_for_server_port "$work/server.log" "$server_pid"); then
  echo "FAIL: the server did not start listening:"; cat "$work/server.log"; exit 1
fi
# The excavator waits up to 180 s for Compiled: generating the pit took over 60 s on a
# machine loaded by parallel builds.
status=0
timeout $((590 * scale)) "$excavator_exe" --host 127.0.0.1 --port "$port" --cycles 1 --output "$work/excavator" --timeout $((180 * scale)) \
  >"$work/excavator.log" 2>&1 || status=$?
wait "$server_pid" || { echo "FAIL: server exit $?"; tail -20 "$work/server.log"; exit 1; }
trap - EXIT
if [[ $status -ne 0 ]]; then
  echo "FAIL: excavator exit $status"; tail -20 "$work/excavator.log"; tail -20 "$work/server.log"; exit 1
fi
grep -E "cycle 1:|mass dumped" "$work/excavator.log"
python3 "$checker" "$work/excavator/excavator.csv"
