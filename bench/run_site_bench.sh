#!/usr/bin/env bash
# The excavator-and-truck site as a benchmark: demlink-server on the site scene
# (examples/cosim/site_scene.json), the truck standing still (--stand-still) and the
# excavator digging, both over loopback, for a fixed simulated time. Per run it prints
# the real-time factor (simulated s per wall s of the exchanges, settling excluded), the
# particle-steps per second per DEM thread, the pit's settling (wall time, simulated time,
# packing fraction, bed top) apart, and the server's sampled stage timing.
#   bench/run_site_bench.sh [--seconds T] [--runs K] [--bin DIR[,DIR2]] [--work DIR] [--perf]
#     --seconds T   simulated time of each run (default 8: approach, penetration and drag)
#     --runs K      runs per binary folder (default 1); with two folders the runs alternate A, B
#     --bin DIR     folder(s) holding demlink-server, demlink-truck, demlink-excavator
#                   (default: build/release's); two, comma-separated, for an A/B comparison
#     --work DIR    logs and outputs (default bench/work/site)
#     --perf        record the server with `perf record -g` from the first exchange on
#                   (perf.data in the run's folder; `perf report -i ... --no-children`)
# Medians over the runs of each folder close the output. The DEM threads are the truck's
# simulation_box.threads (2).
set -euo pipefail
cd "$(dirname "$0")/.."
seconds=8 runs=1 bins=() work=${DEMLINK_BENCH_WORK:-bench/work}/site perf=0
while (($#)); do
  case $1 in
    --seconds) seconds=$2; shift 2 ;;
    --runs) runs=$2; shift 2 ;;
    --bin) IFS=, read -r -a bins <<<"$2"; shift 2 ;;
    --work) work=$2; shift 2 ;;
    --perf) perf=1; shift ;;
    *) echo "run_site_bench: unknown option $1" >&2; exit 2 ;;
  esac
done
[[ $seconds =~ ^[0-9]+([.][0-9]+)?$ ]] || { echo "run_site_bench: --seconds $seconds: expected a positive number" >&2; exit 2; }
[[ $runs =~ ^[1-9][0-9]*$ ]] || { echo "run_site_bench: --runs $runs: expected a whole number >= 1" >&2; exit 2; }
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
printf 'bin\trun\tload\tsettle_wall_s\tsettle_sim_s\tpacking\tbed_top_m\tparticles\tsim_s\twall_s\trtf\tpsteps_per_s_per_thread\n' >"$results"

one_run() {  # folder index, run number
  local b=${bins[$1]} k=$2 dir
  read -r server truck excavator <<<"$(resolve "$b")"
  dir=$work/run_${1}_$k
  rm -rf "$dir" && mkdir -p "$dir"
  local load
  load=$(cut -d' ' -f1 /proc/loadavg)
  "$server" --port 0 --once --scene examples/cosim/site_scene.json --output "$dir/server" >"$dir/server.log" 2>&1 &
  local spid=$! port
  port=$(wait_for_server_port "$dir/server.log" "$spid" 60) || { cat "$dir/server.log" >&2; exit 1; }
  "$truck" --port "$port" --scenario excavator --stand-still --max-time "$seconds" --timeout 1800 \
    --output "$dir/truck" >"$dir/truck.log" 2>&1 &
  local tpid=$!
  sleep 0.5
  "$excavator" --port "$port" --cycles 1 --stop-at "$seconds" --timeout 1800 --output "$dir/excavator" \
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
  local settled sim wall particles threads=2
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
  awk -v b="$b" -v k="$k" -v load="$load" -v sw="${settle_wall:-}" -v ss="${settle_sim:-}" \
    -v pk="${packing:-}" -v top="${top:-}" -v n="$particles" -v sim="$sim" -v wall="$wall" -v dt="$dt" \
    -v th="$threads" 'BEGIN { printf "%s\t%d\t%s\t%s\t%s\t%s\t%s\t%d\t%s\t%s\t%.4f\t%.4g\n", b, k, load, sw, ss, pk, top, n,
                              sim, wall, sim / wall, n * (sim / dt) / wall / th }' >>"$results"
  echo "[$b run $k, load $load] $(tail -n1 "$results" | cut -f4-)"
  grep -h 'stage timing' "$dir/server/sim_001/compile_report.txt" | sed 's/^/  /'
}

for ((k = 1; k <= runs; ++k)); do
  for i in "${!bins[@]}"; do one_run "$i" "$k"; done
done
echo
echo "medians (real-time factor = simulated s / wall s of the exchanges; settling apart):"
for b in "${bins[@]}"; do
  # An empty settling cell (no "settled in" line) is missing: left out of its median.
  awk -F'\t' -v b="$b" 'NR > 1 && $1 == b { n++; rtf[n] = $11; ps[n] = $12; if ($4 != "") sw[++m] = $4 }
    function median(a, n,   i, j, t) { for (i = 1; i <= n; i++) for (j = i + 1; j <= n; j++) if (a[j] < a[i]) { t = a[i]; a[i] = a[j]; a[j] = t }
                                       return n % 2 ? a[(n + 1) / 2] : 0.5 * (a[n / 2] + a[n / 2 + 1]) }
    END { if (n) printf "  %s: real-time factor %.3f, %.3g particle-steps/s per thread, settling %.1f s wall (%d runs)\n",
                        b, median(rtf, n), median(ps, n), m ? median(sw, m) : 0, n }' "$results"
done
echo "table: $results"
