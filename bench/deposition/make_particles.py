#!/usr/bin/env python3
"""Initial condition of the deposition benchmark (bench/deposition/README.md).

N spheres on a loose square lattice above the floor of the 0.1 m x 0.1 m box: 15 x 15
sites per layer, 6.5 mm apart, centred in the box (4.5 mm margin to the side walls); the
first layer's centres at z = 3.5 mm, one layer every 6.5 mm. Radii uniform in [2, 3] mm,
centres jittered by up to 0.2 mm in x and y, from a fixed seed so both codes start from
the same particles. Density 2500 kg/m^3.

Writes, in the current directory:
  init_N.txt   "id x y z r" per line, '#' header (demlink-bench-deposition reads it)
  init_N.data  LIGGGHTS read_data, atom_style granular (id type diameter density x y z)

Usage: make_particles.py N [SEED]      (SEED default 12345)
"""
import argparse
import math
import random

BOX = 0.1            # [m] side of the square box
SPACING = 0.0065     # [m] lattice spacing
PER_ROW = 15         # sites per row and rows per layer
FIRST_Z = 0.0035     # [m] centre height of the first layer
R_MIN, R_MAX = 0.002, 0.003   # [m] radius range
JITTER = 0.0002      # [m] largest x/y offset from a lattice site
DENSITY = 2500.0     # [kg/m^3]
HEADROOM = 0.01      # [m] box top above the highest centre (LIGGGHTS needs a finite z range)
GRAVITY = 9.81       # [m/s^2], only for the printed potential energy


def lattice(count, rng):
    """(x, y, z, r) of `count` spheres, filling the lattice layer by layer.

    Per sphere the generator draws the radius, then the x and then the y offset: the order
    fixes the particles a seed gives, so it must not change."""
    margin = (BOX - (PER_ROW - 1) * SPACING) / 2.0
    spheres = []
    for site in range(count):
        layer, in_layer = divmod(site, PER_ROW * PER_ROW)
        row, column = divmod(in_layer, PER_ROW)
        radius = rng.uniform(R_MIN, R_MAX)
        x = margin + column * SPACING + rng.uniform(-JITTER, JITTER)
        y = margin + row * SPACING + rng.uniform(-JITTER, JITTER)
        spheres.append((x, y, FIRST_Z + layer * SPACING, radius))
    return spheres


def inside_box(sphere):
    x, y, z, r = sphere
    return r < x < BOX - r and r < y < BOX - r and z > r


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("count", type=int, help="number of spheres N")
    parser.add_argument("seed", type=int, nargs="?", default=12345, help="random seed (default 12345)")
    args = parser.parse_args()
    if args.count < 1:
        parser.error("N must be >= 1")

    spheres = lattice(args.count, random.Random(args.seed))
    outside = [k + 1 for k, s in enumerate(spheres) if not inside_box(s)]
    if outside:
        raise SystemExit(f"spheres {outside[:5]} touch a wall or the floor")
    top = max(s[2] for s in spheres) + HEADROOM

    with open(f"init_{args.count}.txt", "w") as out:
        out.write(f"# id x y z r   (N={args.count}, seed={args.seed}, density={DENSITY}, zhi={top:.6f})\n")
        for k, (x, y, z, r) in enumerate(spheres, 1):
            out.write(f"{k} {x:.9e} {y:.9e} {z:.9e} {r:.9e}\n")
    with open(f"init_{args.count}.data", "w") as out:
        out.write(f"deposition-{args.count} initial condition (seed {args.seed})\n\n")
        out.write(f"{args.count} atoms\n1 atom types\n\n")
        out.write(f"0.0 {BOX} xlo xhi\n0.0 {BOX} ylo yhi\n0.0 {top:.6f} zlo zhi\n\nAtoms\n\n")
        for k, (x, y, z, r) in enumerate(spheres, 1):
            out.write(f"{k} 1 {2 * r:.9e} {DENSITY} {x:.9e} {y:.9e} {z:.9e}\n")

    masses = [DENSITY * 4.0 / 3.0 * math.pi * s[3] ** 3 for s in spheres]
    mass = sum(masses)
    potential = sum(m * GRAVITY * s[2] for m, s in zip(masses, spheres))
    layers = (args.count - 1) // (PER_ROW * PER_ROW) + 1
    print(f"N={args.count} layers={layers} top centre z={top - HEADROOM:.4f} m box top={top:.4f} m "
          f"mass={mass:.6f} kg potential energy={potential:.6f} J")


if __name__ == "__main__":
    main()
