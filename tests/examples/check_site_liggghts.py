#!/usr/bin/env python3
"""Judges the shortened excavator-and-truck site on the LIGGGHTS backend
(run_site_liggghts.sh WORKDIR): the clients' CSVs and the server's sensor CSVs.

Checks, each able to fail:
  1. no NaN or infinity reached a client: every cell of excavator.csv and truck.csv is a
     finite number (except the truck load's centre of mass while the load is empty, which
     does not exist: an empty cell, DEMLink's missing value; the text "nan" is a failure);
  2. the DEM pushed on the bucket while it was in the pit: |F_dem| above 2 kN at some
     sample of penetrate, drag or curl;
  3. the fill sensor rode with the bucket: the bucket held more than 50 kg at the last
     sample, lifted out of the pit (the sensor is attached to the moving mesh);
  4. the mass balance closes at the last common sample: pit + bucket + truck + spill +
     removed = the pit at t = 0, to 1e-9 relative (scripts/cosim_summary.py).
"""
import csv
import math
import os
import subprocess
import sys

DIG = {"penetrate", "drag", "curl"}


def finite_rows(path, allowed_missing):
    rows = [r for r in csv.DictReader(line for line in open(path) if not line.startswith("#"))]
    bad = []
    for r in rows:
        for key, value in r.items():
            if key == "phase":
                continue
            if value == "" and allowed_missing(r, key):
                continue
            try:
                finite = math.isfinite(float(value))
            except ValueError:
                finite = False
            if not finite:
                bad.append((r.get("time", r.get("time_s")), key, value))
    return rows, bad


def main(work):
    errors = []
    excavator, bad = finite_rows(os.path.join(work, "excavator", "excavator.csv"), lambda r, k: False)
    if not excavator:
        errors.append("excavator.csv has no rows")
    if bad:
        errors.append(f"excavator.csv: {len(bad)} non-finite values, first {bad[:3]}")
    truck, bad = finite_rows(os.path.join(work, "truck", "truck.csv"),
                             lambda r, k: k.startswith("load_com_") and float(r["load_count"]) == 0)
    if not truck:
        errors.append("truck.csv has no rows")
    if bad:
        errors.append(f"truck.csv: {len(bad)} non-finite values, first {bad[:3]}")

    force = lambda r: math.sqrt(sum(float(r[k]) ** 2 for k in ("dem_fx", "dem_fy", "dem_fz")))
    dig = max((force(r) for r in excavator if r["phase"] in DIG), default=0.0)
    print(f"max |F_dem| on the bucket in the pit {dig / 1e3:.2f} kN over {len(excavator)} samples "
          f"(last t = {float(excavator[-1]['time']) if excavator else float('nan'):.3f} s)")
    if not dig > 2e3:
        errors.append(f"DEM force on the bucket in the pit {dig:.0f} N is not above 2 kN")
    if excavator:
        last = excavator[-1]
        print(f"bucket at the end: phase {last['phase']}, pivot z {float(last['bucket_z']):.3f} m, "
              f"fill {float(last['fill_mass']):.1f} kg")
        if not float(last["fill_mass"]) > 50.0:
            errors.append(f"the bucket holds {float(last['fill_mass']):.1f} kg at the end, not above 50 kg")

    summary = subprocess.run([sys.executable, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..",
                                                           "scripts", "cosim_summary.py"),
                              os.path.join(work, "server", "sim_001")], capture_output=True, text=True)
    print(summary.stdout.strip())
    if summary.returncode != 0:
        errors.append(f"mass balance: cosim_summary.py exit {summary.returncode}: {summary.stderr.strip()}")

    for e in errors:
        print("FAIL:", e)
    if errors:
        return 1
    print("PASS")
    return 0


if __name__ == "__main__":
    if len(sys.argv) != 2:
        print("usage: check_site_liggghts.py WORKDIR", file=sys.stderr)
        sys.exit(2)
    sys.exit(main(sys.argv[1]))
