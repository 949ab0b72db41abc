#!/usr/bin/env python3
"""PNG plots of the excavator-and-truck co-simulation from the clients' CSV files.

Why a script, not the clients: the system models write plain CSV (one row per sample) so
they stay free of plotting libraries; this turns those rows into the pictures a user
checks first (does the bucket fill while digging and empty at the dump, does the truck's
load step up with each dump, does the axle load shift when it accelerates and turns).
matplotlib from Debian (python3-matplotlib) with the Agg backend: no display needed.

    excavator.png: bucket fill mass; cylinder forces            (vs time)
    truck.png:     load mass; axle forces (front/rear) and side forces (left/right, dashed);
                   frame acceleration and yaw rate (vs time)

The CSV column names live in the two tables below (EXCAVATOR_COLUMNS, TRUCK_COLUMNS),
the one place to change when a model's header changes; --column excavator.bucket_fill=NAME
overrides one entry for a run. A missing file or column is an error naming it (exit 2).
It also prints a one-line summary of each file (largest bucket fill, peak cylinder force,
final truck load) for scripts to quote.

Usage: plot_cosim.py [--excavator excavator.csv] [--truck truck.csv] --output-dir DIR
"""

import argparse
import csv
import math
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from csv_cell import cell_number  # noqa: E402  (same folder)

# Role -> CSV column (a list for roles drawn as several curves). As the models wrote them
# when this was written (examples/excavator/main.cpp, examples/truck/truck_client.cpp).
EXCAVATOR_COLUMNS = {
    "time": "time",
    "bucket_fill": "fill_mass",
    "cylinder_forces": ["boom_force", "stick_force", "bucket_force"],
}
TRUCK_COLUMNS = {
    "time": "time_s",
    "load": "load_mass_kg",
    "axle_forces": ["axle_front_N", "axle_rear_N"],
    "side_forces": ["side_left_N", "side_right_N"],
    "acceleration": ["frame_ax_m_s2", "frame_ay_m_s2"],
    "yaw_rate": "yaw_rate_rad_s",
}


class PlotInputError(Exception):
    """A missing file or column, or a value that is not a number; the message names it."""


def read_columns(path, mapping, what):
    """{column name: [float]} for every column the mapping names."""
    try:
        with open(path, newline="") as f:
            # '#' lines carry model parameters (truck.csv's first line), not data.
            rows = [row for row in csv.reader(line for line in f if not line.startswith("#")) if row]
    except OSError as e:
        raise PlotInputError(f"{what} file {path}: cannot read ({e.strerror})") from None
    if len(rows) < 2:
        raise PlotInputError(f"{what} file {path}: needs a header and at least one data row")
    header = [h.strip() for h in rows[0]]
    data = {}
    for role, names in mapping.items():
        for name in names if isinstance(names, list) else [names]:
            if name not in header:
                raise PlotInputError(
                    f"{what} file {path}: no column '{name}' (role '{role}'); header: {', '.join(header)}. "
                    f"Fix the table at the top of scripts/plot_cosim.py or pass --column {what}.{role}=NAME")
            i = header.index(name)
            try:
                data[name] = [cell_number(row[i]) for row in rows[1:]]  # an empty cell: NaN, not drawn
            except (ValueError, IndexError):
                raise PlotInputError(f"{what} file {path}: column '{name}' has a value that is not a number") from None
    return data


def as_list(names):
    return names if isinstance(names, list) else [names]


def finite_max(values, key=lambda v: v):
    finite = [v for v in values if math.isfinite(v)]
    return max(finite, key=key) if finite else float("nan")


def plot_excavator(plt, data, mapping, out_dir):
    t = data[mapping["time"]]
    fig, (fill_ax, force_ax) = plt.subplots(2, 1, sharex=True, figsize=(9, 6.5))
    fill_ax.plot(t, data[mapping["bucket_fill"]], color="tab:brown")
    fill_ax.set_ylabel("bucket fill mass [kg]")
    fill_ax.set_title("Excavator: bucket fill and cylinder forces")
    for name in as_list(mapping["cylinder_forces"]):
        force_ax.plot(t, [f / 1e3 for f in data[name]], label=name)
    force_ax.set_ylabel("cylinder force [kN]")
    force_ax.set_xlabel("time [s]")
    force_ax.legend(loc="best", fontsize="small")
    for ax in (fill_ax, force_ax):
        ax.grid(True, alpha=0.3)
    fig.tight_layout()
    png = os.path.join(out_dir, "excavator.png")
    fig.savefig(png, dpi=110)
    plt.close(fig)
    forces = [abs(f) for name in as_list(mapping["cylinder_forces"]) for f in data[name]]
    print(f"plot_cosim: {png}: largest bucket fill {finite_max(data[mapping['bucket_fill']]):.4g} kg, "
          f"peak cylinder force {finite_max(forces) / 1e3:.4g} kN")
    return png


def plot_truck(plt, data, mapping, out_dir):
    t = data[mapping["time"]]
    fig, (load_ax, axle_ax, motion_ax) = plt.subplots(3, 1, sharex=True, figsize=(9, 8.5))
    load_ax.plot(t, data[mapping["load"]], color="tab:brown")
    load_ax.set_ylabel("load mass [kg]")
    load_ax.set_title("Truck: load, axle forces, frame motion")
    # Front/rear shows the shift when accelerating, left/right the shift when turning.
    for name in as_list(mapping["axle_forces"]):
        axle_ax.plot(t, [f / 1e3 for f in data[name]], label=name)
    for name in as_list(mapping["side_forces"]):
        axle_ax.plot(t, [f / 1e3 for f in data[name]], linestyle="--", label=name)
    axle_ax.set_ylabel("suspension force [kN]")
    axle_ax.legend(loc="best", fontsize="small")
    for name, style in zip(as_list(mapping["acceleration"]), ("-", "--", ":")):
        motion_ax.plot(t, data[name], color="tab:blue", linestyle=style, label=name)
    motion_ax.set_ylabel("frame acceleration [m/s²]", color="tab:blue")
    motion_ax.legend(loc="upper left", fontsize="small")
    yaw_ax = motion_ax.twinx()
    yaw_ax.plot(t, data[mapping["yaw_rate"]], color="tab:red")
    yaw_ax.set_ylabel("yaw rate [rad/s]", color="tab:red")
    motion_ax.set_xlabel("time [s]")
    for ax in (load_ax, axle_ax, motion_ax):
        ax.grid(True, alpha=0.3)
    fig.tight_layout()
    png = os.path.join(out_dir, "truck.png")
    fig.savefig(png, dpi=110)
    plt.close(fig)
    load = [v for v in data[mapping["load"]] if math.isfinite(v)]
    print(f"plot_cosim: {png}: final load {load[-1] if load else float('nan'):.4g} kg, "
          f"largest load {finite_max(load):.4g} kg")
    return png


def apply_overrides(overrides, tables):
    for text in overrides:
        key, sep, column = text.partition("=")
        table_name, dot, role = key.partition(".")
        if not sep or not dot or table_name not in tables or role not in tables[table_name] or not column:
            raise PlotInputError(f"--column {text}: expected excavator.ROLE=NAME or truck.ROLE=NAME with ROLE one of "
                                 + "; ".join(f"{n}: {', '.join(t)}" for n, t in tables.items()))
        table = tables[table_name]
        table[role] = column.split(",") if isinstance(table[role], list) else column


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0],
                                     formatter_class=argparse.RawDescriptionHelpFormatter, epilog=__doc__)
    parser.add_argument("--excavator", help="the excavator's CSV (excavator.csv)")
    parser.add_argument("--truck", help="the truck's CSV (truck.csv)")
    parser.add_argument("--output-dir", required=True, help="where the PNGs go (created if missing)")
    parser.add_argument("--column", action="append", default=[], metavar="TABLE.ROLE=NAME",
                        help="override one column name (comma-separated names for a list role)")
    args = parser.parse_args()
    if not args.excavator and not args.truck:
        parser.error("give --excavator and/or --truck")
    tables = {"excavator": dict(EXCAVATOR_COLUMNS), "truck": dict(TRUCK_COLUMNS)}
    try:
        apply_overrides(args.column, tables)
        # Every input is read and checked before matplotlib is loaded (a second or so).
        excavator = args.excavator and read_columns(args.excavator, tables["excavator"], "excavator")
        truck = args.truck and read_columns(args.truck, tables["truck"], "truck")
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
        os.makedirs(args.output_dir, exist_ok=True)
        if excavator:
            plot_excavator(plt, excavator, tables["excavator"], args.output_dir)
        if truck:
            plot_truck(plt, truck, tables["truck"], args.output_dir)
    except PlotInputError as e:
        print(f"plot_cosim: error: {e}", file=sys.stderr)
        return 2
    except ImportError as e:
        print(f"plot_cosim: error: matplotlib is missing ({e}); install Debian's python3-matplotlib "
              "(scripts/install_deps.sh)", file=sys.stderr)
        return 2
    return 0


if __name__ == "__main__":
    sys.exit(main())
