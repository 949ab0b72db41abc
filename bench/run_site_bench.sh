#!/usr/bin/env bash
# The excavator-and-truck site as a benchmark: demlink-server on the site scene
# (examples/cosim/site_scene.json), natively or on LIGGGHTS, the truck standing still
# (--stand-still) and the excavator digging, both over loopback, for a fixed simulated time
# or one whole dig-dump cycle. Per run it prints the real-time factor (simulated s per wall s of the exchanges,
# settling excluded), the particle-steps per second per DEM thread, the pit's settling
# (wall time, simulated time, packing fraction, bed top) apart, the server's sampled stage
# timing, and what the excavator model saw: the mass it carried to the truck, the bucket's
# peak fill, the peak and mean digging force, and the truck's load.
#   bench/run_site_bench.sh [--seconds T] [--runs K] [--bin DIR[,DIR2]] [--fidelity P[,P2..]]
#                           [--seeds S[,S2..]] [--time-step S] [--modulus-scale S] [--work DIR] [--perf]
#                           [--backend B[,B2]] [--ranks N]
#     --seconds T   simulated time of each run (default 8: approach, penetration and drag);
#                   0: one whole cycle (dig, swing, dump into the truck, swing back)
#     --runs K      runs per binary folder (default 1); with two folders the runs alternate A, B
#     --bin DIR     folder(s) holding demlink-server, demlink-truck, demlink-excavator
#                   (default: build/release's); two, comma-separated, for an A/B comparison
#     --fidelity P  the truck's --fidelity: none (default: 0.2 ms, 10 % tolerance), draft,
#                   engineering, validation; several, comma-separated, run in turn; with
#                   validation among them the close compares every preset with it, seed by seed
#     --seeds S     pit seeds (default: the scene's, 5); each seed is another bed
#     --time-step S the truck's --time-step (default: the preset's step for the site)
#     --modulus-scale S  the truck's --modulus-scale, a softening of the contacts (default: none)
#     --work DIR    logs and outputs (default bench/work/site)
#     --perf        record the server with `perf record -g` from the first exchange on
#                   (perf.data in the run's folder; `perf report -i ... --no-children`)
#     --backend B   native (default) or liggghts (demlink-server --backend liggghts, built
#                   with the LIGGGHTS backend); both, comma-separated, run side by side
#     --ranks N     MPI ranks of the LIGGGHTS server (default 2: mpirun -np 2; 1: no mpirun)
# Medians over the runs of each folder and preset close the output
# (bench/site_presets_summary.py). The DEM threads are the truck's simulation_box.threads (2)
# natively, the ranks on LIGGGHTS: particle-steps per thread divide by them.
set -euo pipefail
cd "$(dirname "$0")/.."
seconds=8 runs=1 bins=() work=${DEMLINK_BENCH_WORK:-bench/work}/site perf=0 fidelities=none seeds= timeStep= modulusScale=
backends=native ranks=2
while (($#)); do
  case $1 in
    --seconds) seconds=$2; shift 2 ;;
    --runs) runs=$2; shift 2 ;;
    --bin) IFS=, read -r -a bins <<<"$2"; shift 2 ;;
    --work) work=$2; shift 2 ;;
    --perf) perf=1; shift ;;
    --fidelity) fidelities=$2; shift 2 ;;
    --seeds) seeds=$2; shift 2 ;;
    --time-step) timeStep=$2; shift 2 ;;
    --modulus-scale) modulusScale=$2; shift 2 ;;
    --backend) backends=$2; shift 2 ;;
    --ranks) ranks=$2; shift 2 ;;
    *) echo "run_site_bench: unknown option $1" >&2; exit 2 ;;
  esac
done
[[ $seconds =~ ^[0-9]+([.][0-9]+)?$ ]] || { echo "run_site_bench: --seconds $seconds: expected a number >= 0" >&2; exit 2; }
IFS=, read -r -a fidelityList <<<"$fidelities"
for f in "${fidelityList[@]}"; do
  [[ $f =~ ^(none|draft|engineering|validation)$ ]] || { echo "run_site_bench: --fidelity $f: expected none, draft, engineering or validation" >&2; exit 2; }
done
IFS=, read -r -a seedList <<<"${seeds:-scene}"
for s in "${seedList[@]}"; do
  [[ $s == scene || $s =~ ^[0-9]+$ ]] || { echo "run_site_bench: --seeds $s: expected whole numbers" >&2; exit 2; }
done
[[ $runs =~ ^[1-9][0-9]*$ ]] || { echo "run_site_bench: --runs $runs: expected a whole number >= 1" >&2; exit 2; }
[[ $ranks =~ ^[1-9][0-9]*$ ]] || { echo "run_site_bench: --ranks $ranks: expected a whole number >= 1" >&2; exit 2; }
IFS=, read -r -a backendList <<<"$backends"
for be in "${backendList[@]}"; do
  [[ $be =~ ^(native|liggghts)$ ]] || { echo "run_site_bench: --backend $be: expected native or liggghts" >&2; exit 2; }
done
# Open MPI refuses root without these (containers); more ranks than cores need --oversubscribe.
if [[ $(id -u) -eq 0 ]]; then export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1; fi
((${#bins[@]})) || bins=(build/release)
resolve() {  # folder -> "server truck excavator" (a build tree or a flat folder of the three)
  local d=$1 s=$1/demlink-server t=$1/demlink-truck e=$1/demlink-excavator
  [[ -x $s ]] || s=$d/server/demlink-server
  [[ -x $t ]] || t=$d/examples/truck/demlink-truck
  [[ -x $e ]] || e=$d/examples/excavator/demlink-excavator
  for x in "$s" "$t" "$e"; do [[ -x $x ]] || { echo "run_site_bench: $x is missing" >&2; exit 2; }; done
  echo "$s $t $e"
}
for b in "${bins[@]}"; do resolve "$b" >/dev/null; done
mkdir -p "$work"
source scripts/lib/child_server.sh
results=$work/results.tsv
printf 'bin\tbackend\trun\tload\tsettle_wall_s\tsettle_sim_s\tpacking\tbed_top_m\tparticles\tsim_s\twall_s\trtf\tpsteps_per_s_per_thread\tfidelity\tseed\ttime_step_s\tcarried_kg\tpeak_fill_kg\tdig_force_peak_N\tdig_force_mean_N\ttruck_load_kg\n' >"$results"

scene_for() {  # seed -> the scene file to run
  local seed=$1 out
  [[ $seed == scene ]] && { echo examples/cosim/site_scene.json; return; }
  out=$work/site_scene_seed_$seed.json
  python3 - "$seed" "$out" <<'EOF'
import json, sys
scene = json.load(open("examples/cosim/site_scene.json"))
for c in scene["components"]:
    if "pit_generator" in c:
        c["pit_generator"]["seed"] = sys.argv[1]
json.dump(scene, open(sys.argv[2], "w"), indent=1)
EOF
  echo "$out"
}

one_run() {  # folder index, run number, fidelity, seed, backend
  local b=${bins[$1]} k=$2 fidelity=$3 seed=$4 backend=$5 dir
  read -r server truck excavator <<<"$(resolve "$b")"
  dir=$work/run_${1}_${k}_${fidelity}_${seed}_$backend
  rm -rf "$dir" && mkdir -p "$dir"
  local load scene
  load=$(cut -d' ' -f1 /proc/loadavg)
  scene=$(scene_for "$seed")
  local serverCmd=("$server") threads=2
  if [[ $backend == liggghts ]]; then
    serverCmd+=(--backend liggghts)
    threads=$ranks
    ((ranks > 1)) && serverCmd=(mpirun --oversubscribe -np "$ranks" "${serverCmd[@]}")
  fi
  "${serverCmd[@]}" --port 0 --once --scene "$scene" --output "$dir/server" >"$dir/server.log" 2>&1 &
  local spid=$! port
  # mpirun and LIGGGHTS take a while to start.
  port=$(wait_for_server_port "$dir/server.log" "$spid" 120) || { cat "$dir/server.log" >&2; exit 1; }
  local truckArgs=(--max-time "$seconds") excavatorArgs=(--stop-at "$seconds")
  # A whole cycle: the truck holds after the one dump, the excavator ends after swinging back.
  [[ $seconds =~ ^0*([.]0*)?$ ]] && { truckArgs=(--dumps 1); excavatorArgs=(); }
  [[ $fidelity != none ]] && truckArgs+=(--fidelity "$fidelity")
  [[ -n $timeStep ]] && truckArgs+=(--time-step "$timeStep")
  [[ -n $modulusScale ]] && truckArgs+=(--modulus-scale "$modulusScale")
  "$truck" --port "$port" --scenario excavator --stand-still "${truckArgs[@]}" --timeout 1800 \
    --output "$dir/truck" >"$dir/truck.log" 2>&1 &
  local tpid=$!
  sleep 0.5
  "$excavator" --port "$port" --cycles 1 "${excavatorArgs[@]}" --timeout 1800 --output "$dir/excavator" \
    >"$dir/excavator.log" 2>&1 &
  local epid=$! ppid=
  if ((perf)); then
    until grep -q 'simulation 1 starts' "$dir/server.log" 2>/dev/null; do
      kill -0 "$spid" 2>/dev/null || break
      sleep 0.2
    done
    perf record -g -o "$dir/perf.data" -p "$spid" >"$dir/perf.log" 2>&1 &
    ppid=$!
  fi
  wait "$epid" || { echo "run_site_bench: excavator failed ($dir/excavator.log)" >&2; }
  wait "$tpid" || true
  [[ -n $ppid ]] && { kill -INT "$ppid" 2>/dev/null || true; wait "$ppid" || true; }
  wait "$spid" || true
  local settled sim wall particles
  settled=$(grep -m1 'pit_generator pit: settled in' "$dir/server.log" || true)
  local settle_sim settle_wall packing top
  settle_sim=$(sed -n 's/.*settled in \([0-9.e+-]*\) s .*/\1/p' <<<"$settled")
  settle_wall=$(sed -n 's/.*steps, \([0-9.e+-]*\) s wall.*/\1/p' <<<"$settled")
  packing=$(sed -n 's/.*packing fraction \([0-9.e+-]*\).*/\1/p' <<<"$settled")
  top=$(sed -n 's/.*bed top \([0-9.e+-]*\) m.*/\1/p' <<<"$settled")
  sim=$(sed -n 's/^simulated_s = //p' "$dir/excavator/excavator_summary.txt")
  wall=$(sed -n 's/^wall_s = //p' "$dir/excavator/excavator_summary.txt")
  particles=$(sed -n 's/.*compiled, .* \([0-9]*\) particles$/\1/p' "$dir/excavator.log")
  local dt
  dt=$(sed -n 's/^time step: \([0-9.e+-]*\) s.*/\1/p' "$dir/server.log" | head -n1)
  local summary=$dir/excavator/excavator_summary.txt carried fill dfp dfm truckLoad
  carried=$(sed -n 's/^cycle_1_carried_kg = //p' "$summary")
  fill=$(sed -n 's/^cycle_1_peak_fill_kg = //p' "$summary")
  dfp=$(sed -n 's/^cycle_1_dig_force_peak_N = //p' "$summary")
  dfm=$(sed -n 's/^cycle_1_dig_force_mean_N = //p' "$summary")
  truckLoad=$(sed -n 's/.*finished (.*); load \([0-9.e+-]*\) kg.*/\1/p' "$dir/truck.log")
  awk -v b="$b" -v be="$backend" -v k="$k" -v load="$load" -v sw="${settle_wall:-}" -v ss="${settle_sim:-}" \
    -v pk="${packing:-}" -v top="${top:-}" -v n="$particles" -v sim="$sim" -v wall="$wall" -v dt="$dt" \
    -v th="$threads" -v f="$fidelity" -v seed="$seed" -v c="$carried" -v fill="$fill" -v dfp="$dfp" -v dfm="$dfm" \
    -v tl="${truckLoad:-}" \
    'BEGIN { printf "%s\t%s\t%d\t%s\t%s\t%s\t%s\t%s\t%d\t%s\t%s\t%.4f\t%.4g\t%s\t%s\t%s\t%s\t%s\t%s\t%s\t%s\n", b, be, k, load, sw, ss, pk,
             top, n, sim, wall, sim / wall, n * (sim / dt) / wall / th, f, seed, dt, c, fill, dfp, dfm, tl }' >>"$results"
  echo "[$b $backend run $k, $fidelity, seed $seed, load $load] $(tail -n1 "$results" | cut -f5-13,16-)"
  { grep -h 'stage timing' "$dir/server/sim_001/compile_report.txt" 2>/dev/null || true; } | sed 's/^/  /'
}

for ((k = 1; k <= runs; ++k)); do
  for seed in "${seedList[@]}"; do
    for f in "${fidelityList[@]}"; do
      for be in "${backendList[@]}"; do
        for i in "${!bins[@]}"; do one_run "$i" "$k" "$f" "$seed" "$be"; done
      done
    done
  done
done
echo
python3 bench/site_presets_summary.py "$results"
echo "table: $results"
