#!/usr/bin/env python3
"""PNG plot of the sheet-impact example (examples/deformable/README.md) from its run's CSV files.

Why from the CSV files: the run writes plain rows (node tracker, summary, broken springs);
this turns them into the picture a user checks first: how far the sheet's centre sags as
the spheres land, how many spheres lie in the world, and how many springs broke.
matplotlib with the Agg backend (no display needed).

    sheet_impact.png: centre node displacement uz (top); particles in the world and broken
                      springs (bottom), against time

Also prints a one-line summary (largest sag, final sag, final particle count, broken
springs). A missing file or column is an error naming it (exit 2).

Usage: plot_sheet.py RUN_DIR [--node sheet_302] [--output sheet_impact.png]
"""

import argparse
import csv
import math
import os
import sys


class PlotInputError(Exception):
    """A missing file or column; the message names it."""


def read_csv(path):
    """{column: [float]} of a CSV file with a header row."""
    try:
        with open(path, newline="") as f:
            rows = [row for row in csv.reader(f) if row]
    except OSError as e:
        raise PlotInputError(f"{path}: cannot read ({e.strerror})") from None
    if not rows:
        raise PlotInputError(f"{path}: empty")
    header = rows[0]
    columns = {name: [] for name in header}
    for row in rows[1:]:
        for name, value in zip(header, row):
            if not value.strip():  # DEMLink writes a value that does not exist as an empty cell
                columns[name].append(math.nan)
                continue
            try:
                columns[name].append(float(value))
            except ValueError:
                columns[name].append(value)
    return columns


def column(table, name, path):
    if name not in table:
        raise PlotInputError(f"{path}: no column {name} (have: {', '.join(table)})")
    return table[name]


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("run_dir")
    parser.add_argument("--node", default="sheet_302", help="node label <body>_<node> in the tracker CSV")
    parser.add_argument("--tracker", default="node_tracker_centre.csv")
    parser.add_argument("--output", default=None, help="PNG path (default: RUN_DIR/sheet_impact.png)")
    args = parser.parse_args()
    try:
        tracker_path = os.path.join(args.run_dir, args.tracker)
        tracker = read_csv(tracker_path)
        t = column(tracker, "time_s", tracker_path)
        uz = column(tracker, f"{args.node}_uz_m", tracker_path)
        summary_path = os.path.join(args.run_dir, "summary.csv")
        summary = read_csv(summary_path)
        ts = column(summary, "time_s", summary_path)
        particles = column(summary, "particles", summary_path)
        broken_path = os.path.join(args.run_dir, "broken_springs.csv")
        broken_times = column(read_csv(broken_path), "time_s", broken_path) if os.path.exists(broken_path) else []
    except PlotInputError as e:
        print(f"plot_sheet.py: {e}", file=sys.stderr)
        return 2

    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, (top, bottom) = plt.subplots(2, 1, figsize=(8, 6), sharex=True)
    top.plot(t, [1000.0 * u for u in uz], color="tab:blue")
    top.set_ylabel(f"node {args.node}: u_z [mm]")
    top.grid(True, alpha=0.3)
    bottom.plot(ts, particles, color="tab:green", label="particles in the world")
    bottom.set_ylabel("particles [-]")
    bottom.set_xlabel("time [s]")
    bottom.grid(True, alpha=0.3)
    broken_axis = bottom.twinx()
    broken_axis.step(sorted(broken_times) + [ts[-1]], list(range(1, len(broken_times) + 1)) + [len(broken_times)],
                     where="post", color="tab:red", label="broken springs")
    broken_axis.set_ylim(0, max(1, 1.1 * len(broken_times)))
    broken_axis.set_ylabel("broken springs [-]", color="tab:red")
    fig.suptitle("Spheres falling on a mass-spring sheet pinned at its corners")
    fig.tight_layout()
    output = args.output or os.path.join(args.run_dir, "sheet_impact.png")
    fig.savefig(output, dpi=120)
    print(f"sheet_impact: largest sag {-1000.0 * min(uz):.1f} mm, final sag {-1000.0 * uz[-1]:.1f} mm, "
          f"final particles {int(particles[-1])}, broken springs {len(broken_times)} -> {output}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
