#!/usr/bin/env python3
"""Tests of scripts/cosim_summary.py with a synthetic simulation folder.

Why: the demo's closing numbers (mass dug, delivered, spilled, peak cylinder force) and its
mass-balance verdict come from it; a summary that balanced anything would hide particles
lost between regions. Checked: mass moving pit -> bucket -> truck and onto the ground, with
particles removed at the bounds, balances at the last shared time and the numbers are
printed; a particle missing from every region fails (exit 1); the bucket -> truck check
passes when the truck got what the bucket carried and fails when it got too little or
more than was carried; a missing sensor file or column, a run log without the removed-mass row and a non-number in it are input errors
(exit 2) naming them.
"""

import os
import subprocess
import sys
import tempfile
import unittest

SCRIPT = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "scripts", "cosim_summary.py")
HEADER = ["time_s", "count", "mass_kg"]


def write_sensor(folder, name, rows):
    with open(os.path.join(folder, f"region_sensor_{name}.csv"), "w") as f:
        f.write(",".join(HEADER) + "\n")
        for t, m in rows:
            f.write(f"{t!r},0,{m!r}\n")


class CosimSummaryTest(unittest.TestCase):
    def setUp(self):
        self.tmp = tempfile.TemporaryDirectory()
        self.sim = os.path.join(self.tmp.name, "sim_001")
        os.makedirs(self.sim)
        # 1000 kg in the pit; by t = 2 s: 300 kg dug, 250 kg in the truck, 20 + 10 kg on the
        # ground, 5 kg in the bucket, 15 kg removed at the bounds. The pit and spill sensors
        # sample every 0.5 s, bucket and truck every 0.25 s (and once more at 2.1 s).
        write_sensor(self.sim, "pit_contents", [(0.0, 1000.0), (0.5, 900.0), (1.0, 800.0), (1.5, 700.0), (2.0, 700.0)])
        write_sensor(self.sim, "spill_north", [(0.5 * i, 0.0 if i < 4 else 20.0) for i in range(5)])
        write_sensor(self.sim, "spill_south", [(0.5 * i, 0.0 if i < 4 else 10.0) for i in range(5)])
        fast = [0.25 * i for i in range(9)] + [2.1]
        write_sensor(self.sim, "bucket_fill", [(t, 100.0 if 0.4 < t < 1.9 else (5.0 if t >= 1.9 else 0.0)) for t in fast])
        write_sensor(self.sim, "truck_load", [(t, 250.0 if t >= 1.9 else 0.0) for t in fast])
        self.write_run_log(15.0)
        self.summary = os.path.join(self.tmp.name, "excavator_summary.txt")
        with open(self.summary, "w") as f:
            f.write("cycle_1_carried_kg = 255\ncycle_1_after_dump_kg = 5\ncycle_1_peak_fill_kg = 300\n"
                    "peak_force_boom_N = 136742\npeak_force_stick_N = 436094\nwall_s = 43\n")

    def tearDown(self):
        self.tmp.cleanup()

    def write_run_log(self, removed_kg):
        with open(os.path.join(self.sim, "run_log.csv"), "w") as f:
            f.write("section,key,value,unit\ntiming,removed_at_bounds,3,\n")
            if removed_kg is not None:
                f.write(f"timing,removed_mass_at_bounds,{removed_kg},kg\n")
            f.write("timing,status,completed,\n")

    def run_script(self, *args):
        return subprocess.run([sys.executable, SCRIPT, self.sim, *args], capture_output=True, text=True, timeout=30)

    def test_balanced_site_prints_the_numbers(self):
        r = self.run_script("--excavator-summary", self.summary)
        self.assertEqual(r.returncode, 0, r.stdout + r.stderr)
        self.assertRegex(r.stdout, r"mass dug from the pit: +300\.0 kg")
        self.assertRegex(r.stdout, r"mass delivered \(truck\): +250\.0 kg")
        self.assertRegex(r.stdout, r"spilled on the ground: +30\.0 kg")
        self.assertRegex(r.stdout, r"removed at the bounds: +15\.0 kg")
        self.assertIn("at t = 2.000 s", r.stdout)  # the last time all sensors share
        self.assertRegex(r.stdout, r"peak cylinder force: +436\.1 kN \(stick\)")
        self.assertIn("cycle 1: carried 255.0 kg", r.stdout)
        self.assertIn("mass balanced", r.stdout)

    def test_a_particle_in_no_region_fails(self):
        self.write_run_log(14.0)  # 1 kg neither removed nor in any region
        r = self.run_script()
        self.assertEqual(r.returncode, 1, r.stdout)
        self.assertIn("-1 kg unaccounted", r.stderr)

    def test_delivery_check_compares_the_truck_with_what_the_bucket_carried(self):
        # The bucket carried 255 kg; the truck holds 250 kg (98 %).
        r = self.run_script("--excavator-summary", self.summary, "--min-delivered-fraction", "0.95")
        self.assertEqual(r.returncode, 0, r.stdout + r.stderr)
        self.assertIn("carried 255.0 kg in 1 cycle(s), delivered 250.0 kg (98.0%", r.stdout)
        r = self.run_script("--excavator-summary", self.summary, "--min-delivered-fraction", "0.99")
        self.assertEqual(r.returncode, 1)
        self.assertIn("did NOT arrive in the truck", r.stderr)
        with open(self.summary, "w") as f:
            f.write("cycle_1_carried_kg = 200\n")  # the truck holds more than was carried
        r = self.run_script("--excavator-summary", self.summary, "--min-delivered-fraction", "0.5")
        self.assertEqual(r.returncode, 1)
        r = self.run_script("--min-delivered-fraction", "0.5")
        self.assertEqual(r.returncode, 2)
        self.assertIn("needs --excavator-summary", r.stderr)

    def test_missing_sensor_file_and_column_are_input_errors(self):
        os.remove(os.path.join(self.sim, "region_sensor_truck_load.csv"))
        r = self.run_script()
        self.assertEqual(r.returncode, 2)
        self.assertIn("region_sensor_truck_load.csv", r.stderr)
        with open(os.path.join(self.sim, "region_sensor_truck_load.csv"), "w") as f:
            f.write("time_s,count\n0,0\n")
        r = self.run_script()
        self.assertEqual(r.returncode, 2)
        self.assertIn("no column 'mass_kg'", r.stderr)

    def test_run_log_without_or_with_a_bad_removed_mass_is_an_input_error(self):
        self.write_run_log(None)
        r = self.run_script()
        self.assertEqual(r.returncode, 2)
        self.assertIn("no 'timing,removed_mass_at_bounds' row", r.stderr)
        self.write_run_log("lots")
        r = self.run_script()
        self.assertEqual(r.returncode, 2)
        self.assertIn("removed_mass_at_bounds = 'lots' is not a mass >= 0", r.stderr)
        self.assertNotIn("Traceback", r.stderr)


if __name__ == "__main__":
    unittest.main()
