#!/usr/bin/env python3
"""Closes bench/run_site_bench.sh: medians per build and fidelity preset, and what each
preset's speed costs in what the excavator model sees, against VALIDATION.

    site_presets_summary.py RESULTS.tsv   (lines starting with # are comments)

Per build (and backend, when a run names one other than native) and preset: the median real-time factor, particle-steps per second per thread,
settling wall time, and the median over runs of the carried mass, peak fill, peak and mean
digging force and truck load. With VALIDATION among the presets, each other preset's
difference from it is taken seed by seed (same bed, same build) and reported as the
median and range over the seeds, beside VALIDATION's own seed-to-seed scatter (sample
standard deviation over the seeds as a share of its mean), and as the mean of the seed-by-
seed differences with its 95 % confidence interval (Student's t over the seeds): a digging
cycle is chaotic (any change of step sends it along another trajectory), so one seed's
difference mixes the step's systematic cost with that spread; the mean over seeds says
which part is systematic, and a mean whose interval holds zero is a cost the bench cannot
resolve.
"""
import csv
import statistics
import sys

METRICS = [("carried_kg", "carried", "kg"), ("peak_fill_kg", "peak fill", "kg"),
           ("dig_force_peak_N", "dig force peak", "N"), ("dig_force_mean_N", "dig force mean", "N"),
           ("truck_load_kg", "truck load", "kg")]


def number(text):
    try:
        return float(text)
    except (TypeError, ValueError):
        return None


def median(values):
    values = [v for v in values if v is not None]
    return statistics.median(values) if values else None


# Two-sided 95 % quantiles of Student's t by degrees of freedom (1..30); beyond, the
# normal 1.96 (at most 4 % narrow).
T95 = [12.706, 4.303, 3.182, 2.776, 2.571, 2.447, 2.365, 2.306, 2.262, 2.228,
       2.201, 2.179, 2.160, 2.145, 2.131, 2.120, 2.110, 2.101, 2.093, 2.086,
       2.080, 2.074, 2.069, 2.064, 2.060, 2.056, 2.052, 2.048, 2.045, 2.042]


def paired_difference(diffs):
    """Mean of seed-by-seed differences, the half-width of its 95 % confidence interval
    (None below 2 seeds), and whether the interval excludes zero: a cost the bench resolves."""
    mean = statistics.mean(diffs)
    if len(diffs) < 2:
        return mean, None, False
    dof = len(diffs) - 1
    t = T95[dof - 1] if dof <= len(T95) else 1.96
    half_width = t * statistics.stdev(diffs) / len(diffs) ** 0.5
    return mean, half_width, abs(mean) > half_width


def show(value, digits=4):
    return "-" if value is None else f"{value:.{digits}g}"


def main(path):
    with open(path, newline="") as f:
        rows = list(csv.DictReader((line for line in f if not line.startswith("#")), delimiter="\t"))
    if not rows:
        print("site_presets_summary: no runs in " + path)
        return 1
    groups = {}
    for row in rows:
        # A build on another backend than the native engine is its own group.
        if row.get("backend") not in (None, "", "native"):
            row["bin"] = f"{row['bin']} ({row['backend']})"
        groups.setdefault((row["bin"], row.get("fidelity", "none")), []).append(row)
    print("medians (real-time factor = simulated s / wall s of the exchanges; settling apart):")
    for (build, preset), runs in groups.items():
        line = (f"  {build} {preset}: real-time factor {show(median(number(r['rtf']) for r in runs), 3)}, "
                f"{show(median(number(r['psteps_per_s_per_thread']) for r in runs), 3)} particle-steps/s per thread, "
                f"settling {show(median(number(r['settle_wall_s']) for r in runs), 3)} s wall, "
                f"dt {show(median(number(r.get('time_step_s')) for r in runs), 3)} s ({len(runs)} runs)")
        print(line)
        metrics = [f"{label} {show(median(number(r.get(key)) for r in runs))} {unit}" for key, label, unit in METRICS]
        if any(number(r.get(METRICS[0][0])) is not None for r in runs):
            print("    " + ", ".join(metrics))
    for build in sorted({b for b, _ in groups}):
        reference = {(r["seed"], r["run"]): r for r in groups.get((build, "validation"), [])}
        if not reference:
            continue
        print(f"\nagainst VALIDATION, seed by seed ({build}):")
        for key, label, unit in METRICS:
            values = [number(r.get(key)) for r in reference.values()]
            values = [v for v in values if v is not None]
            if len(values) >= 2 and statistics.mean(values) != 0.0:
                scatter = statistics.stdev(values) / abs(statistics.mean(values))
                print(f"  VALIDATION {label}: mean {statistics.mean(values):.4g} {unit}, "
                      f"seed-to-seed scatter {100.0 * scatter:.1f} % ({len(values)} seeds)")
        for (b, preset), runs in groups.items():
            if b != build or preset == "validation":
                continue
            for key, label, unit in METRICS:
                diffs = []
                for r in runs:
                    ref = reference.get((r["seed"], r["run"]))
                    a, v = number(r.get(key)), number(ref.get(key)) if ref else None
                    if a is not None and v not in (None, 0.0):
                        diffs.append(100.0 * (a - v) / abs(v))
                if diffs:
                    mean, half_width, resolved = paired_difference(diffs)
                    spread = "" if half_width is None else (
                        f"; mean {mean:+.1f} % +- {half_width:.1f} % (95 %): "
                        + ("resolved" if resolved else "within the trajectories' spread"))
                    print(f"  {preset} {label}: {statistics.median(diffs):+.1f} % median "
                          f"({min(diffs):+.1f} .. {max(diffs):+.1f} %, {len(diffs)} seeds){spread}")
    return 0


if __name__ == "__main__":
    if len(sys.argv) != 2:
        print(__doc__)
        sys.exit(2)
    sys.exit(main(sys.argv[1]))
