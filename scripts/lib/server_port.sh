# Sourced by the scripts that start demlink-server as a child process with `--port 0`
# (scripts/demo_cosim.sh, tests/examples/*.sh, tests/python/run_with_server.sh): the port
# is only known once the server prints "listening on ADDR:PORT".
#
# wait_for_server_port LOG PID [SECONDS]
#   Prints the port once LOG has the line and returns 0; returns 1 when PID exits without
#   it or SECONDS (default 10) pass. Never waits longer.
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
