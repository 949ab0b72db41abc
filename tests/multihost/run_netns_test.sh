#!/usr/bin/env bash
# The co-simulation across three hosts, emulated with Linux network namespaces, compared
# with the same co-simulation over loopback.
#
# Why namespaces: the server and its two clients must talk over a real network path
# (their own addresses, a link between them), not loopback, and CI has one machine and
# no container engine. Three namespaces (server, client A, client B) are three network
# stacks: each client namespace is joined by a veth pair to a bridge inside the server
# namespace (a star; nothing is added to the machine's own network namespace):
#
#     [ns A] eth0 10.77.0.2 ---- va \
#                                     br0 10.77.0.1 [ns server]: demlink-server --listen 10.77.0.1
#     [ns B] eth0 10.77.0.3 ---- vb /
#
# The server listens only on 10.77.0.1 inside its namespace, so a client reaching it went
# over the veth links. Then the same run over loopback in the machine's namespace, and the
# results must be equal: checkpoint_final.bin bit for bit (the co-simulation is
# deterministic given the same packages), the sensor CSVs and COMPARE_FILES byte for byte;
# optionally a mass balance over CSVs (scripts/check_mass_balance.py) in both runs.
#
# Usage: run_netns_test.sh SERVER_EXE SCENE_FILE
# Environment:
#   CLIENT_A_CMD, CLIENT_B_CMD  client commands, run with `bash -c` in their own working
#       directory (client_a/, client_b/ of the run) with DEMLINK_HOST, DEMLINK_PORT and
#       DEMLINK_TOKEN exported. Defaults: the demo's clients, A = demlink-truck (it
#       declares the SimulationBox), B = demlink-excavator, each with
#       --host "$DEMLINK_HOST" --port "$DEMLINK_PORT" --output . (on PATH).
#   CLIENT_A_READY  extended regular expression; client B starts only once the server's
#       log matches it (e.g. 'declared "a_ram"', A's last declaration). The compiler takes
#       declarations in arrival order, so without it the order of the two clients'
#       components, and with it the bits of the result, may differ between runs.
#   COMPARE_FILES  more files to compare between the runs, relative to a run directory
#       (server/sim_001/..., client_a/..., client_b/...), space-separated.
#   MASS_BALANCE_ARGS  arguments of the mass-balance script, run in each run directory
#       (paths relative to it, space-separated, no quoting).
#   MASS_BALANCE_SCRIPT  that script, in scripts/ (default check_mass_balance.py; the
#       excavator-and-truck site uses cosim_summary.py, which also checks bucket -> truck).
#   DEMLINK_TOKEN  access token the server requires (it reads the variable) and the client
#       commands should pass on (default: a fixed test token; set it empty for none).
#   DEMLINK_NETNS_TIMEOUT  seconds each client may take (default 240).
#   DEMLINK_NETNS_KEEP  keep the outputs in this directory (default: removed).
#   PYTHON  interpreter for check_mass_balance.py (default python3).
# Exit codes: 0 passed; 1 failed (says what); 2 usage; 77 skipped, with the reason
# printed (no `ip`, no privilege to create namespaces, a container that forbids them) -
# ctest maps 77 to SKIPPED (SKIP_RETURN_CODE), so it is never a silent pass.
set -euo pipefail

readonly kSkip=77
readonly kServerAddress=10.77.0.1
readonly kClientAAddress=10.77.0.2
readonly kClientBAddress=10.77.0.3
readonly kPort=47000  # fixed: the server's namespace is private to this run

if (($# != 2)); then
  echo "usage: $0 SERVER_EXE SCENE_FILE" >&2
  exit 2
fi
server_exe=$(realpath "$1")
scene=$(realpath "$2")
here=$(cd "$(dirname "$0")" && pwd)
repo=$(cd "$here/../.." && pwd)
client_timeout=${DEMLINK_NETNS_TIMEOUT:-240}
server_timeout=$((client_timeout + 60))
python=${PYTHON:-python3}
export DEMLINK_TOKEN=${DEMLINK_TOKEN-netns-test-token}  # set it empty for no token
client_a_cmd=${CLIENT_A_CMD:-'demlink-truck --host "$DEMLINK_HOST" --port "$DEMLINK_PORT" --output .'}
client_b_cmd=${CLIENT_B_CMD:-'demlink-excavator --host "$DEMLINK_HOST" --port "$DEMLINK_PORT" --output .'}
client_a_ready=${CLIENT_A_READY:-}
if [[ -z "$client_a_ready" ]]; then
  echo "run_netns_test: warning: CLIENT_A_READY is not set; both clients start at once, so the" \
       "order of their declarations, and the result's bits, may differ between the runs" >&2
fi

skip() {
  echo "SKIPPED: $*"
  exit "$kSkip"
}
fail() {
  echo "run_netns_test: FAILED: $*" >&2
  exit 1
}
log() { echo "run_netns_test: $*"; }

# --- Cleanup: every exit path (trap), only what this script started ---------------------
ns_prefix="dlk$$"
ns_server="${ns_prefix}_s" ns_a="${ns_prefix}_a" ns_b="${ns_prefix}_b"
created_ns=()
pids=()
workdir=""
cleanup() {
  local status=$?
  local pid ns
  for pid in "${pids[@]}"; do
    kill -0 "$pid" 2>/dev/null && kill -TERM "$pid" 2>/dev/null || true
  done
  for pid in "${pids[@]}"; do
    for _ in $(seq 1 30); do kill -0 "$pid" 2>/dev/null || break; sleep 0.1; done
    kill -0 "$pid" 2>/dev/null && kill -KILL "$pid" 2>/dev/null || true
  done
  for ns in "${created_ns[@]}"; do
    # Anything still inside this run's namespaces was started by this run.
    for pid in $(ip netns pids "$ns" 2>/dev/null); do kill -KILL "$pid" 2>/dev/null || true; done
    ip netns del "$ns" 2>/dev/null || echo "run_netns_test: could not delete namespace $ns" >&2
  done
  if [[ -n "$workdir" && -z "${DEMLINK_NETNS_KEEP:-}" ]]; then rm -rf "$workdir"; fi
  exit "$status"
}
trap cleanup EXIT
trap 'exit 130' INT TERM HUP

# --- Can namespaces be made here? -----------------------------------------------------
command -v ip >/dev/null 2>&1 || skip "no 'ip' binary (install Debian's iproute2: scripts/install_deps.sh)"
command -v timeout >/dev/null 2>&1 || fail "no 'timeout' binary (coreutils)"
[[ -x "$server_exe" ]] || fail "server executable '$1' not found or not executable"
[[ -f "$scene" ]] || fail "scene file '$2' not found"

# Namespaces left by an earlier run of this script that was killed (SIGKILL skips the trap).
for ns in $(ip netns list 2>/dev/null | grep -oE '^dlk[0-9]+_[sab]' || true); do
  owner=${ns#dlk}; owner=${owner%_*}
  if ! kill -0 "$owner" 2>/dev/null; then
    log "removing stale namespace $ns of a killed run (pid $owner)"
    ip netns del "$ns" 2>/dev/null || true
  fi
done

if ! why=$(ip netns add "$ns_server" 2>&1); then
  skip "cannot create a network namespace (uid $(id -u); needs root or CAP_NET_ADMIN, and a" \
       "kernel/container that allows it): ip netns add: $why"
fi
created_ns+=("$ns_server")
if ! why=$(ip netns exec "$ns_server" true 2>&1); then
  skip "a namespace was created but 'ip netns exec' fails (container forbids the mounts?): $why"
fi
ip netns add "$ns_a" || fail "ip netns add $ns_a"
created_ns+=("$ns_a")
ip netns add "$ns_b" || fail "ip netns add $ns_b"
created_ns+=("$ns_b")

# --- The network: a bridge in the server namespace, one veth pair per client ----------
if ! why=$(ip -n "$ns_server" link add br0 type bridge 2>&1); then
  skip "namespaces work but a bridge cannot be created (no bridge support in this kernel?): $why"
fi
setup_client_link() {  # namespace, server-side name, address (set -e is off in `f || fail`)
  ip -n "$1" link add eth0 type veth peer name "$2" netns "$ns_server" &&
    ip -n "$ns_server" link set "$2" master br0 &&
    ip -n "$ns_server" link set "$2" up &&
    ip -n "$1" addr add "$3/24" dev eth0 &&
    ip -n "$1" link set eth0 up &&
    ip -n "$1" link set lo up
}
setup_client_link "$ns_a" va "$kClientAAddress" || fail "veth pair for $ns_a"
setup_client_link "$ns_b" vb "$kClientBAddress" || fail "veth pair for $ns_b"
ip -n "$ns_server" addr add "$kServerAddress/24" dev br0 || fail "address of br0"
ip -n "$ns_server" link set br0 up || fail "br0 up"
ip -n "$ns_server" link set lo up || fail "lo up in $ns_server"
log "namespaces $ns_server ($kServerAddress), $ns_a ($kClientAAddress), $ns_b ($kClientBAddress)"

workdir=$(mktemp -d "${TMPDIR:-/tmp}/demlink_netns.XXXXXX")
if [[ -n "${DEMLINK_NETNS_KEEP:-}" ]]; then
  mkdir -p "$DEMLINK_NETNS_KEEP"
  rm -rf "$workdir"
  workdir=$(realpath "$DEMLINK_NETNS_KEEP")
fi

# --- One co-simulation: server + two clients ------------------------------------------
# start LOG NETNS|"" DIR CMD...: runs CMD in DIR (inside NETNS if given), output to LOG;
# sets started_pid. Every command is bounded by `timeout` by the callers.
start() {
  local log_file=$1 ns=$2 dir=$3
  shift 3
  local prefix=()
  if [[ -n "$ns" ]]; then prefix=(ip netns exec "$ns"); fi
  (cd "$dir" && exec "${prefix[@]}" "$@") >"$log_file" 2>&1 &
  started_pid=$!
  pids+=("$started_pid")
}
# wait_for_pattern LOG ERE PID SECONDS: the log matches, or fail if PID died / time is up.
wait_for_pattern() {
  local waited=0
  while ! grep -qE "$2" "$1" 2>/dev/null; do
    kill -0 "$3" 2>/dev/null || { cat "$1" >&2; fail "process $3 exited before its log matched '$2'"; }
    ((waited++ < $4 * 10)) || { cat "$1" >&2; fail "'$2' not in $1 within $4 s"; }
    sleep 0.1
  done
}
run_cosim() {  # mode (netns|loopback) -> $workdir/mode/{server,client_a,client_b,*.log}
  local mode=$1 dir=$workdir/$1
  local ns_s="" ns_ca="" ns_cb="" listen=127.0.0.1 port=0
  if [[ "$mode" == netns ]]; then
    ns_s=$ns_server ns_ca=$ns_a ns_cb=$ns_b listen=$kServerAddress port=$kPort
  fi
  rm -rf "$dir"
  mkdir -p "$dir/client_a" "$dir/client_b"
  local began=$SECONDS
  start "$dir/server.log" "$ns_s" "$dir" timeout --kill-after=10 "$server_timeout" "$server_exe" \
    --listen "$listen" --port "$port" --once --scene "$scene" --output "$dir/server" --timeout 60
  local server_pid=$started_pid
  wait_for_pattern "$dir/server.log" "listening on [^ ]+:[0-9]+" "$server_pid" 20
  local line
  line=$(grep -m1 -oE 'listening on [^ ]+:[0-9]+' "$dir/server.log")
  export DEMLINK_HOST=$listen DEMLINK_PORT=${line##*:}
  [[ "${line#listening on }" == "$listen:$DEMLINK_PORT" ]] || fail "$mode: server says '$line', expected $listen"
  log "$mode: server pid $server_pid listening on $DEMLINK_HOST:$DEMLINK_PORT"

  start "$dir/client_a.log" "$ns_ca" "$dir/client_a" timeout --kill-after=10 "$client_timeout" \
    bash -c "$client_a_cmd"
  local a_pid=$started_pid
  if [[ -n "$client_a_ready" ]]; then
    wait_for_pattern "$dir/server.log" "$client_a_ready" "$a_pid" 60
  fi
  start "$dir/client_b.log" "$ns_cb" "$dir/client_b" timeout --kill-after=10 "$client_timeout" \
    bash -c "$client_b_cmd"
  local b_pid=$started_pid
  # Each is bounded by `timeout`, so these waits cannot hang.
  local a_status=0 b_status=0 server_status=0
  wait "$a_pid" || a_status=$?
  wait "$b_pid" || b_status=$?
  wait "$server_pid" || server_status=$?
  pids=()
  local name
  for name in server client_a client_b; do
    echo "---- $mode: $name output (last 15 lines) ----"
    tail -n 15 "$dir/$name.log"
  done
  echo "----"
  ((a_status == 0 && b_status == 0 && server_status == 0)) ||
    fail "$mode: exit codes client A $a_status, client B $b_status, server $server_status (124: timed out)"
  [[ -f "$dir/server/sim_001/checkpoint_final.bin" ]] ||
    fail "$mode: no server/sim_001/checkpoint_final.bin (files: $(ls "$dir/server/sim_001" 2>/dev/null | tr '\n' ' '))"
  if [[ "$mode" == netns ]]; then
    # The server saw each client come from its own namespace's address.
    local address
    for address in "$kClientAAddress" "$kClientBAddress"; do
      grep -qE "connection [0-9]+ from $address:[0-9]+" "$dir/server.log" ||
        fail "netns: the server log has no connection from $address"
    done
  fi
  log "$mode: co-simulation completed in $((SECONDS - began)) s"
}

# The clients of the netns run must really be in their namespaces: their view of the
# network has exactly their own address (checked before the run, cheap).
for pair in "$ns_a:$kClientAAddress" "$ns_b:$kClientBAddress"; do
  addrs=$(ip -n "${pair%%:*}" -4 -o addr show | awk '{print $4}' | tr '\n' ' ')
  [[ "$addrs" == *"${pair#*:}/24"* && "$addrs" != *"$kServerAddress"* ]] ||
    fail "namespace ${pair%%:*} has addresses '$addrs'"
done

run_cosim netns
run_cosim loopback

# --- Compare the runs -----------------------------------------------------------------
compare=(server/sim_001/checkpoint_final.bin)
for f in "$workdir"/netns/server/sim_001/{region_sensor,particle_sink,particle_source,flow_sensor}_*.csv; do
  [[ -e "$f" ]] && compare+=("server/sim_001/${f##*/}")
done
read -r -a extra <<<"${COMPARE_FILES:-}"
compare+=("${extra[@]}")
for f in "${compare[@]}"; do
  [[ -f "$workdir/netns/$f" && -f "$workdir/loopback/$f" ]] || fail "$f is missing from a run"
  cmp -s "$workdir/netns/$f" "$workdir/loopback/$f" ||
    fail "$f differs between the netns and the loopback run ($(cmp "$workdir/netns/$f" "$workdir/loopback/$f" | head -1))"
done
log "identical in both runs: ${compare[*]}"

if [[ -n "${MASS_BALANCE_ARGS:-}" ]]; then
  read -r -a balance <<<"$MASS_BALANCE_ARGS"
  for mode in netns loopback; do
    (cd "$workdir/$mode" && "$python" "$repo/scripts/${MASS_BALANCE_SCRIPT:-check_mass_balance.py}" "${balance[@]}") ||
      fail "$mode: mass balance"
  done
fi
log "PASSED (outputs: ${DEMLINK_NETNS_KEEP:-removed})"
