#!/usr/bin/env python3
"""The excavator-and-truck demo's summary and mass balance, from the server's sensor CSVs.

Why a separate script: the mass of the site is spread over components that each write their
own CSV (the pit, the ground around it in four spill regions, the bucket, the truck bed) and
the run log (particles removed at the domain bounds). Every particle must be in exactly one
of them at the end, when the bucket is lifted out of the pit:

    pit + bucket + truck + spill + removed = pit at t = 0        (to rounding)

Prints the mass dug (pit at t = 0 minus pit at the end), delivered (truck at the end),
spilled, the balance and, from the excavator's summary, the peak cylinder force and the
mass carried per cycle.

    cosim_summary.py SIM_DIR [--excavator-summary FILE] [--rel-tol 1e-9]
                     [--min-delivered-fraction F]

With --min-delivered-fraction (needs --excavator-summary) it also checks that the load that
left the bucket arrived in the truck: delivered >= F x the sum of the cycles' carried mass
(some may bounce off the body onto the ground; none may appear from nowhere: delivered
<= carried + 1 %).

Exit code 0: balanced (and delivered); 1: unbalanced (a particle is in none of the
regions, or in two) or not delivered; 2: bad input (missing file or column), with a
message naming it.
"""

import argparse
import csv
import glob
import math
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from check_mass_balance import InputProblem, read_series  # noqa: E402  (same folder)
from csv_cell import cell_number, is_missing  # noqa: E402

TIME_COLUMNS = ["time_s"]


def last_shared(series_by_name):
    """The latest time every series has a row for, and each series' mass then."""
    shared = set.intersection(*(set(s.keys()) for s in series_by_name.values()))
    if not shared:
        raise InputProblem("the sensor CSVs share no sample time: " + ", ".join(series_by_name))
    key = max(shared)
    return series_by_name[next(iter(series_by_name))][key][0], {n: s[key][1] for n, s in series_by_name.items()}


def removed_at_bounds(sim_dir):
    """Mass removed at the domain bounds [kg]: run_log.csv's row 'timing,removed_mass_at_bounds,KG,kg'."""
    path = os.path.join(sim_dir, "run_log.csv")
    try:
        with open(path, newline="") as f:
            rows = list(csv.reader(f))
    except OSError as e:
        raise InputProblem(f"{path}: cannot read ({e.strerror})") from None
    for row in rows:
        if len(row) >= 3 and row[0] == "timing" and row[1] == "removed_mass_at_bounds":
            try:
                value = cell_number(row[2])
            except ValueError:
                value = math.nan
            if is_missing(value) or value < 0:
                raise InputProblem(f"{path}: removed_mass_at_bounds = '{row[2]}' is not a mass >= 0")
            return value
    # Written when a run ends (with the timing rows): missing means it did not end.
    raise InputProblem(f"{path}: no 'timing,removed_mass_at_bounds' row (the run did not end, or the "
                       "server predates the row)")


def excavator_numbers(path):
    """key = value lines of excavator_summary.txt."""
    values = {}
    try:
        with open(path) as f:
            for line in f:
                key, sep, value = line.partition("=")
                if sep:
                    values[key.strip()] = float(value)
    except OSError:
        raise InputProblem(f"{path}: cannot read") from None
    except ValueError:
        raise InputProblem(f"{path}: '{line.strip()}' is not key = number") from None
    return values


def summarize(args):
    def csv_of(name):
        return os.path.join(args.sim_dir, f"region_sensor_{name}.csv")

    spills = sorted(os.path.basename(p)[len("region_sensor_"):-len(".csv")]
                    for p in glob.glob(csv_of("spill_*")))
    names = ["pit_contents", "bucket_fill", "truck_load"] + spills
    series = {n: read_series(csv_of(n), "mass_kg", TIME_COLUMNS) for n in names}
    pit = series["pit_contents"]
    initial = pit[min(pit)][1]
    t_end, mass = last_shared(series)
    removed = removed_at_bounds(args.sim_dir)
    spilled = math.fsum(mass[n] for n in spills)
    accounted = math.fsum(mass.values()) + removed
    residual = accounted - initial
    tolerance = args.rel_tol * initial
    print(f"site mass at t = 0 (pit): {initial:10.1f} kg")
    print(f"mass dug from the pit:    {initial - mass['pit_contents']:10.1f} kg")
    print(f"mass delivered (truck):   {mass['truck_load']:10.1f} kg")
    print(f"spilled on the ground:    {spilled:10.1f} kg  ({', '.join(f'{n} {mass[n]:.1f}' for n in spills)})")
    print(f"left in the bucket:       {mass['bucket_fill']:10.1f} kg")
    print(f"removed at the bounds:    {removed:10.1f} kg")
    print(f"mass balance at t = {t_end:.3f} s: pit + bucket + truck + spill + removed = {accounted:.6f} kg, "
          f"initial {initial:.6f} kg, residual {residual:+.3g} kg (tolerance {tolerance:.3g} kg)")
    failed = False
    if args.excavator_summary:
        ex = excavator_numbers(args.excavator_summary)
        forces = {k[len("peak_force_"):-len("_N")]: v for k, v in ex.items() if k.startswith("peak_force_")}
        if forces:
            name = max(forces, key=forces.get)
            print(f"peak cylinder force:      {forces[name] / 1e3:10.1f} kN ({name})")
        if "real_time_factor" in ex and "simulated_s" in ex and "wall_s" in ex:
            print(f"real-time factor:         {ex['real_time_factor']:10.3f}    ({ex['simulated_s']:.2f} s simulated in "
                  f"{ex['wall_s']:.1f} s wall after the compile; the pit's settling is before it)")
        cycle = 1
        while f"cycle_{cycle}_carried_kg" in ex:
            print(f"cycle {cycle}: carried {ex[f'cycle_{cycle}_carried_kg']:.1f} kg to the truck, "
                  f"{ex.get(f'cycle_{cycle}_after_dump_kg', float('nan')):.1f} kg left after the dump, "
                  f"peak fill {ex.get(f'cycle_{cycle}_peak_fill_kg', float('nan')):.1f} kg")
            cycle += 1
        if args.min_delivered_fraction is not None:
            carried = math.fsum(ex[f"cycle_{c}_carried_kg"] for c in range(1, cycle))
            delivered = mass["truck_load"]
            ok = carried > 0 and args.min_delivered_fraction * carried <= delivered <= 1.01 * carried
            print(f"bucket -> truck: carried {carried:.1f} kg in {cycle - 1} cycle(s), delivered {delivered:.1f} kg "
                  f"({delivered / carried if carried > 0 else float('nan'):.1%}; required "
                  f"{args.min_delivered_fraction:.0%} .. 101 %)")
            if not ok:
                print("cosim_summary: the load that left the bucket did NOT arrive in the truck", file=sys.stderr)
                failed = True
    elif args.min_delivered_fraction is not None:
        raise InputProblem("--min-delivered-fraction needs --excavator-summary (the mass carried per cycle)")
    if abs(residual) > tolerance:
        print(f"cosim_summary: mass NOT balanced: {residual:+.6g} kg unaccounted (a particle outside every "
              "region, or in two of them)", file=sys.stderr)
        return 1
    print("cosim_summary: mass balanced")
    return 1 if failed else 0


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0],
                                     formatter_class=argparse.RawDescriptionHelpFormatter, epilog=__doc__)
    parser.add_argument("sim_dir", help="the server's simulation folder (sim_001)")
    parser.add_argument("--excavator-summary", help="demlink-excavator's excavator_summary.txt")
    parser.add_argument("--rel-tol", type=float, default=1e-9, help="balance tolerance relative to the initial mass")
    parser.add_argument("--min-delivered-fraction", type=float,
                        help="require truck load >= this fraction of the mass the bucket carried")
    args = parser.parse_args()
    try:
        return summarize(args)
    except InputProblem as e:
        print(f"cosim_summary: {e}", file=sys.stderr)
        return 2


if __name__ == "__main__":
    sys.exit(main())
