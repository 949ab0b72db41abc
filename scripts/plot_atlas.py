#!/usr/bin/env python3
"""Tables and PNG plots of the speed-for-accuracy atlas (demlink-study, docs/accuracy.md).

Reads atlas.csv and coupling.csv from the study's output directory and writes
    atlas_tradeoff.png  per knob: speed-up against the finest run vs the largest bulk error
    atlas_metrics.png   every bulk quantity's relative error vs each knob's value
    coupling.png        the coupled plate's depth error and oscillation vs interval
and prints the Markdown tables docs/accuracy.md quotes. matplotlib with the Agg backend
(no display needed).

Usage: plot_atlas.py DIR        (DIR holds atlas.csv and coupling.csv)
"""

import csv
import math
import os
import sys
from collections import OrderedDict

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

BULK_SCENES = ("bed", "heap", "hopper")
METRICS = OrderedDict([
    ("restitution_ratio", "e ratio"),
    ("packing_fraction", "packing"),
    ("drag_force", "blade drag"),
    ("repose_angle_deg", "repose angle"),
    ("discharge_rate", "discharge"),
])


def number(text):
    try:
        return float(text)
    except ValueError:
        return math.nan


def load_atlas(path):
    """OrderedDict (knob, value) -> {"scenes": {scene: row}, "metrics": {metric: row}}."""
    settings = OrderedDict()
    with open(path, newline="") as f:
        for row in csv.DictReader(f):
            key = (row["knob"], row["value"])
            entry = settings.setdefault(key, {"scenes": {}, "metrics": {}})
            entry["scenes"][row["scene"]] = row
            if row["metric"]:
                entry["metrics"][row["metric"]] = row
    rows = [row for entry in settings.values() for row in entry["scenes"].values()]
    COST_COLUMN[0] = "cpu_s" if all(row.get("cpu_s") for row in rows) else "wall_s"
    # Errors against the finest run, recomputed here so that files of separate runs (a
    # sweep split over processes) can be concatenated.
    reference = settings.get(("reference", "finest"), {"metrics": {}})["metrics"]
    for entry in settings.values():
        for metric, row in entry["metrics"].items():
            ref = number(reference[metric]["metric_value"]) if metric in reference else math.nan
            row["relative_error"] = str((number(row["metric_value"]) - ref) / ref if ref else math.nan)
    return settings


COST_COLUMN = ["cpu_s"]  # "wall_s" when a row has no CPU time (load_atlas decides)


def bulk_wall(entry):
    """CPU seconds of the bulk scenes (wall seconds when some row of the file has no CPU
    time), or NaN when one broke. CPU time is the cost that survives a shared machine's
    load; mixing the two would not compare."""
    total = 0.0
    for scene in BULK_SCENES:
        row = entry["scenes"].get(scene)
        if row is None or row["status"] != "ok":
            return math.nan
        total += number(row[COST_COLUMN[0]])
    return total


def status(entry):
    broken = [s for s, row in entry["scenes"].items() if row["status"] != "ok"]
    return "ok" if not broken else "broke: " + ", ".join(broken)


def atlas_table(settings):
    reference = settings[("reference", "finest")]
    ref_wall = bulk_wall(reference)
    lines = ["| knob | value | dt [s] | speed-up | M particle-steps/s (bed) | "
             + " | ".join(METRICS.values()) + " | status |",
             "|---|---|---|---|---|" + "---|" * len(METRICS) + "---|"]
    for (knob, value), entry in settings.items():
        wall = bulk_wall(entry)
        speedup = ref_wall / wall if wall > 0 else math.nan
        bed = entry["scenes"].get("bed", {})
        rate = number(bed.get("particle_steps_per_s", "nan")) / 1e6
        dt = number(next(iter(entry["scenes"].values()))["dt_s"])
        cells = []
        for metric in METRICS:
            row = entry["metrics"].get(metric)
            if row is None or row["status"] != "ok":
                cells.append("—")
            elif knob == "reference":
                cells.append("%.4g" % number(row["metric_value"]))
            else:
                cells.append("%+.1f %%" % (100.0 * number(row["relative_error"])))
        lines.append("| %s | %s | %.3g | %s | %s | %s | %s |" % (
            knob, value, dt, "%.2f" % speedup if math.isfinite(speedup) else "—",
            "%.2f" % rate if math.isfinite(rate) else "—", " | ".join(cells), status(entry)))
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
        errors = [abs(number(entry["metrics"][m]["relative_error"])) for m in METRICS
                  if m in entry["metrics"] and m != "drag_force"]
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
    ax.set_xlabel("speed-up against the finest run (bulk scenes' %s)" % COST_COLUMN[0])
    ax.set_ylabel("largest |relative error| of packing, angle, discharge, e [%]")
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
    noise = settings.get(("seed", "2"))
    fig, axes = plt.subplots(1, len(knobs), figsize=(3.2 * len(knobs), 3.6), sharey=True)
    for ax, (knob, points) in zip(axes, knobs.items()):
        for metric, label in METRICS.items():
            xs, ys = [], []
            for i, (value, entry) in enumerate(points):
                row = entry["metrics"].get(metric)
                if row is not None and row["status"] == "ok":
                    xs.append(i)
                    ys.append(100.0 * number(row["relative_error"]))
            ax.plot(xs, ys, "o-", label=label)
            if noise is not None and metric in noise["metrics"]:
                ax.axhline(100.0 * number(noise["metrics"][metric]["relative_error"]), ls=":", lw=0.8,
                           color=ax.lines[-1].get_color())
        ax.set_xticks(range(len(points)))
        ax.set_xticklabels([v for v, _ in points], rotation=45, fontsize=7)
        ax.set_title(knob, fontsize=9)
        ax.set_yscale("symlog", linthresh=1.0)
        ax.grid(True, alpha=0.3)
    axes[0].set_ylabel("relative error vs finest [%] (dotted: second seed)")
    axes[-1].legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(path, dpi=120)


def plot_coupling(rows, path):
    fig, (a, b) = plt.subplots(1, 2, figsize=(10, 4))
    groups = OrderedDict()
    for r in rows:
        groups.setdefault((r["order"], r["mass_kg"]), []).append(r)
    for (order, mass), rs in groups.items():
        style = "o-" if order == "exchange" else "s--"
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
    if len(argv) != 2:
        print(__doc__.strip().splitlines()[-1], file=sys.stderr)
        return 2
    directory = argv[1]
    atlas_path = os.path.join(directory, "atlas.csv")
    coupling_path = os.path.join(directory, "coupling.csv")
    for path in (atlas_path, coupling_path):
        if not os.path.exists(path):
            print("missing %s" % path, file=sys.stderr)
            return 2
    settings = load_atlas(atlas_path)
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
