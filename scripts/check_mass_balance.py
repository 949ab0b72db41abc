#!/usr/bin/env python3
"""Checks that a sum of masses read from CSV files stays what it was (mass balance).

Why: a co-simulation's mass is spread over several components that each write their own
CSV (region sensors over the pit, the bucket and the truck bed, a sink that removes spill,
the clients' own logs). Conservation is the check that ties them together:

    pit + bucket + truck + spill + removed = initial   (at every common sample time)

This script knows nothing about excavators: each term is FILE:COLUMN (added), or
--subtract FILE:COLUMN. Rows of different files are matched by their time column
(the first of --time-columns the file has; times equal to within 1e-9 s), and the sum is
checked at every time all files share. The reference is --initial KG if given, otherwise
the sum at the first shared time.

A row whose term or time cell is empty (a value that does not exist, the CSV rule of
csv_cell.py) has no sample to balance: it is skipped, and the skipped rows are counted.

Exit code 0: balanced; 1: out of tolerance (the worst rows are printed); 2: bad input
(a missing file or column, no shared times, a non-number), with a message naming it.

Example (the server's sensor CSVs of one simulation):
    check_mass_balance.py --rel-tol 1e-3 \\
        sim_001/region_sensor_pit.csv:mass_kg sim_001/region_sensor_bucket.csv:mass_kg \\
        sim_001/region_sensor_truck_bed.csv:mass_kg sim_001/particle_sink_spill.csv:removed_mass_total_kg
"""

import argparse
import csv
import math
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from csv_cell import cell_number, is_missing  # noqa: E402  (same folder)

TIME_MATCH_S = 1e-9  # two rows belong to the same sample when their times differ by less [s]


class InputProblem(Exception):
    """Bad input; the message names the file, column or value."""


def parse_term(text, sign):
    path, sep, column = text.rpartition(":")
    if not sep or not path or not column:
        raise InputProblem(f"term '{text}': expected FILE:COLUMN")
    return sign, path, column


def read_series(path, column, time_columns):
    """{rounded time key: (time, value)} of one column of one CSV file."""
    try:
        with open(path, newline="") as f:
            rows = list(csv.reader(f))
    except OSError as e:
        raise InputProblem(f"{path}: cannot read ({e.strerror})") from None
    if not rows:
        raise InputProblem(f"{path}: empty file (no header)")
    header = [h.strip() for h in rows[0]]
    time_column = next((c for c in time_columns if c in header), None)
    if time_column is None:
        raise InputProblem(f"{path}: none of the time columns {time_columns} in header {header}")
    if column not in header:
        raise InputProblem(f"{path}: no column '{column}' (header: {header})")
    ti, vi = header.index(time_column), header.index(column)
    series = {}
    missing = 0
    for line, row in enumerate(rows[1:], start=2):
        if not row:
            continue
        try:
            t, v = cell_number(row[ti]), cell_number(row[vi])
        except (ValueError, IndexError):
            raise InputProblem(f"{path}:{line}: '{column}' or '{time_column}' is not a number: {row}") from None
        if is_missing(t) or is_missing(v):
            missing += 1
            continue
        series[round(t / TIME_MATCH_S)] = (t, v)
    if missing:
        print(f"{path}: {missing} rows without a '{column}' or '{time_column}' value (empty cell) skipped")
    if not series:
        raise InputProblem(f"{path}: no data rows")
    return series


def check(args):
    terms = [parse_term(t, 1.0) for t in args.terms] + [parse_term(t, -1.0) for t in args.subtract]
    series = [(sign, path, column, read_series(path, column, args.time_columns)) for sign, path, column in terms]
    shared = sorted(set.intersection(*(set(s.keys()) for _, _, _, s in series)))
    if not shared:
        raise InputProblem("the files share no sample time: " +
                           ", ".join(f"{p} ({min(s.values())[0]} .. {max(s.values())[0]} s)" for _, p, _, s in series))
    sums = [(series[0][3][key][0], math.fsum(sign * s[key][1] for sign, _, _, s in series)) for key in shared]
    reference = args.initial if args.initial is not None else sums[0][1]
    tolerance = args.abs_tol + args.rel_tol * abs(reference)
    worst = sorted(sums, key=lambda ts: -abs(ts[1] - reference))
    bad = [(t, total) for t, total in worst if abs(total - reference) > tolerance]
    last_t, last_sum = sums[-1]
    print(f"mass balance over {len(shared)} shared times ({sums[0][0]:.6g} .. {last_t:.6g} s), "
          f"{len(terms)} terms: reference {reference:.9g} kg, final {last_sum:.9g} kg, "
          f"largest deviation {worst[0][1] - reference:+.3g} kg (tolerance {tolerance:.3g} kg)")
    final_terms = ", ".join(f"{'-' if sign < 0 else ''}{path}:{column} = {s[shared[-1]][1]:.6g}"
                            for sign, path, column, s in series)
    print(f"  at {last_t:.6g} s: {final_terms}")
    if bad:
        for t, total in bad[:5]:
            print(f"  OUT OF TOLERANCE at t = {t:.9g} s: sum {total:.9g} kg, "
                  f"deviation {total - reference:+.3g} kg", file=sys.stderr)
        print(f"check_mass_balance: FAILED at {len(bad)} of {len(shared)} times", file=sys.stderr)
        return 1
    print("check_mass_balance: balanced")
    return 0


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0],
                                     formatter_class=argparse.RawDescriptionHelpFormatter, epilog=__doc__)
    parser.add_argument("terms", nargs="+", metavar="FILE:COLUMN", help="a mass term [kg], added")
    parser.add_argument("--subtract", action="append", default=[], metavar="FILE:COLUMN",
                        help="a mass term [kg] to subtract (repeatable)")
    parser.add_argument("--initial", type=float, help="expected sum [kg] (default: the sum at the first shared time)")
    parser.add_argument("--rel-tol", type=float, default=1e-9, help="tolerance relative to the reference [-]")
    parser.add_argument("--abs-tol", type=float, default=0.0, help="absolute tolerance [kg]")
    parser.add_argument("--time-columns", default="time_s,time,t",
                        type=lambda s: [c for c in s.split(",") if c],
                        help="names tried for the time column, in order (default time_s,time,t)")
    args = parser.parse_intermixed_args()
    if args.rel_tol < 0 or args.abs_tol < 0:
        parser.error("tolerances must be >= 0")
    try:
        return check(args)
    except InputProblem as e:
        print(f"check_mass_balance: {e}", file=sys.stderr)
        return 2


if __name__ == "__main__":
    sys.exit(main())
