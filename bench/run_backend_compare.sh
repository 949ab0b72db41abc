#!/usr/bin/env bash
# The same scene through demlink-run on both backends: the native engine on 1 and 2
# threads and LIGGGHTS (--backend liggghts) on 1 and 2 MPI ranks (docs/scale-out.md).
#
# Usage: bench/run_backend_compare.sh [N] [end_time] [--runs K] [--largest] [--hopper]
#   N          deposition: particles, rounded up to whole layers of 15 x 15 (default 50000 -> 50175);
#              --hopper: spheres the source pours in (default 3000)
#   end_time   simulated seconds (deposition default 0.5 = 50,000 steps of 1e-5 s; hopper 1.0)
#   --runs K   repeat the four configurations K times, alternating, and report medians
#   --largest  deposition with the largest N this machine's free memory holds (a quarter of
#              MemAvailable at 4 kB per particle, the larger of the two codes' footprints)
#   --hopper   the hopper of examples/scenes/hopper_discharge_D27.json (orifice plate as a
#              mesh_body, no gate: it drains while it fills) instead; prints the discharge
#              rate W (slope of the flow sensor's net mass over the second half of the run)
# Environment:
#   DEMLINK_BENCH_WORK work directory (default: <repo>/bench/work, git-ignored)
#   DEMLINK_RUN        demlink-run built with the LIGGGHTS backend
#                      (default: <repo>/build/release/server/demlink-run)
#   MPIRUN             MPI launcher and flags (default: mpirun --oversubscribe)
# Prints the load average and, per configuration: median wall seconds, particle-steps per
# second, final mean centre height (deposition) or W (hopper); logs stay in the work
# directory (backend_<config>_<k>.log).
set -euo pipefail

script_dir=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
repo=$(cd "$script_dir/.." && pwd)
# shellcheck source=lib/compare_common.sh
source "$script_dir/lib/compare_common.sh"
bench_usage_lines='5,22'

largest=0
hopper=0
bench_extra_option() {
  case "$1" in
    --largest) largest=1; bench_consumed=1 ;;
    --hopper) hopper=1; bench_consumed=1 ;;
  esac
}
bench_parse_args "$@"
((${#positional[@]} <= 2)) || bench_usage
if ((hopper)); then
  n=${positional[0]:-3000}
  end_time=${positional[1]:-1.0}
elif ((largest)); then
  available_kb=$(awk '/MemAvailable/ {print $2}' /proc/meminfo)
  n=$((available_kb / 4 / 4))
  end_time=${positional[1]:-0.5}
  echo "largest deposition for MemAvailable $((available_kb / 1024)) MB: N = $n"
else
  n=${positional[0]:-50000}
  end_time=${positional[1]:-0.5}
fi
[[ "$n" =~ ^[0-9]+$ ]] && ((n >= 1)) || bench_usage

run_exe=${DEMLINK_RUN:-$repo/build/release/server/demlink-run}
mpirun_cmd=${MPIRUN:-mpirun --oversubscribe}
work=$(bench_work_dir)
[[ -x "$run_exe" ]] || { echo "no $run_exe: build demlink_run (with libliggghts-dev installed)" >&2; exit 1; }
bench_allow_mpi_root

# One scene file per thread count (simulation_box.threads); LIGGGHTS ignores threads.
kind=$([[ $hopper == 1 ]] && echo hopper || echo deposition)
for threads in 1 2; do
  python3 - "$repo/examples/scenes" "$work/backend_${kind}_t$threads.json" "$n" "$end_time" "$threads" "$kind" <<'PY'
import json, math, os, shutil, sys
scenes, target, n, end_time, threads, kind = sys.argv[1], sys.argv[2], int(sys.argv[3]), float(sys.argv[4]), \
    int(sys.argv[5]), sys.argv[6]
if kind == "deposition":
    scene = json.load(open(os.path.join(scenes, "deposition_small.json")))
    layers = math.ceil(n / 225)
    for component in scene["components"]:
        if "simulation_box" in component:
            box = component["simulation_box"]
            # LIGGGHTS needs a fixed box: the lattice's height plus a margin.
            box["bounds"] = {"lower": {"x": 0, "y": 0, "z": 0},
                             "upper": {"x": 0.1, "y": 0.1, "z": 0.0035 + 0.0065 * layers + 0.01}}
        if "particle_lattice" in component:
            component["particle_lattice"]["counts"]["nz"] = layers
else:
    scene = json.load(open(os.path.join(scenes, "hopper_discharge_D27.json")))
    kept = []
    for component in scene["components"]:
        if component["name"] == "gate":
            continue  # LIGGGHTS has no switched-off walls: the hopper drains while it fills
        if component["name"] == "orifice_plate":
            plate = component.pop("facet_body")
            # Scene files may only read files from their own folder: a copy next to it.
            stl = os.path.basename(plate["stl_file"])
            shutil.copy(os.path.join(scenes, plate["stl_file"]), os.path.join(os.path.dirname(target), stl))
            component["mesh_body"] = {"stl_file": stl, "material": plate["material"]}
        if "particle_source" in component:
            source = component["particle_source"]
            source["stop_time"] = n / source["rate_particles_per_s"]
        kept.append(component)
    scene["components"] = kept
for component in scene["components"]:
    if "simulation_box" in component:
        box = component["simulation_box"]
        box["end_time"] = end_time
        box["threads"] = threads
        box["output"] = {"vtk_interval": end_time / 5, "progress_interval_s": 30.0}
json.dump(scene, open(target, "w"), indent=1)
PY
done

configs=(native_1thread native_2threads liggghts_1rank liggghts_2ranks)
declare -A walls
for ((k = 1; k <= runs; ++k)); do
  for config in "${configs[@]}"; do
    log=$work/backend_${config}_$k.log
    out=$work/backend_out_${config}_$k
    case "$config" in
      native_1thread) cmd=("$run_exe" "$work/backend_${kind}_t1.json") ;;
      native_2threads) cmd=("$run_exe" "$work/backend_${kind}_t2.json") ;;
      liggghts_1rank) cmd=("$run_exe" "$work/backend_${kind}_t1.json" --backend liggghts) ;;
      liggghts_2ranks) cmd=($mpirun_cmd -np 2 "$run_exe" "$work/backend_${kind}_t1.json" --backend liggghts) ;;
    esac
    start=$(date +%s.%N)
    "${cmd[@]}" --output "$out" --overwrite >"$log" 2>&1 || { echo "$config failed: see $log" >&2; exit 1; }
    end=$(date +%s.%N)
    walls[$config]+="$(python3 -c "print($end - $start)") "
  done
done

particles=$n
((hopper)) || particles=$(((n + 224) / 225 * 225))
steps=$(python3 -c "import json; b = next(c['simulation_box'] for c in json.load(open('$work/backend_${kind}_t1.json'))['components'] if 'simulation_box' in c); print(round(b['end_time'] / b['time_step']))")
echo "$kind, $particles particles, $end_time s ($steps steps), median of $runs; load average now: $(cut -d' ' -f1-3 /proc/loadavg)"
last=$([[ $hopper == 1 ]] && echo "W [kg/s]" || echo "mean z [m]")
printf '%-18s %12s %16s %14s\n' configuration "wall [s]" "particle-steps/s" "$last"
for config in "${configs[@]}"; do
  # shellcheck disable=SC2086
  median=$(bench_median ${walls[$config]})
  rate=$(python3 -c "print(f'{$particles * $steps / $median:.3g}')")
  if ((hopper)); then
    value=$(python3 - "$work/backend_out_${config}_$runs/flow_sensor_discharge.csv" "$end_time" <<'PY'
import csv, sys
rows = [r for r in csv.DictReader(open(sys.argv[1])) if float(r["time_s"]) >= float(sys.argv[2]) / 2]
t = [float(r["time_s"]) for r in rows]
m = [-float(r["net_mass_total_kg"]) for r in rows]
tm, mm = sum(t) / len(t), sum(m) / len(m)
print(f"{sum((a - tm) * (b - mm) for a, b in zip(t, m)) / sum((a - tm) ** 2 for a in t):.5g}")
PY
)
  else
    value=$(grep -o 'mean z [0-9.e+-]*' "$work/backend_${config}_$runs.log" | tail -n1 | awk '{print $3}')
  fi
  printf '%-18s %12.2f %16s %14s\n' "$config" "$median" "$rate" "$value"
done
