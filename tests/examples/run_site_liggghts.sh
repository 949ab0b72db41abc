#!/usr/bin/env bash
# The excavator-and-truck site, shortened, on the LIGGGHTS backend under `mpirun -np 2`:
# demlink-server --backend liggghts (rank 0 serves, rank 1 mirrors), demlink-truck
# --stand-still and demlink-excavator as child processes, then check_site_liggghts.py.
#
# Why shortened: the site with a 1.6 m pit (make_site_scene.py --pit-half-x 0.8, about
# 1,100 particles) and the excavator stopped at 8.8 s (--stop-at), when it has dug, curled
# and lifted its first load out of the pit: every part of the coupling has run (FIXED facet
# bodies, the pit generator's bed, the bucket's moving mesh and its wrench, the fill sensor
# riding on it, the truck's body and load sensor) in about half the time of the whole
# cycle (scripts/demo_cosim.sh --backend liggghts --ranks 2 --small: 504 s on 2 cores,
# docs/scale-out.md). Every wait is bounded.
# usage: run_site_liggghts.sh SERVER_EXE TRUCK_EXE EXCAVATOR_EXE MPIEXEC SOURCE_DIR WORKDIR
set -euo pipefail
scale=${DEMLINK_TEST_TIME_SCALE:-1}
server_exe=$1 truck_exe=$2 excavator_exe=$3 mpiexec=$4 source_dir=$5 work=$6
stop_at=8.8
rm -rf "$work" && mkdir -p "$work"
python3 "$source_dir/examples/cosim/make_site_scene.py" --pit-half-x 0.8 --output "$work/site_scene_small.json"
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
timeout $((1700 * scale)) "$mpiexec" --oversubscribe -np 2 "$server_exe" --backend liggghts --port 0 --once \
  --scene "$work/site_scene_small.json" --output "$work/server" --timeout $((600 * scale)) >"$work/server.log" 2>&1 &
server_pid=$!
source "$source_dir/scripts/lib/child_server.sh"
trap 'stop_server "$server_pid"' EXIT
if ! port=$(wait_for_server_port "$work/server.log" "$server_pid" 120); then
  echo "FAIL: the server did not start listening:"; cat "$work/server.log"; exit 1
fi
# The truck is loaded by nothing before the stop: it stands still, holds and says Bye at
# --max-time; the excavator says Bye at --stop-at.
timeout $((1600 * scale)) "$truck_exe" --port "$port" --stand-still --max-time "$stop_at" --output "$work/truck" \
  --timeout $((900 * scale)) >"$work/truck.log" 2>&1 &
truck_pid=$!
status=0
timeout $((1600 * scale)) "$excavator_exe" --port "$port" --cycles 1 --stop-at "$stop_at" --output "$work/excavator" \
  --timeout $((900 * scale)) >"$work/excavator.log" 2>&1 || status=$?
truck_status=0
wait "$truck_pid" || truck_status=$?
server_status=0
wait_for_server_exit "$server_pid" $((60 * scale)) || server_status=$?
trap - EXIT
tail -3 "$work/truck.log"
grep -E "simulated in|mass dumped" "$work/excavator.log" || true
if ((status != 0 || truck_status != 0 || server_status != 0)); then
  echo "FAIL: excavator exit $status, truck exit $truck_status, server exit $server_status"
  tail -20 "$work/excavator.log"; tail -20 "$work/truck.log"; tail -30 "$work/server.log"
  stop_server "$server_pid"
  exit 1
fi
python3 "$source_dir/tests/examples/check_site_liggghts.py" "$work"
