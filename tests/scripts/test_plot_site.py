#!/usr/bin/env python3
"""Tests of scripts/plot_site.py on a real run of demlink-run (env DEMLINK_RUN).

Why a real run: the script parses the server's own VTK writer output (raw appended
binary); a synthetic file would only test the script against its author's reading of the
format. Checked: the particles read from every frame reproduce the run's summary.csv
(count and mean height, to 1e-8 m), mesh polygons are read, a PNG of the expected size is
written with the frames nearest the asked times (`end` = the last); a truncated frame and a
missing folder are clear errors (exit 2) naming the file.
"""

import csv
import os
import shutil
import subprocess
import sys
import tempfile
import unittest

HERE = os.path.dirname(os.path.abspath(__file__))
REPO = os.path.join(HERE, "..", "..")
SCRIPT = os.path.join(REPO, "scripts", "plot_site.py")
SCENE = os.path.join(REPO, "examples", "scenes", "facet_bodies.json")
sys.path.insert(0, os.path.join(REPO, "scripts"))
import plot_site  # noqa: E402


class PlotSiteTest(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.tmp = tempfile.TemporaryDirectory()
        cls.sim = os.path.join(cls.tmp.name, "run")
        r = subprocess.run([os.environ["DEMLINK_RUN"], SCENE, "--output", cls.sim], capture_output=True, text=True,
                           timeout=120)
        if r.returncode != 0:
            raise RuntimeError(f"demlink-run failed: {r.stderr}")

    @classmethod
    def tearDownClass(cls):
        cls.tmp.cleanup()

    def run_script(self, *args):
        return subprocess.run([sys.executable, SCRIPT, *args], capture_output=True, text=True, timeout=120)

    def test_frames_reproduce_the_run_summary(self):
        with open(os.path.join(self.sim, "summary.csv")) as f:
            summary = {round(float(r["time_s"]), 9): r for r in csv.DictReader(f)}
        frames = plot_site.read_pvd(os.path.join(self.sim, "particles.pvd"))
        self.assertGreater(len(frames), 5)
        matched = 0
        for t, path in frames:
            row = summary.get(round(t, 9))
            if row is None:
                continue
            z = plot_site.read_vtp(path)["position"][2::3]
            self.assertEqual(len(z), int(row["particles"]), path)
            self.assertAlmostEqual(sum(z) / len(z), float(row["mean_z_m"]), delta=1e-8, msg=path)
            matched += 1
        self.assertGreater(matched, 5)
        mesh_frames = plot_site.read_pvd(os.path.join(self.sim, "meshes.pvd"))
        polys = plot_site.triangles_of(plot_site.read_vtp(mesh_frames[0][1]))
        self.assertGreater(len(polys), 0)
        self.assertTrue(all(len(p) == 3 for p in polys))

    def test_writes_the_png_with_the_nearest_frames(self):
        out = os.path.join(self.tmp.name, "site.png")
        frames = [t for t, _ in plot_site.read_pvd(os.path.join(self.sim, "particles.pvd"))]
        asked = 0.5 * (frames[1] + frames[2]) - 1e-4  # just nearer to frames[1]
        r = self.run_script(self.sim, "--times", f"{asked!r},end", "--output", out)
        self.assertEqual(r.returncode, 0, r.stderr)
        self.assertIn(f"2 snapshot(s) at t = {frames[1]:g}, {frames[-1]:g} s", r.stdout)
        with open(out, "rb") as f:
            head = f.read(24)
        self.assertEqual(head[:8], b"\x89PNG\r\n\x1a\n")
        self.assertEqual(int.from_bytes(head[16:20], "big"), 1300)  # 13 in at 100 dpi

    def test_truncated_frame_and_missing_folder_are_clear_errors(self):
        broken = os.path.join(self.tmp.name, "broken")
        shutil.copytree(self.sim, broken)
        frame = plot_site.read_pvd(os.path.join(broken, "particles.pvd"))[0][1]
        with open(frame, "rb") as f:
            data = f.read()
        with open(frame, "wb") as f:
            f.write(data[: len(data) // 2])
        r = self.run_script(broken, "--times", "0")
        self.assertEqual(r.returncode, 2)
        self.assertIn(os.path.basename(frame), r.stderr)
        self.assertNotIn("Traceback", r.stderr)
        r = self.run_script(os.path.join(self.tmp.name, "nope"), "--times", "0")
        self.assertEqual(r.returncode, 2)
        self.assertIn("particles.pvd: cannot read", r.stderr)


if __name__ == "__main__":
    unittest.main()
