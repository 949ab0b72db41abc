#!/usr/bin/env python3
"""Tables and PNG plots of the speed-for-accuracy atlas (demlink-study, docs/accuracy.md).

Reads atlas.csv and coupling.csv from the study's output directory and writes
    atlas_tradeoff.png  per knob: speed-up against the finest run vs the largest bulk error
    atlas_metrics.png   every bulk quantity's relative error vs each knob's value
    coupling.png        the coupled plate's depth error and oscillation vs interval
and prints the Markdown tables docs/accuracy.md quotes. matplotlib with the Agg backend
(no display needed).

Every statistic comes from atlas.csv's per-run rows: with several seeds per setting the
tables give each error with its standard error, bold when it is resolved (beyond two
standard errors), and a noise-floor row (the finest setting's seed-to-seed spread).

Usage: plot_atlas.py DIR [MORE_ATLAS_CSV...]   (DIR holds atlas.csv and coupling.csv; more
       files of a sweep split over processes are read with it)
"""

import csv
import math
import os
import sys
from collections import OrderedDict

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from csv_cell import cell_number  # noqa: E402  (same folder)

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

BULK_SCENES = ("bed", "bed_cohesive", "heap", "hopper")
# (scene, metric) -> column label
METRICS = OrderedDict([
    (("impact", "restitution_ratio"), "e ratio"),
    (("bed", "packing_fraction"), "packing"),
    (("bed", "drag_force"), "blade drag"),
    (("bed_cohesive", "drag_force"), "cohesive drag"),
    (("heap", "repose_angle_deg"), "repose angle"),
    (("hopper", "discharge_rate"), "discharge"),
])


def number(text):
    """A cell's number; NaN for an empty cell (missing, csv_cell.py) or a cell that is not one."""
    try:
        return cell_number(text)
    except (AttributeError, TypeError, ValueError):
        return math.nan


def mean_and_error(values):
    """Mean and standard error of the mean (NaN for fewer than two values)."""
    if not values:
        return math.nan, math.nan
    mean = sum(values) / len(values)
    if len(values) < 2:
        return mean, math.nan
    variance = sum((v - mean) ** 2 for v in values) / (len(values) - 1)
    return mean, math.sqrt(variance / len(values))


def load_atlas(paths):
    """OrderedDict (knob, value) -> {"scenes": {scene: [rows]}, "metrics": {(scene, metric): stats}}.

    Several files (a sweep split over processes) are read as one; every statistic is
    recomputed here from the per-run rows: per setting and metric the mean over the seeds
    and its standard error, the error against the finest setting's mean, its standard
    error, and whether it is resolved (beyond twice that standard error)."""
    settings = OrderedDict()
    for path in paths:
        with open(path, newline="") as f:
            for row in csv.DictReader(f):
                entry = settings.setdefault((row["knob"], row["value"]), {"scenes": OrderedDict(), "values": {}})
                runs = entry["scenes"].setdefault(row["scene"], OrderedDict())
                runs[row["seed"]] = row
                if row["metric"] and row["status"] == "ok":
                    values = entry["values"].setdefault((row["scene"], row["metric"]), OrderedDict())
                    values[row["seed"]] = number(row["metric_value"])
    rows = [row for entry in settings.values() for runs in entry["scenes"].values() for row in runs.values()]
    COST_COLUMN[0] = "cpu_s" if all(row.get("cpu_s") for row in rows) else "wall_s"
    reference = settings.get(("reference", "finest"), {"values": {}})["values"]
    second_seed = settings.get(("seed", "2"), {"values": {}})["values"]
    for entry in settings.values():
        entry["metrics"] = {}
        for key, by_seed in entry["values"].items():
            values = list(by_seed.values())
            mean, error = mean_and_error(values)
            ref_values = list(reference.get(key, {}).values())
            ref_mean, ref_error = mean_and_error(ref_values)
            if not math.isfinite(error) and len(ref_values) >= 2:
                # One seed: its scatter is taken to be the finest setting's.
                error = ref_error * math.sqrt(len(ref_values) / len(values))
            if len(ref_values) >= 2:
                noise = ref_error * math.sqrt(len(ref_values)) / abs(ref_mean)
            elif key in second_seed and ref_values:
                noise = abs(list(second_seed[key].values())[0] - ref_mean) / abs(ref_mean)
            else:
                noise = math.nan
            combined = math.hypot(error, ref_error)
            entry["metrics"][key] = {
                "seeds": len(values), "mean": mean, "error": error,
                "relative_error": (mean - ref_mean) / ref_mean if ref_mean else math.nan,
                "relative_error_se": combined / abs(ref_mean) if ref_mean else math.nan,
                "resolved": abs(mean - ref_mean) > 2.0 * combined if math.isfinite(combined) else None,
                "noise_floor": noise,
            }
    return settings


COST_COLUMN = ["cpu_s"]  # "wall_s" when a row has no CPU time (load_atlas decides)


def bulk_wall(entry):
    """Mean CPU seconds over the seeds of the bulk scenes (wall seconds when some row of
    the files has no CPU time), or NaN when one broke or did not run. CPU time is the
    cost that survives a shared machine's load; mixing the two would not compare."""
    total = 0.0
    for scene in BULK_SCENES:
        runs = entry["scenes"].get(scene)
        if not runs or any(row["status"] != "ok" for row in runs.values()):
            return math.nan
        total += sum(number(row[COST_COLUMN[0]]) for row in runs.values()) / len(runs)
    return total


def status(entry):
    broken = [s for s, runs in entry["scenes"].items() if any(row["status"] != "ok" for row in runs.values())]
    return "ok" if not broken else "broke: " + ", ".join(broken)


def error_cell(stats):
    """'+12.3 ± 4.5 %' (the standard error), bold when resolved; no ± for one seed."""
    value = 100.0 * stats["relative_error"]
    if not math.isfinite(stats["relative_error_se"]):
        return "%+.1f %%" % value
    text = "%+.1f ± %.1f %%" % (value, 100.0 * stats["relative_error_se"])
    return "**%s**" % text if stats["resolved"] else text


def atlas_table(settings):
    reference = settings[("reference", "finest")]
    ref_wall = bulk_wall(reference)
    lines = ["| knob | value | seeds | dt [s] | speed-up | M particle-steps/s (bed) | "
             + " | ".join(METRICS.values()) + " | status |",
             "|---|---|---|---|---|---|" + "---|" * len(METRICS) + "---|"]
    for (knob, value), entry in settings.items():
        wall = bulk_wall(entry)
        speedup = ref_wall / wall if wall > 0 else math.nan
        bed = list(entry["scenes"].get("bed", {}).values())
        rate = sum(number(r["particle_steps_per_s"]) for r in bed) / len(bed) / 1e6 if bed else math.nan
        dt = number(next(iter(next(iter(entry["scenes"].values())).values()))["dt_s"])
        seeds = max((s["seeds"] for s in entry["metrics"].values()), default=0)
        cells = []
        for key in METRICS:
            stats = entry["metrics"].get(key)
            if stats is None:
                cells.append("—")
            elif knob == "reference":
                cells.append("%.4g" % stats["mean"] + (" ± %.2g" % stats["error"] if math.isfinite(stats["error"]) else ""))
            else:
                cells.append(error_cell(stats))
        lines.append("| %s | %s | %d | %.3g | %s | %s | %s | %s |" % (
            knob, value, seeds, dt, "%.2f" % speedup if math.isfinite(speedup) else "—",
            "%.2f" % rate if math.isfinite(rate) else "—", " | ".join(cells), status(entry)))
    noise = ["%.1f %%" % (100.0 * reference["metrics"][k]["noise_floor"])
             if k in reference["metrics"] and math.isfinite(reference["metrics"][k]["noise_floor"]) else "—"
             for k in METRICS]
    lines.append("| noise floor | seed-to-seed | | | | | %s | |" % " | ".join(noise))
    return "\n".join(lines)


def load_coupling(path):
    with open(path, newline="") as f:
        rows = list(csv.DictReader(f))
    reference = {(r["mass_kg"], r["order"]): number(r["depth_m"]) for r in rows
                 if r["interval_steps"] == "1" and r["status"] == "ok"}
    for r in rows:
        r["depth_error_m"] = str(number(r["depth_m"]) - reference.get((r["mass_kg"], r["order"]), math.nan))
    return rows


def coupling_table(rows):
    lines = ["| order | mass [kg] | interval [steps] | interval [s] | status | depth [mm] | error [mm] | "
             "oscillation [mm] |", "|---|---|---|---|---|---|---|---|"]
    for r in rows:
        ok = r["status"] == "ok"
        lines.append("| %s | %s | %s | %.3g | %s | %s | %s | %s |" % (
            r["order"], r["mass_kg"], r["interval_steps"], number(r["interval_s"]), r["status"],
            "%.3f" % (1e3 * number(r["depth_m"])) if ok else "—",
            "%+.3f" % (1e3 * number(r["depth_error_m"])) if ok else "—",
            "%.3f" % (1e3 * number(r["oscillation_m"])) if ok else "—"))
    return "\n".join(lines)


def plot_tradeoff(settings, path):
    reference = settings[("reference", "finest")]
    ref_wall = bulk_wall(reference)
    fig, ax = plt.subplots(figsize=(7, 5))
    knobs = OrderedDict()
    for (knob, value), entry in settings.items():
        if knob == "reference":
            continue
        wall = bulk_wall(entry)
        errors = [abs(entry["metrics"][m]["relative_error"]) for m in METRICS
                  if m in entry["metrics"] and m[1] != "drag_force" and entry["metrics"][m]["resolved"] is not False]
        if not (wall > 0) or not errors:
            continue
        knobs.setdefault(knob, []).append((ref_wall / wall, 100.0 * max(errors), value))
    for knob, points in knobs.items():
        xs, ys, labels = zip(*points)
        ax.plot(xs, ys, "o-", label=knob)
        for x, y, label in points:
            ax.annotate(label, (x, y), fontsize=7, xytext=(3, 3), textcoords="offset points")
    ax.set_xscale("log")
    ax.set_yscale("symlog", linthresh=1.0)
    ax.set_ylim(bottom=0.0)  # an absolute error: no negative half of the symlog axis
    ax.set_xlabel("speed-up against the finest run (bulk scenes' %s)" % COST_COLUMN[0])
    ax.set_ylabel("largest resolved |relative error| of packing, angle, discharge, e [%]")
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(path, dpi=120)


def plot_metrics(settings, path):
    knobs = OrderedDict()
    for (knob, value), entry in settings.items():
        if knob in ("reference", "seed"):
            continue
        knobs.setdefault(knob, []).append((value, entry))
    reference = settings[("reference", "finest")]["metrics"]
    fig, axes = plt.subplots(1, len(knobs), figsize=(3.2 * len(knobs), 3.8), sharey=True, squeeze=False)
    axes = axes[0]
    for ax, (knob, points) in zip(axes, knobs.items()):
        for key, label in METRICS.items():
            xs, ys, es = [], [], []
            for i, (value, entry) in enumerate(points):
                stats = entry["metrics"].get(key)
                if stats is not None:
                    xs.append(i)
                    ys.append(100.0 * stats["relative_error"])
                    es.append(200.0 * stats["relative_error_se"] if math.isfinite(stats["relative_error_se"]) else 0.0)
            if not xs:
                continue
            line = ax.errorbar(xs, ys, yerr=es, fmt="o-", capsize=2, label=label)
            noise = reference.get(key, {}).get("noise_floor", math.nan)
            if math.isfinite(noise):
                ax.axhspan(-100.0 * noise, 100.0 * noise, alpha=0.06, color=line[0].get_color())
        ax.set_xticks(range(len(points)))
        ax.set_xticklabels([v for v, _ in points], rotation=45, fontsize=7)
        ax.set_title(knob, fontsize=9)
        ax.set_yscale("symlog", linthresh=1.0)
        ax.grid(True, alpha=0.3)
    axes[0].set_ylabel("relative error vs finest [%]\n(bars: 2 standard errors; bands: noise floor)", fontsize=8)
    axes[-1].legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(path, dpi=120)


def plot_coupling(rows, path):
    fig, (a, b) = plt.subplots(1, 2, figsize=(10, 4))
    groups = OrderedDict()
    for r in rows:
        groups.setdefault((r["order"], r["mass_kg"]), []).append(r)
    for (order, mass), rs in groups.items():
        style = "o-" if order == "send_first" else "s--"
        ok = [r for r in rs if r["status"] == "ok"]
        xs = [number(r["interval_s"]) for r in ok]
        a.plot(xs, [1e3 * abs(number(r["depth_error_m"])) + 1e-6 for r in ok], style, label="%s, %s kg" % (order, mass))
        b.plot(xs, [1e3 * number(r["oscillation_m"]) + 1e-6 for r in ok], style, label="%s, %s kg" % (order, mass))
        for r in rs:
            if r["status"] != "ok":
                a.plot(number(r["interval_s"]), 1e1, "rx")
    for ax, label in ((a, "|depth error| vs one step [mm] (x: unstable)"), (b, "oscillation [mm]")):
        ax.set_xscale("log")
        ax.set_yscale("log")
        ax.set_xlabel("communication interval [s]")
        ax.set_ylabel(label)
        ax.grid(True, which="both", alpha=0.3)
    a.legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(path, dpi=120)


def main(argv):
    if len(argv) < 2:
        print(__doc__.strip().splitlines()[-1], file=sys.stderr)
        return 2
    directory = argv[1]
    atlas_path = os.path.join(directory, "atlas.csv")
    coupling_path = os.path.join(directory, "coupling.csv")
    for path in [atlas_path, coupling_path] + argv[2:]:
        if not os.path.exists(path):
            print("missing %s" % path, file=sys.stderr)
            return 2
    settings = load_atlas([atlas_path] + argv[2:])
    rows = load_coupling(coupling_path)
    print(atlas_table(settings))
    print()
    print(coupling_table(rows))
    plot_tradeoff(settings, os.path.join(directory, "atlas_tradeoff.png"))
    plot_metrics(settings, os.path.join(directory, "atlas_metrics.png"))
    plot_coupling(rows, os.path.join(directory, "coupling.png"))
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
