#!/usr/bin/env python3
"""Tests of scripts/check_mass_balance.py with synthetic CSVs.

Why: the multi-host test and the demo rely on it to say mass is conserved across pit,
bucket, truck and losses; a checker that passes everything would hide a leak. Checked:
mass moving between three files with a sink's running total balances (exit 0); one row
off by more than the tolerance fails (exit 1) naming the time; --initial against a wrong
total fails; a subtracted term (--subtract FILE:COLUMN) works; files are matched by time even when
they sample at different rates and name the time column differently; a missing column,
a missing file and files with no common time are input errors (exit 2) naming them; an
empty cell (DEMLink's missing value) skips its row, while the text "nan" is refused.
"""

import os
import subprocess
import sys
import tempfile
import unittest

SCRIPT = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "scripts", "check_mass_balance.py")


def write_csv(path, header, rows):
    with open(path, "w") as f:
        f.write(",".join(header) + "\n")
        for row in rows:
            f.write(",".join(repr(v) for v in row) + "\n")


class CheckMassBalanceTest(unittest.TestCase):
    def setUp(self):
        self.tmp = tempfile.TemporaryDirectory()
        d = self.tmp.name
        self.pit, self.truck, self.sink = (os.path.join(d, n) for n in ("pit.csv", "truck.csv", "sink.csv"))
        # Mass leaves the pit at 0.6 kg per 0.1 s: 0.5 kg into the truck, 0.1 kg into a
        # sink (its running total). The truck samples twice as often and calls its time
        # column "time". Sums: 100 kg at every common time.
        write_csv(self.pit, ["time_s", "mass_kg"], [(i * 0.1, 100.0 - 0.6 * i) for i in range(101)])
        write_csv(self.truck, ["time", "load_kg"], [(i * 0.05, 0.25 * i) for i in range(201)])
        write_csv(self.sink, ["time_s", "removed_mass_total_kg"], [(i * 0.1, 0.1 * i) for i in range(101)])
        self.terms = [f"{self.pit}:mass_kg", f"{self.truck}:load_kg", f"{self.sink}:removed_mass_total_kg"]

    def tearDown(self):
        self.tmp.cleanup()

    def run_script(self, *args):
        return subprocess.run([sys.executable, SCRIPT, *args], capture_output=True, text=True, timeout=30)

    def test_balanced_transfer_passes_at_every_shared_time(self):
        r = self.run_script("--initial", "100", "--rel-tol", "1e-9", *self.terms)
        self.assertEqual(r.returncode, 0, r.stderr)
        self.assertIn("over 101 shared times", r.stdout)

    def test_one_bad_row_fails_and_names_its_time(self):
        rows = [(i * 0.1, 100.0 - 0.6 * i - (0.01 if i == 37 else 0.0)) for i in range(101)]
        write_csv(self.pit, ["time_s", "mass_kg"], rows)
        r = self.run_script("--rel-tol", "1e-6", *self.terms)
        self.assertEqual(r.returncode, 1)
        self.assertIn("t = 3.7", r.stderr)
        self.assertIn("FAILED at 1 of 101 times", r.stderr)
        self.assertEqual(self.run_script("--abs-tol", "0.02", *self.terms).returncode, 0)

    def test_wrong_initial_fails(self):
        self.assertEqual(self.run_script("--initial", "101", "--rel-tol", "1e-3", *self.terms).returncode, 1)

    def test_subtracted_term(self):
        # pit + 2 x truck - truck + sink = 100 kg.
        double = self.truck + ".double"
        write_csv(double, ["time_s", "double_kg"], [(i * 0.1, 1.0 * i) for i in range(101)])
        r = self.run_script("--initial", "100", f"{self.pit}:mass_kg", f"{double}:double_kg",
                            "--subtract", f"{self.truck}:load_kg", f"{self.sink}:removed_mass_total_kg")
        self.assertEqual(r.returncode, 0, r.stderr)
        r = self.run_script("--initial", "100", f"{self.pit}:mass_kg", f"{double}:double_kg",
                            f"{self.truck}:load_kg", f"{self.sink}:removed_mass_total_kg")
        self.assertEqual(r.returncode, 1)

    def test_input_errors_name_the_problem(self):
        r = self.run_script(f"{self.pit}:mass", self.terms[1])
        self.assertEqual(r.returncode, 2)
        self.assertIn("no column 'mass'", r.stderr)
        r = self.run_script(f"{self.pit}.missing:mass_kg")
        self.assertEqual(r.returncode, 2)
        self.assertIn("pit.csv.missing", r.stderr)
        write_csv(self.sink, ["time_s", "removed_mass_total_kg"], [(20.0 + i, 0.0) for i in range(3)])
        r = self.run_script(*self.terms)
        self.assertEqual(r.returncode, 2)
        self.assertIn("share no sample time", r.stderr)
        self.assertNotIn("Traceback", r.stderr)

    def test_empty_cell_is_a_missing_value(self):
        # Row 37 of the pit has no mass: that time is skipped (100 shared times, not 101),
        # the others still balance. Written by hand: write_csv cannot write an empty cell.
        with open(self.pit, "w") as f:
            f.write("time_s,mass_kg,com_z_m\n")
            for i in range(101):
                f.write(f"{i * 0.1!r},{'' if i == 37 else repr(100.0 - 0.6 * i)},\n")
        r = self.run_script("--initial", "100", "--rel-tol", "1e-9", *self.terms)
        self.assertEqual(r.returncode, 0, r.stderr)
        self.assertIn("over 100 shared times", r.stdout)
        self.assertIn("1 rows without a 'mass_kg' or 'time_s' value (empty cell) skipped", r.stdout)
        with open(self.pit, "a") as f:
            f.write("10.1,nan,\n")
        r = self.run_script("--initial", "100", *self.terms)
        self.assertEqual(r.returncode, 2)
        self.assertIn("is not a number", r.stderr)
        self.assertNotIn("Traceback", r.stderr)


if __name__ == "__main__":
    unittest.main(verbosity=2)
