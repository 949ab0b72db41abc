#!/usr/bin/env bash
# The excavator-and-truck co-simulation on one machine (docs/tutorial.md): demlink-server with the site scene (pit, ground, gravel), demlink-truck
# (C ABI; declares the SimulationBox and waits for the excavator's components) and
# demlink-excavator (C++ client library) over loopback. Everything goes into one folder:
# server/ (VTK for ParaView, sensor CSVs, checkpoints), truck/ and excavator/ (model CSVs,
# STL), the PNG plots and summary.txt (mass dug, delivered, spilled, the mass balance over
# pit + bucket + truck + spill + removed, peak cylinder force). The truck drives off once
# CYCLES dumps have settled on its body. Exit code 1 if a process failed or mass is not
# balanced (or less than 90 % of what the bucket carried reached the truck).
#   scripts/demo_cosim.sh [OUT_DIR] [CYCLES] [--backend native|liggghts] [--ranks N] [--small]
#                         [--view PORT]
#   (defaults: out/cosim_demo, 2, native, 1 rank, the full site, no view)
# --view PORT serves the live 3D view of the site on 127.0.0.1:PORT and prints its address
# (docs/view.md); open it in a browser while the demo runs.
# --backend liggghts runs the server on LIGGGHTS-PUBLIC under `mpirun -np N` (N > 1; one
# rank: no mpirun) and the truck with --stand-still (LIGGGHTS has no moving frame: the truck
# is loaded, then says Bye without driving). --small: the site with a 1.6 m pit (about
# 1,100 particles instead of 4,400; make_site_scene.py --pit-half-x 0.8), for machines on
# which the full site is too slow (docs/scale-out.md has the wall times).
# Expects a release build (scripts/build.sh).
set -euo pipefail
cd "$(dirname "$0")/.."
backend=native ranks=1 small=0 view= positional=()
while (($#)); do
  case $1 in
    --backend) backend=$2; shift 2 ;;
    --ranks) ranks=$2; shift 2 ;;
    --small) small=1; shift ;;
    --view) view=$2; shift 2 ;;
    *) positional+=("$1"); shift ;;
  esac
done
[[ $backend == native || $backend == liggghts ]] || { echo "demo_cosim: --backend $backend: expected native or liggghts" >&2; exit 2; }
[[ $ranks =~ ^[1-9][0-9]*$ ]] || { echo "demo_cosim: --ranks $ranks: expected a whole number >= 1" >&2; exit 2; }
[[ -z $view || $view =~ ^[0-9]+$ ]] || { echo "demo_cosim: --view $view: expected a port number" >&2; exit 2; }
out=${positional[0]:-out/cosim_demo}
cycles=${positional[1]:-2}
bin=build/release
for exe in "$bin/server/demlink-server" "$bin/examples/truck/demlink-truck" "$bin/examples/excavator/demlink-excavator"; do
  [[ -x "$exe" ]] || { echo "demo_cosim: $exe is missing; build first (scripts/build.sh)" >&2; exit 2; }
done
rm -rf "$out" && mkdir -p "$out"
start=$(date +%s)

scene=examples/cosim/site_scene.json
if ((small)); then
  scene=$out/site_scene_small.json
  python3 examples/cosim/make_site_scene.py --pit-half-x 0.8 --output "$scene"
fi
server_cmd=("$bin/server/demlink-server")
[[ -n $view ]] && server_cmd+=(--view "127.0.0.1:$view")
truck_flags=()
# Every rank settles the pit before the compile answers, and a busy machine makes that
# slow: the clients wait up to half an hour for it (their default is 300 s).
client_flags=(--timeout 1800)
if [[ $backend == liggghts ]]; then
  server_cmd+=(--backend liggghts)
  truck_flags+=(--stand-still)
  if ((ranks > 1)); then
    # Open MPI refuses root without these (containers); more ranks than cores need --oversubscribe.
    export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
    server_cmd=(mpirun --oversubscribe -np "$ranks" "${server_cmd[@]}")
  fi
fi
echo "demo_cosim: $backend backend on $ranks rank(s), scene $scene"
"${server_cmd[@]}" --port 0 --once --scene "$scene" --output "$out/server" \
  >"$out/server.log" 2>&1 &
server=$!
pids=("$server")
trap 'kill "${pids[@]}" 2>/dev/null || true' EXIT
source scripts/lib/child_server.sh
# mpirun and LIGGGHTS take a while to start on a loaded machine.
port=$(wait_for_server_port "$out/server.log" "$server" 120) ||
  { echo "demo_cosim: the server did not start:" >&2; cat "$out/server.log" >&2; exit 1; }
echo "demo_cosim: server on 127.0.0.1:$port; output in $out"
if [[ -n $view ]]; then
  view_url=$(grep -m1 -o 'view at http://[^ ]*' "$out/server.log" | cut -d' ' -f3)
  echo "demo_cosim: live view at ${view_url:-http://127.0.0.1:$view/} (open it in a browser)"
fi

# The truck declares the SimulationBox first; the server compiles once the excavator's
# bucket and fill sensor are declared too (the box's expected_names).
"$bin/examples/truck/demlink-truck" --host 127.0.0.1 --port "$port" --scenario excavator --dumps "$cycles" \
  --output "$out/truck" "${client_flags[@]}" ${truck_flags[@]+"${truck_flags[@]}"} \
  >"$out/truck.log" 2>&1 &
truck=$!
pids+=("$truck")
sleep 1
"$bin/examples/excavator/demlink-excavator" --host 127.0.0.1 --port "$port" --cycles "$cycles" \
  --output "$out/excavator" "${client_flags[@]}" >"$out/excavator.log" 2>&1 &
excavator=$!
pids+=("$excavator")

# Progress: the models' latest log lines every 10 s until both clients are done.
while kill -0 "$excavator" 2>/dev/null || kill -0 "$truck" 2>/dev/null; do
  sleep 10
  echo "[$(($(date +%s) - start)) s] excavator: $(tail -n1 "$out/excavator.log" 2>/dev/null | cut -c1-110)"
  echo "[$(($(date +%s) - start)) s] truck:     $(tail -n1 "$out/truck.log" 2>/dev/null | cut -c1-110)"
done
status=0
wait "$excavator" || status=$?
wait "$truck" || status=$?
wait "$server" || status=$?
trap - EXIT
if ((status != 0)); then
  echo "demo_cosim: a process failed (exit $status); logs in $out/*.log" >&2
  exit "$status"
fi
# The first python3 on PATH may be a private one without Debian's matplotlib.
python=python3
"$python" -c 'import matplotlib' 2>/dev/null || python=/usr/bin/python3
"$python" scripts/plot_cosim.py --excavator "$out/excavator/excavator.csv" --truck "$out/truck/truck.csv" \
  --output-dir "$out" >"$out/plots.log"
# Snapshots: the first cycle's drag and dump (phases in the excavator's CSV) and the end.
times=$(awk -F, 'NR > 1 && !drag && $3 == "drag" { drag = $1 + 1.0 } NR > 1 && !dump && $3 == "dump" { dump = $1 + 0.5 }
                 END { printf "%s,%s,end", drag + 0, dump + 0 }' "$out/excavator/excavator.csv")
"$python" scripts/plot_site.py "$out/server/sim_001" --times "$times" --output "$out/site.png" >>"$out/plots.log"
balance=0
"$python" scripts/cosim_summary.py "$out/server/sim_001" --excavator-summary "$out/excavator/excavator_summary.txt" \
  --min-delivered-fraction 0.9 >"$out/summary.txt" 2>&1 || balance=$?
echo
cat "$out/summary.txt"
echo
echo "demo_cosim: done in $(($(date +%s) - start)) s. Results in $out:"
echo "  ParaView:  $out/server/sim_001/particles.pvd and meshes.pvd (VTK)"
echo "  plots:     $out/excavator.png (bucket fill, cylinder forces), $out/truck.png (load, axle forces, frame motion),"
echo "             $out/site.png (the site from above and the side while digging, dumping and at the end)"
echo "  CSV:       $out/excavator/excavator.csv, $out/truck/truck.csv, $out/server/sim_001/region_sensor_*.csv"
echo "  summary:   $out/summary.txt; logs: $out/*.log"
exit "$balance"
