# Sourced by the scripts that run demlink-server as a child process with `--port 0 --once`
# (scripts/demo_cosim.sh, tests/examples/*.sh, tests/python/run_with_server.sh): the port
# is only known once the server prints "listening on ADDR:PORT", and the server exits by
# itself after its one simulation. Every wait here is bounded.

# wait_for_server_port LOG PID [SECONDS]
#   Prints the port once LOG has the line and returns 0; returns 1 when PID exits without
#   it or SECONDS (default 10) pass.
wait_for_server_port() {
  local log=$1 pid=$2 limit=${3:-10} line tick
  for ((tick = 0; tick <= limit * 10; ++tick)); do
    if line=$(grep -m1 -oE 'listening on [^ ]+:[0-9]+' "$log" 2>/dev/null); then
      echo "${line##*:}"
      return 0
    fi
    # Exited: one more look (it may have printed the line just before), then give up.
    if ! kill -0 "$pid" 2>/dev/null; then
      line=$(grep -m1 -oE 'listening on [^ ]+:[0-9]+' "$log" 2>/dev/null) || return 1
      echo "${line##*:}"
      return 0
    fi
    sleep 0.1
  done
  return 1
}

# wait_for_server_exit PID [SECONDS]
#   Waits up to SECONDS (default 20) for the child PID to exit; returns its exit status, or
#   124 if it is still running (then stop it with stop_server). Call it in the shell that
#   started the child (not in $(...)), so `wait` can collect the status.
wait_for_server_exit() {
  local pid=$1 limit=${2:-20} tick
  for ((tick = 0; tick < limit * 10; ++tick)); do
    kill -0 "$pid" 2>/dev/null || break
    sleep 0.1
  done
  kill -0 "$pid" 2>/dev/null && return 124
  wait "$pid"
}

# stop_server PID
#   SIGTERM (the server flushes its outputs), SIGKILL after 0.5 s; nothing if PID is gone
#   or empty. For the scripts' EXIT traps.
stop_server() {
  local pid=$1
  [[ -n "$pid" ]] && kill -0 "$pid" 2>/dev/null || return 0
  kill "$pid" 2>/dev/null || true
  sleep 0.5
  kill -9 "$pid" 2>/dev/null || true
}
