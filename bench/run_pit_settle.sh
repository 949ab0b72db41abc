#!/usr/bin/env bash
# The site's pit generation alone (examples/cosim/site_scene.json's pit_generator, 2 threads,
# one step of the site afterwards) through demlink-run, for several seeds and one or two
# builds, alternating: per run the settling's wall time, simulated time and steps, the kept
# particles, the packing fraction below the target height and the bed top.
#   bench/run_pit_settle.sh [--seeds 5,6,7] [--bin DIR[,DIR2]] [--work DIR]
#     --bin DIR   folder(s) holding demlink-run (a build tree or a flat folder; default build/release)
set -euo pipefail
cd "$(dirname "$0")/.."
seeds=5,6,7 bins=() work=${DEMLINK_BENCH_WORK:-bench/work}/pit
while (($#)); do
  case $1 in
    --seeds) seeds=$2; shift 2 ;;
    --bin) IFS=, read -r -a bins <<<"$2"; shift 2 ;;
    --work) work=$2; shift 2 ;;
    *) echo "run_pit_settle: unknown option $1" >&2; exit 2 ;;
  esac
done
((${#bins[@]})) || bins=(build/release)
mkdir -p "$work"
whole=0
printf 'bin\tseed\tload\tsettle_wall_s\tsettle_sim_s\tsteps\tkept\tpacking\tbed_top_m\n'
IFS=, read -r -a seedList <<<"$seeds"
for seed in "${seedList[@]}"; do
  [[ $seed =~ ^[0-9]+$ ]] || { echo "run_pit_settle: seed $seed: expected a whole number" >&2; exit 2; }
  scene=$work/pit_seed_$seed.json
  python3 - "$seed" "$scene" <<'EOF'
import json, sys
seed, out = sys.argv[1], sys.argv[2]
scene = json.load(open("examples/cosim/site_scene.json"))
for c in scene["components"]:
    if "pit_generator" in c:
        c["pit_generator"]["seed"] = seed
scene["components"].append({"name": "box", "simulation_box": {
    "time_step": 2e-4, "restitution_tolerance": 0.1, "end_time": 2e-4, "threads": 2,
    "bounds": {"lower": {"x": -6, "y": -7, "z": -1.5}, "upper": {"x": 9, "y": 3, "z": 6}},
    "output": {"vtk_interval": 1.0}}})
json.dump(scene, open(out, "w"), indent=1)
EOF
  for b in "${bins[@]}"; do
    run=$b/demlink-run
    [[ -x $run ]] || run=$b/server/demlink-run
    [[ -x $run ]] || { echo "run_pit_settle: $run is missing" >&2; exit 2; }
    load=$(cut -d' ' -f1 /proc/loadavg)
    log=$work/$(basename "$b")_seed_$seed.log
    start=$(date +%s.%N)
    "$run" "$scene" --output "$work/out_$(basename "$b")_$seed" --overwrite >"$log" 2>&1
    end=$(date +%s.%N)
    line=$(grep -m1 'pit_generator pit: settled in' "$log")
    rained=$(sed -n 's/.*settling \([0-9]*\) particles.*/\1/p' "$log" | head -n1)
    wall=$(sed -n 's/.*steps, \([0-9.e+-]*\) s wall.*/\1/p' <<<"$line")
    # Builds whose log gives no wall time: the whole run's (settling is nearly all of it).
    [[ -n $wall ]] || { wall=$(awk -v a="$start" -v b="$end" 'BEGIN { printf "%.1f*", b - a }'); whole=1; }
    sim=$(sed -n 's/.*settled in \([0-9.e+-]*\) s (\([0-9]*\) steps.*/\1\t\2/p' <<<"$line")
    kept=$(sed -n 's/.*kept \([0-9]*\) of.*/\1/p' <<<"$line")
    mass=$(sed -n 's/.*particles (\([0-9.e+-]*\) kg).*/\1/p' <<<"$line")
    top=$(sed -n 's/.*bed top \([0-9.e+-]*\) m.*/\1/p' <<<"$line")
    # Packing fraction from the kept mass: gravel's density (materials database) over the 6 x 2 x 1 m pit.
    density=$(grep -m1 '^gravel,' data/materials.csv | cut -d, -f2)
    packing=$(awk -v m="$mass" -v d="$density" 'BEGIN { printf "%.4f", m / d / 12.0 }')
    printf '%s\t%s\t%s\t%s\t%s\t%s of %s\t%s\t%s\n' "$b" "$seed" "$load" "$wall" "$sim" "$kept" "$rained" "$packing" "$top"
  done
done
((whole)) && echo "(* wall time of the whole demlink-run: the build's log does not give the settling's)"
exit 0
