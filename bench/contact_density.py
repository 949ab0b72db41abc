#!/usr/bin/env python3
"""Contact density of a particle frame: touching sphere pairs per particle, and the pairs a
Verlet list with a given skin holds per particle (what the pair loop walks), from a VTK
frame that demlink-run or demlink-server wrote (particles_NNNNNN.vtp).

    /usr/bin/python3 bench/contact_density.py FRAME.vtp [--skin M] [--below Z]

--below Z counts only the particles whose centre lies below z = Z (e.g. the pit: 0).
Needs numpy and scipy (Debian: python3-numpy, python3-scipy)."""
import argparse
import os
import sys

import numpy as np
from scipy.spatial import cKDTree

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "scripts"))
from plot_site import SiteInputError, read_vtp  # noqa: E402


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("frame")
    parser.add_argument("--skin", type=float, default=0.0, help="Verlet skin [m] (default 0: touching only)")
    parser.add_argument("--below", type=float, default=None, help="only centres below this z [m]")
    a = parser.parse_args()
    try:
        arrays = read_vtp(a.frame)
    except SiteInputError as e:
        sys.exit(f"contact_density: {e}")
    x = np.asarray(arrays["position"], dtype=float).reshape(-1, 3)
    r = np.asarray(arrays["radius"], dtype=float)
    if a.below is not None:
        keep = x[:, 2] < a.below
        x, r = x[keep], r[keep]
    n = len(r)
    if n == 0:
        sys.exit("contact_density: no particles")
    tree = cKDTree(x)
    pairs = tree.query_pairs(2.0 * r.max() + a.skin, output_type="ndarray")
    i, j = pairs[:, 0], pairs[:, 1]
    d = np.linalg.norm(x[i] - x[j], axis=1)
    touching = int(np.count_nonzero(d < r[i] + r[j]))
    listed = int(np.count_nonzero(d < r[i] + r[j] + a.skin))
    print(f"particles {n}")
    print(f"touching_pairs {touching} ({touching / n:.3f} per particle, coordination {2 * touching / n:.3f})")
    if a.skin > 0.0:
        print(f"listed_pairs_skin_{a.skin:g} {listed} ({listed / n:.3f} per particle)")


if __name__ == "__main__":
    main()
