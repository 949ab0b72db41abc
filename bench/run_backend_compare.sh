#!/usr/bin/env bash
# The deposition scene (bench/deposition/README.md) through demlink-run on both backends:
# the native engine on 1 and 2 threads and LIGGGHTS (--backend liggghts) on 1 and 2 MPI
# ranks, the same scene file and the same run (docs/scale-out.md).
#
# Usage: bench/run_backend_compare.sh N [end_time] [--runs K]
#   N          particles, rounded up to whole layers of 15 x 15 (default run: 50000 -> 50175)
#   end_time   simulated seconds (default 0.5 = 50,000 steps of 1e-5 s)
#   --runs K   repeat the four configurations K times, alternating, and report medians
# Environment:
#   DEMLINK_BENCH_WORK work directory (default: <repo>/bench/work, git-ignored)
#   DEMLINK_RUN        demlink-run built with the LIGGGHTS backend
#                      (default: <repo>/build/release/server/demlink-run)
#   MPIRUN             MPI launcher and flags (default: mpirun --oversubscribe)
# Prints per configuration: median wall seconds, particle-steps per second, final mean
# centre height; logs stay in the work directory (backend_<config>_<k>.log).
set -euo pipefail

script_dir=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
repo=$(cd "$script_dir/.." && pwd)
usage() { sed -n '6,16p' "${BASH_SOURCE[0]}" | sed 's/^# \{0,1\}//' >&2; exit 2; }

runs=1
positional=()
while (($#)); do
  case "$1" in
    --runs) runs=${2:?--runs needs a value}; shift 2 ;;
    -h|--help) usage ;;
    -*) echo "unknown option $1" >&2; usage ;;
    *) positional+=("$1"); shift ;;
  esac
done
((${#positional[@]} >= 1 && ${#positional[@]} <= 2)) || usage
n=${positional[0]}
end_time=${positional[1]:-0.5}
[[ "$n" =~ ^[0-9]+$ && "$runs" =~ ^[0-9]+$ ]] && ((n >= 1 && runs >= 1)) || usage

run_exe=${DEMLINK_RUN:-$repo/build/release/server/demlink-run}
mpirun_cmd=${MPIRUN:-mpirun --oversubscribe}
work=${DEMLINK_BENCH_WORK:-$repo/bench/work}
mkdir -p "$work"
[[ -x "$run_exe" ]] || { echo "no $run_exe: build demlink_run (with libliggghts-dev installed)" >&2; exit 1; }
if [[ $(id -u) -eq 0 ]]; then export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1; fi

# One scene file per thread count (simulation_box.threads); LIGGGHTS ignores threads.
for threads in 1 2; do
  python3 - "$repo/examples/scenes/deposition_small.json" "$work/backend_deposition_t$threads.json" "$n" \
    "$end_time" "$threads" <<'PY'
import json, math, sys
source, target, n, end_time, threads = sys.argv[1], sys.argv[2], int(sys.argv[3]), float(sys.argv[4]), int(sys.argv[5])
scene = json.load(open(source))
layers = math.ceil(n / 225)
for component in scene["components"]:
    if "simulation_box" in component:
        box = component["simulation_box"]
        box["end_time"] = end_time
        box["threads"] = threads
        box["output"] = {"vtk_interval": end_time / 5, "progress_interval_s": 30.0}
        # LIGGGHTS needs a fixed box: the lattice's height plus a margin.
        box["bounds"] = {"lower": {"x": 0, "y": 0, "z": 0},
                         "upper": {"x": 0.1, "y": 0.1, "z": 0.0035 + 0.0065 * layers + 0.01}}
    if "particle_lattice" in component:
        component["particle_lattice"]["counts"]["nz"] = layers
json.dump(scene, open(target, "w"), indent=1)
PY
done

configs=(native_1thread native_2threads liggghts_1rank liggghts_2ranks)
declare -A walls
for ((k = 1; k <= runs; ++k)); do
  for config in "${configs[@]}"; do
    log=$work/backend_${config}_$k.log
    out=$work/backend_out_$config
    case "$config" in
      native_1thread) cmd=("$run_exe" "$work/backend_deposition_t1.json") ;;
      native_2threads) cmd=("$run_exe" "$work/backend_deposition_t2.json") ;;
      liggghts_1rank) cmd=("$run_exe" "$work/backend_deposition_t1.json" --backend liggghts) ;;
      liggghts_2ranks) cmd=($mpirun_cmd -np 2 "$run_exe" "$work/backend_deposition_t1.json" --backend liggghts) ;;
    esac
    start=$(date +%s.%N)
    "${cmd[@]}" --output "$out" --overwrite >"$log" 2>&1
    end=$(date +%s.%N)
    walls[$config]+="$(python3 -c "print($end - $start)") "
  done
done

echo "deposition, $(( (n + 224) / 225 * 225 )) particles, $end_time s; load: $(uptime | sed 's/.*load average: //')"
printf '%-18s %12s %16s %14s\n' configuration "wall [s]" "particle-steps/s" "mean z [m]"
for config in "${configs[@]}"; do
  median=$(python3 -c "import statistics, sys; print(statistics.median(float(x) for x in sys.argv[1:]))" ${walls[$config]})
  mean_z=$(grep -o 'mean z [0-9.e+-]*' "$work/backend_${config}_$runs.log" | tail -n1 | awk '{print $3}')
  rate=$(python3 -c "print(f'{$(( (n + 224) / 225 * 225 )) * $end_time / 1e-5 / $median:.3g}')")
  printf '%-18s %12.2f %16s %14s\n' "$config" "$median" "$rate" "$mean_z"
done
