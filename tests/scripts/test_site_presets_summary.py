#!/usr/bin/env python3
"""Tests of bench/site_presets_summary.py with a synthetic results table.

Why: the presets' accuracy table (docs/accuracy.md) reads its verdicts from it; a summary
that called spread a cost, or a cost spread, would mislead the user choosing a preset.
Checked: a preset whose carried mass sits 10 % above VALIDATION on every seed (plus a
little spread) is reported with that mean and a 95 % interval that excludes zero
(resolved); differences that straddle zero are within the trajectories' spread; the
half-width is Student's t times the standard error; medians and VALIDATION's seed-to-seed
scatter are printed; an empty table is a clear message, not a traceback.
"""

import os
import statistics
import subprocess
import sys
import tempfile
import unittest

HERE = os.path.dirname(os.path.abspath(__file__))
SCRIPT = os.path.join(HERE, "..", "..", "bench", "site_presets_summary.py")
COLUMNS = ["bin", "backend", "run", "load", "settle_wall_s", "settle_sim_s", "packing", "bed_top_m", "particles",
           "sim_s", "wall_s", "rtf", "psteps_per_s_per_thread", "fidelity", "seed", "time_step_s", "carried_kg",
           "peak_fill_kg", "dig_force_peak_N", "dig_force_mean_N", "truck_load_kg"]


def row(preset, seed, carried, force_mean):
    values = {c: "1" for c in COLUMNS}
    values.update(bin="A", backend="native", fidelity=preset, seed=str(seed), carried_kg=repr(carried),
                  truck_load_kg=repr(carried), dig_force_mean_N=repr(force_mean), rtf="0.5")
    return "\t".join(values[c] for c in COLUMNS)


class SitePresetsSummaryTest(unittest.TestCase):
    def setUp(self):
        self.tmp = tempfile.TemporaryDirectory()
        self.table = os.path.join(self.tmp.name, "results.tsv")
        self.validation = {5: 400.0, 6: 360.0, 7: 380.0, 8: 420.0}
        # draft: +10 % carried with +-1 % spread (resolved); its mean force +-20 % around
        # VALIDATION's (not resolved).
        self.draft_carried_pct = [10.0, 11.0, 9.0, 10.4]
        self.draft_force_pct = [20.0, -20.0, 15.0, -18.0]
        lines = ["\t".join(COLUMNS)]
        for (seed, v), dc, df in zip(self.validation.items(), self.draft_carried_pct, self.draft_force_pct):
            lines.append(row("validation", seed, v, 10000.0))
            lines.append(row("draft", seed, v * (1 + dc / 100), 10000.0 * (1 + df / 100)))
        with open(self.table, "w") as f:
            f.write("\n".join(lines) + "\n")

    def tearDown(self):
        self.tmp.cleanup()

    def run_summary(self, path):
        return subprocess.run([sys.executable, SCRIPT, path], capture_output=True, text=True, timeout=60)

    def line(self, out, start):
        found = [l for l in out.splitlines() if l.strip().startswith(start)]
        self.assertEqual(len(found), 1, out)
        return found[0]

    def test_systematic_offset_is_resolved(self):
        result = self.run_summary(self.table)
        self.assertEqual(result.returncode, 0, result.stderr)
        line = self.line(result.stdout, "draft carried:")
        mean = statistics.mean(self.draft_carried_pct)
        half = 3.182 * statistics.stdev(self.draft_carried_pct) / 2.0  # t(3 dof) * s / sqrt(4)
        self.assertIn(f"mean {mean:+.1f} % +- {half:.1f} % (95 %): resolved", line)
        self.assertIn(f"{statistics.median(self.draft_carried_pct):+.1f} % median", line)

    def test_spread_around_zero_is_not_a_cost(self):
        result = self.run_summary(self.table)
        line = self.line(result.stdout, "draft dig force mean:")
        self.assertIn("within the trajectories' spread", line)
        self.assertNotIn("resolved", line)

    def test_validation_scatter(self):
        result = self.run_summary(self.table)
        values = list(self.validation.values())
        scatter = 100.0 * statistics.stdev(values) / statistics.mean(values)
        line = self.line(result.stdout, "VALIDATION carried:")
        self.assertIn(f"seed-to-seed scatter {scatter:.1f} % (4 seeds)", line)

    def test_empty_table(self):
        empty = os.path.join(self.tmp.name, "empty.tsv")
        with open(empty, "w") as f:
            f.write("\t".join(COLUMNS) + "\n")
        result = self.run_summary(empty)
        self.assertEqual(result.returncode, 1)
        self.assertIn("no runs in", result.stdout)
        self.assertNotIn("Traceback", result.stderr)


if __name__ == "__main__":
    unittest.main()
