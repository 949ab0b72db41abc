#!/usr/bin/env python3
"""Tests of scripts/plot_cosim.py with synthetic CSVs (no co-simulation needed).

Why: the plots are the demo's visible result, and the script runs after a long
simulation, where a renamed column must give a clear error naming it, not a traceback.
Checked: both PNGs are written, are PNG files of a sensible size with the figure's
pixel dimensions; the printed summary quotes the synthetic data's largest bucket fill,
peak cylinder force and final load; a missing column, a missing file and a value that is
not a number each exit 2 with a message naming the file and the column; --column renames
one column for a run.

Run: python3 test_plot_cosim.py  (needs python3-matplotlib)
"""

import math
import os
import struct
import subprocess
import sys
import tempfile
import unittest

SCRIPT = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "scripts", "plot_cosim.py")
PNG_MAGIC = b"\x89PNG\r\n\x1a\n"


def write_csv(path, columns, rows):
    with open(path, "w") as f:
        f.write(",".join(columns) + "\n")
        for row in rows:
            f.write(",".join(repr(v) for v in row) + "\n")


def excavator_rows(n=200):
    """Dig (fill rises to 400 kg), lift, dump (fill falls to 0); forces follow the fill."""
    rows = []
    for i in range(n):
        t = i * 0.05
        fill = 400.0 * min(1.0, t / 4.0) if t < 7.0 else max(0.0, 400.0 - 400.0 * (t - 7.0))
        rows.append((t, fill, 20e3 + 50.0 * fill, -10e3 - 30.0 * fill, 5e3 * math.sin(t)))
    return rows


def truck_rows(n=200):
    """Load steps up twice, then acceleration and a turn shift the axle forces."""
    rows = []
    for i in range(n):
        t = i * 0.05
        load = 350.0 * (t >= 2.0) + 350.0 * (t >= 4.0)
        accel = 1.5 if 6.0 <= t < 8.0 else 0.0
        yaw = 0.2 if t >= 8.0 else 0.0
        weight = (3000.0 + load) * 9.81
        lateral = 0.4 * yaw  # v * yaw rate at 2 m/s
        rows.append((t, load, weight / 2 - 300.0 * accel, weight / 2 + 300.0 * accel, accel, lateral, yaw,
                     weight / 2 + 500.0 * lateral, weight / 2 - 500.0 * lateral))
    return rows


EXCAVATOR_HEADER = ["time", "fill_mass", "boom_force", "stick_force", "bucket_force"]
TRUCK_HEADER = ["time_s", "load_mass_kg", "axle_front_N", "axle_rear_N", "frame_ax_m_s2", "frame_ay_m_s2",
                "yaw_rate_rad_s", "side_left_N", "side_right_N"]


def png_size(path):
    with open(path, "rb") as f:
        head = f.read(24)
    if head[:8] != PNG_MAGIC:
        return None
    return struct.unpack(">II", head[16:24])


class PlotCosimTest(unittest.TestCase):
    def setUp(self):
        self.tmp = tempfile.TemporaryDirectory()
        self.dir = self.tmp.name
        self.excavator = os.path.join(self.dir, "excavator.csv")
        self.truck = os.path.join(self.dir, "truck.csv")
        write_csv(self.excavator, EXCAVATOR_HEADER, excavator_rows())
        write_csv(self.truck, TRUCK_HEADER, truck_rows())
        self.out = os.path.join(self.dir, "plots")

    def tearDown(self):
        self.tmp.cleanup()

    def run_script(self, *args):
        return subprocess.run([sys.executable, SCRIPT, *args], capture_output=True, text=True, timeout=120)

    def test_writes_both_pngs_and_a_summary(self):
        r = self.run_script("--excavator", self.excavator, "--truck", self.truck, "--output-dir", self.out)
        self.assertEqual(r.returncode, 0, r.stderr)
        for name, figure_inches in (("excavator.png", (9, 6.5)), ("truck.png", (9, 8.5))):
            path = os.path.join(self.out, name)
            self.assertTrue(os.path.isfile(path), f"{name} not written")
            self.assertGreater(os.path.getsize(path), 10_000, f"{name} is too small to hold the plots")
            self.assertEqual(png_size(path), (round(figure_inches[0] * 110), round(figure_inches[1] * 110)),
                             f"{name}: not a PNG of the figure's size at 110 dpi")
        # Largest fill 400 kg; peak |force| = boom at 400 kg = 20 kN + 50 x 400 N = 40 kN;
        # final load 700 kg.
        self.assertIn("largest bucket fill 400 kg", r.stdout)
        self.assertIn("peak cylinder force 40 kN", r.stdout)
        self.assertIn("final load 700 kg", r.stdout)

    def test_missing_column_names_file_and_column(self):
        header = list(EXCAVATOR_HEADER)
        header[2] = "boom_cylinder_force"
        write_csv(self.excavator, header, excavator_rows())
        r = self.run_script("--excavator", self.excavator, "--output-dir", self.out)
        self.assertEqual(r.returncode, 2)
        self.assertIn("no column 'boom_force'", r.stderr)
        self.assertIn(self.excavator, r.stderr)
        self.assertNotIn("Traceback", r.stderr)
        self.assertFalse(os.path.exists(os.path.join(self.out, "excavator.png")))

    def test_column_override_accepts_the_renamed_column(self):
        header = list(TRUCK_HEADER)
        header[1] = "bed_mass_kg"
        write_csv(self.truck, header, truck_rows())
        r = self.run_script("--truck", self.truck, "--output-dir", self.out, "--column", "truck.load=bed_mass_kg")
        self.assertEqual(r.returncode, 0, r.stderr)
        self.assertTrue(os.path.getsize(os.path.join(self.out, "truck.png")) > 10_000)

    def test_missing_file_and_bad_value_are_clear_errors(self):
        r = self.run_script("--truck", os.path.join(self.dir, "nope.csv"), "--output-dir", self.out)
        self.assertEqual(r.returncode, 2)
        self.assertIn("nope.csv", r.stderr)
        rows = truck_rows()
        with open(self.truck, "w") as f:
            f.write(",".join(TRUCK_HEADER) + "\n")
            for i, row in enumerate(rows):
                values = [repr(v) for v in row]
                if i == 5:
                    values[4] = "fast"
                f.write(",".join(values) + "\n")
        r = self.run_script("--truck", self.truck, "--output-dir", self.out)
        self.assertEqual(r.returncode, 2)
        self.assertIn("'frame_ax_m_s2' has a value that is not a number", r.stderr)
        self.assertNotIn("Traceback", r.stderr)


if __name__ == "__main__":
    unittest.main(verbosity=2)
