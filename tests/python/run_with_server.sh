#!/usr/bin/env bash
# Starts a demlink-server on an ephemeral loopback port, runs a Python client script
# against it, and checks both exit codes.
#
# Why a wrapper: ctest runs one command per test; the Python client needs a live server
# whose port is only known once it listens. The server is started with `--port 0 --once`
# (serve one simulation, then exit) and prints "listening on ADDR:PORT"; the wrapper
# reads that line, runs the client, then waits for the server to exit by itself. Every
# wait is bounded (`timeout`), and the trap kills the server on any exit, so a bug
# fails the test instead of hanging it or leaving a server behind.
#
# Usage: run_with_server.sh SERVER_EXE PYTHON SCRIPT [script args...]
#   The script gets --host 127.0.0.1 --port PORT appended.
# Environment: DEMLINK_TEST_TIMEOUT (seconds for the client, default 60).
set -euo pipefail

if (($# < 3)); then
  echo "usage: $0 SERVER_EXE PYTHON SCRIPT [args...]" >&2
  exit 2
fi
server_exe=$1
if [[ "$server_exe" == */* ]]; then server_exe=$(realpath "$server_exe"); fi
python=$2
script=$3
shift 3
client_timeout=${DEMLINK_TEST_TIMEOUT:-60}

workdir=$(mktemp -d "${TMPDIR:-/tmp}/demlink_pytest.XXXXXX")
server_log=$workdir/server.log
server_pid=""
source "$(dirname "$0")/../../scripts/lib/child_server.sh"
cleanup() {
  stop_server "$server_pid"
  rm -rf "$workdir"
}
trap cleanup EXIT

# The server writes its simulation output below its working directory.
(cd "$workdir" && exec "$server_exe" --port 0 --once) >"$server_log" 2>&1 &
server_pid=$!

if ! port=$(wait_for_server_port "$server_log" "$server_pid"); then
  echo "run_with_server: the server did not print 'listening on ADDR:PORT' within 10 s; its output:" >&2
  cat "$server_log" >&2
  exit 1
fi
echo "run_with_server: server pid $server_pid listening on 127.0.0.1:$port"

client_status=0
timeout --kill-after=5 "$client_timeout" "$python" "$script" "$@" --host 127.0.0.1 --port "$port" ||
  client_status=$?
if ((client_status == 124)); then
  echo "run_with_server: the client did not finish within ${client_timeout} s" >&2
fi

# --once: the server exits by itself after the simulation; 20 s at most (else the trap
# stops it).
server_status=0
wait_for_server_exit "$server_pid" 20 || server_status=$?
if ((server_status == 124)); then
  echo "run_with_server: the server did not exit within 20 s after the client" >&2
fi

echo "---- server output ----"
cat "$server_log"
echo "-----------------------"
if ((client_status != 0 || server_status != 0)); then
  echo "run_with_server: FAILED (client exit $client_status, server exit $server_status)" >&2
  exit 1
fi
echo "run_with_server: client and server exited 0"
