#!/usr/bin/env python3
"""Judges one excavator cycle from excavator.csv (written by demlink-excavator).

Checks, each able to fail:
  1. the bucket fills while digging: peak fill mass above 50 kg;
  2. the dump empties it: fill mass at the end of the run below 5 kg and 5 % of the peak;
  3. the DEM pushes on the bucket while digging (|F| > 2 kN) and not once it is empty in
     the air (swing back: |F| < 100 N);
  4. digging harder slows the machine: for the stick and bucket cylinders, at samples with
     the valve open (|u| > 0.3), the speed relative to the unloaded speed at that opening
     is lower when the DEM share of the load is large (> 25 % of the cylinder's force limit,
     against the motion) than when there is no DEM load: median below 0.9 and at least 0.05
     below the no-DEM median.
"""
import csv
import math
import statistics
import sys

DIG = {"penetrate", "drag", "curl"}


def main(path):
    rows = list(csv.DictReader(open(path)))
    if not rows:
        return fail(f"{path} has no rows")
    f = lambda r, k: float(r[k])
    errors = []

    fill = [f(r, "fill_mass") for r in rows]
    peak = max(fill)
    tail = [f(r, "fill_mass") for r in rows if f(r, "time") > f(rows[-1], "time") - 0.3]
    end_fill = statistics.mean(tail)
    print(f"peak fill {peak:.1f} kg, fill at the end {end_fill:.2f} kg")
    if not peak > 50.0:
        errors.append(f"peak fill {peak:.1f} kg is not above 50 kg")
    if not (end_fill < 5.0 and end_fill < 0.05 * peak):
        errors.append(f"fill after the dump {end_fill:.2f} kg is not near zero (peak {peak:.1f} kg)")

    force = lambda r: math.sqrt(sum(f(r, k) ** 2 for k in ("dem_fx", "dem_fy", "dem_fz")))
    dig_force = max((force(r) for r in rows if r["phase"] in DIG), default=0.0)
    back_force = max((force(r) for r in rows if r["phase"] == "swing_back"), default=math.inf)
    print(f"max |F_dem| digging {dig_force / 1e3:.2f} kN, swinging back {back_force:.1f} N")
    if not dig_force > 2e3:
        errors.append(f"DEM force while digging {dig_force:.0f} N is not above 2 kN")
    if not back_force < 100.0:
        errors.append(f"DEM force on the empty bucket in the air {back_force:.1f} N is not below 100 N")

    for cyl in ("stick", "bucket"):
        caps = [abs(f(r, f"{cyl}_force") / f(r, f"{cyl}_load_ratio")) for r in rows
                if abs(f(r, f"{cyl}_load_ratio")) > 0.01]
        if not caps:
            errors.append(f"{cyl}: no loaded sample to derive the force limit from")
            continue
        cap = statistics.median(caps)
        loaded, free = [], []
        for r in rows:
            u = f(r, f"{cyl}_valve")
            if abs(u) <= 0.3 or f(r, f"{cyl}_free_speed") == 0.0:
                continue
            ratio = f(r, f"{cyl}_speed") / f(r, f"{cyl}_free_speed")
            against = math.copysign(1.0, u) * f(r, f"{cyl}_dem_force")
            if r["phase"] in DIG and against > 0.25 * cap:
                loaded.append(ratio)
            elif abs(f(r, f"{cyl}_dem_force")) < 1.0:
                free.append(ratio)
        print(f"{cyl}: force limit {cap / 1e3:.0f} kN; speed / unloaded speed: "
              f"{len(loaded)} samples with a large DEM load, median "
              f"{statistics.median(loaded) if loaded else float('nan'):.3f}; {len(free)} without, median "
              f"{statistics.median(free) if free else float('nan'):.3f}")
        if cyl == "stick" or loaded:
            if len(loaded) < 20 or len(free) < 20:
                errors.append(f"{cyl}: too few samples ({len(loaded)} loaded, {len(free)} free)")
                continue
            lo, fr = statistics.median(loaded), statistics.median(free)
            if not (lo < 0.9 and lo < fr - 0.05):
                errors.append(f"{cyl}: loaded speed ratio {lo:.3f} is not clearly below the free one {fr:.3f}")
    if errors:
        return fail("; ".join(errors))
    print("PASS")
    return 0


def fail(message):
    print("FAIL: " + message)
    return 1


if __name__ == "__main__":
    sys.exit(main(sys.argv[1]))
