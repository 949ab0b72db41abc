#!/usr/bin/env bash
# Side-by-side deposition benchmark: DEMLink (demlink-bench-deposition) vs LIGGGHTS
# on the "deposition-N" scene of bench/deposition/ (see its README.md and docs/benchmarks.md).
#
# Usage: bench/run_deposition_compare.sh N [steps] [--runs K] [--thermo T] [--np P] [--threads T] [--rebuild]
#   N          number of particles (bench/deposition/make_particles.py N)
#   steps      time steps (default 50000 = 0.5 s)
#   --runs K   repeat each code K times (alternating) and report medians (default 1)
#   --thermo T thermo interval in steps (default steps/10)
#   --np P     P threads for DEMLink (--threads P) and P MPI ranks for LIGGGHTS
#              (mpirun -np P, -var px P); default 1 (both serial)
#   --threads T  DEMLink threads only (default: P), e.g. DEMLink on 2 threads
#              against serial LIGGGHTS, our speed target
#   --rebuild  rebuild our release binary even if it exists
# Environment:
#   DEMLINK_BENCH_WORK work directory (default: <repo>/bench/work, git-ignored)
#   LIGGGHTS           LIGGGHTS executable (default: liggghts)
# Logs of every run are kept in the work directory (ours_N_S_k.log, liggghts_N_S_k.log,
# and the /usr/bin/time -v reports *.time).
set -euo pipefail

script_dir=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
repo=$(cd "$script_dir/.." && pwd)

# shellcheck source=lib/compare_common.sh
source "$script_dir/lib/compare_common.sh"
bench_usage_lines='4,17'

steps=50000; thermo=""; np=1; ours_threads=""; rebuild=0
bench_extra_option() {
  case "$1" in
    --thermo) thermo=${2:?--thermo needs a value}; bench_consumed=2 ;;
    --np) np=${2:?--np needs a value}; bench_consumed=2 ;;
    --threads) ours_threads=${2:?--threads needs a value}; bench_consumed=2 ;;
    --rebuild) rebuild=1; bench_consumed=1 ;;
  esac
}
bench_parse_args "$@"
((${#positional[@]} >= 1 && ${#positional[@]} <= 2)) || bench_usage
n=${positional[0]}
((${#positional[@]} == 2)) && steps=${positional[1]}
[[ "$n" =~ ^[0-9]+$ && "$steps" =~ ^[0-9]+$ && "$np" =~ ^[0-9]+$ ]] || bench_usage
((np >= 1)) || bench_usage
ours_threads=${ours_threads:-$np}
[[ "$ours_threads" =~ ^[0-9]+$ ]] && ((ours_threads >= 1)) || bench_usage
[[ -n "$thermo" ]] || thermo=$(( steps >= 10 ? steps / 10 : 1 ))

scene=$repo/bench/deposition
work=$(bench_work_dir)
liggghts=${LIGGGHTS:-liggghts}
bench="$repo/build/release/bench/demlink-bench-deposition"

[[ -x /usr/bin/time ]] || { echo "/usr/bin/time not found (Debian package 'time')" >&2; exit 1; }
command -v "$liggghts" >/dev/null || { echo "$liggghts not found (Debian package 'liggghts')" >&2; exit 1; }
liggghts_launch=()
if ((np > 1)); then
  command -v mpirun >/dev/null || { echo "mpirun not found (needed for --np $np)" >&2; exit 1; }
  liggghts_launch=(mpirun -np "$np")
  (($(id -u) == 0)) && liggghts_launch+=(--allow-run-as-root)
fi

if ((rebuild)) || [[ ! -x "$bench" ]]; then
  echo "== building demlink-bench-deposition (release)"
  (cd "$repo" && cmake --preset release -G Ninja >/dev/null &&
     cmake --build build/release --target demlink-bench-deposition)
elif [[ -n "$(find "$repo/core" "$repo/bench/deposition_bench.cpp" -newer "$bench" \
                \( -name '*.cpp' -o -name '*.hpp' -o -name CMakeLists.txt \) -print -quit)" ]]; then
  echo "warning: $bench is older than core/ or bench/deposition_bench.cpp; pass --rebuild to measure the current code" >&2
fi
revision=$(git -C "$repo" describe --always --dirty 2>/dev/null || echo unknown)

cd "$work"
cp "$scene/in.deposition" in.deposition
if [[ ! -f "init_$n.txt" || ! -f "init_$n.data" ]]; then
  echo "== make_particles.py $n"
  python3 "$scene/make_particles.py" "$n"
fi

prefix="${n}_${steps}_"
((np > 1 || ours_threads > 1)) && prefix="${n}_${steps}_np${np}_t${ours_threads}_"
for ((k = 1; k <= runs; ++k)); do
  tag="$prefix$k"
  echo "== run $k/$runs: DEMLink (N=$n, steps=$steps, threads=$ours_threads; load average $(cut -d" " -f1-3 /proc/loadavg))"
  /usr/bin/time -v -o "ours_$tag.time" \
    "$bench" "init_$n.txt" --steps "$steps" --thermo "$thermo" --threads "$ours_threads" > "ours_$tag.log" 2>&1 ||
    { echo "DEMLink run failed, see $work/ours_$tag.log" >&2; tail -5 "ours_$tag.log" >&2; exit 1; }
  echo "== run $k/$runs: LIGGGHTS (N=$n, steps=$steps, ranks=$np; load average $(cut -d" " -f1-3 /proc/loadavg))"
  /usr/bin/time -v -o "liggghts_$tag.time" \
    ${liggghts_launch[@]+"${liggghts_launch[@]}"} \
    "$liggghts" -in in.deposition -var N "$n" -var steps "$steps" -var tout "$thermo" -var px "$np" \
    -log "liggghts_$tag.lammpslog" > "liggghts_$tag.log" 2>&1 ||
    { echo "LIGGGHTS run failed, see $work/liggghts_$tag.log" >&2; tail -5 "liggghts_$tag.log" >&2; exit 1; }
done

python3 - "$n" "$steps" "$runs" "$revision" "$np" "$prefix" "$ours_threads" <<'PY'
import os, platform, re, statistics, sys, time

n, steps, runs, revision, np_ = int(sys.argv[1]), int(sys.argv[2]), int(sys.argv[3]), sys.argv[4], int(sys.argv[5])
prefix = sys.argv[6]

def elapsed_and_rss(path):
    text = open(path).read()
    m = re.search(r"Elapsed \(wall clock\) time \(h:mm:ss or m:ss\): (\S+)", text)
    parts = [float(x) for x in m.group(1).split(":")]
    seconds = 0.0
    for p in parts:
        seconds = seconds * 60.0 + p
    rss_kb = int(re.search(r"Maximum resident set size \(kbytes\): (\d+)", text).group(1))
    cpu = sum(float(re.search(rf"{k} time \(seconds\): (\S+)", text).group(1)) for k in ("User", "System"))
    return seconds, rss_kb / 1024.0, cpu

def ours(tag):
    text = open(f"ours_{tag}.log").read()
    val = lambda key: float(re.search(rf"^{key} (\S+)$", text, re.M).group(1))
    return {"loop": val("wall_seconds"), "mean_z": val("final_mean_z"), "max_z": val("final_max_z"),
            "ke": val("final_ke_translational"), "ker": val("final_ke_rotational"),
            "builds": val("neighbour_builds")}

def liggghts(tag):
    lines = open(f"liggghts_{tag}.log").read().splitlines()
    loop_idx = next(i for i, l in enumerate(lines) if l.startswith("Loop time of"))
    loop = float(lines[loop_idx].split()[3])  # "Loop time of X on P procs for S steps ..."
    final = None
    for l in lines[:loop_idx]:
        f = l.split()
        if len(f) == 8 and f[0] == str(steps):
            final = [float(x) for x in f]
    if final is None:
        raise SystemExit(f"no final thermo line (step {steps}) in liggghts_{tag}.log")
    builds = next((float(l.split("=")[1]) for l in lines if l.startswith("Neighbor list builds")), float("nan"))
    # Step Time Atoms c_ket c_ker c_zmx c_zav CPU
    return {"loop": loop, "mean_z": final[6], "max_z": final[5], "ke": final[3], "ker": final[4], "builds": builds}

rows = {}
for code, parse in (("ours", ours), ("liggghts", liggghts)):
    samples = []
    for k in range(1, runs + 1):
        tag = f"{prefix}{k}"
        d = parse(tag)
        d["elapsed"], d["rss"], d["cpu"] = elapsed_and_rss(f"{code}_{tag}.time")
        samples.append(d)
    med = {key: statistics.median(s[key] for s in samples) for key in samples[0]}
    med["rate"] = n * steps / med["loop"] / 1e6
    med["rate_elapsed"] = n * steps / med["elapsed"] / 1e6
    med["rate_cpu"] = n * steps / med["cpu"] / 1e6
    med["loops"] = [s["loop"] for s in samples]
    med["cpus"] = [s["cpu"] for s in samples]
    rows[code] = med

ours_threads = int(sys.argv[7])
label = {"ours": "DEMLink" + (f" ({ours_threads} threads)" if ours_threads > 1 else ""),
         "liggghts": "LIGGGHTS" + (f" ({np_} MPI ranks)" if np_ > 1 else "")}
note = f" (median of {runs})" if runs > 1 else ""
print(f"\ndeposition-{n}, {steps} steps{note}; rate = N*steps/loop time; elapsed, CPU = /usr/bin/time"
      " wall and user+system time")
cpu = next((l.split(":", 1)[1].strip() for l in open("/proc/cpuinfo") if l.startswith("model name")), "?")
print(f"{time.strftime('%Y-%m-%d %H:%M %Z')}, {platform.node()}, {os.cpu_count()} CPUs ({cpu}), "
      f"DEMLink {revision}, load average now {os.getloadavg()[0]:.2f}")
hdr = ("code", "elapsed s", "CPU s", "loop s", "M p-steps/s", "peak RSS MB", "nbr builds", "mean z m", "max z m",
       "KE trans J", "KE rot J")
print("| " + " | ".join(hdr) + " |")
print("|" + "---|" * len(hdr))
for code in ("ours", "liggghts"):
    r = rows[code]
    print(f"| {label[code]} | {r['elapsed']:.2f} | {r['cpu']:.2f} | {r['loop']:.2f} | {r['rate']:.2f} | {r['rss']:.1f} | "
          f"{r['builds']:.0f} | {r['mean_z']:.5f} | {r['max_z']:.4f} | {r['ke']:.3e} | {r['ker']:.3e} |")
if runs > 1:
    for code in ("ours", "liggghts"):
        print(f"{label[code]} loop times: " + ", ".join(f"{x:.2f}" for x in rows[code]["loops"]) +
              "; CPU times: " + ", ".join(f"{x:.2f}" for x in rows[code]["cpus"]))
o, l = rows["ours"], rows["liggghts"]
print(f"\nparticle-steps/s ratio DEMLink/LIGGGHTS: {o['rate'] / l['rate']:.2f} (loop), "
      f"{o['rate_elapsed'] / l['rate_elapsed']:.2f} (elapsed), {o['rate_cpu'] / l['rate_cpu']:.2f} (CPU time)")
print(f"peak RSS ratio DEMLink/LIGGGHTS:        {o['rss'] / l['rss']:.2f}" +
      (" (LIGGGHTS: largest single rank)" if np_ > 1 else ""))
rel = (o["mean_z"] - l["mean_z"]) / l["mean_z"]
print(f"final mean z relative difference:       {100 * rel:+.2f} % (DEMLink vs LIGGGHTS)")
PY
