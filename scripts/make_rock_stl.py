#!/usr/bin/env python3
"""Writes an ASCII STL of a closed, rock-like solid for the clump-fit examples
(docs/clumps.md, "Fitting a template to an STL").

An icosahedron is subdivided (each triangle into four, SUBDIVISIONS times) and
its vertices projected onto the unit sphere; each vertex is then moved to radius
1 + a smooth bumpy function of its direction (a few fixed low-order harmonics, no
random numbers, so the file is the same every time) and the solid is stretched
along x and flattened along z. Every vertex stays on its own ray from the centre,
so the surface stays closed and outward-oriented.

usage: make_rock_stl.py SIZE_M OUT.stl [--subdivisions N]
"""
import argparse
import math


def icosahedron():
    t = (1.0 + math.sqrt(5.0)) / 2.0
    vertices = [(-1, t, 0), (1, t, 0), (-1, -t, 0), (1, -t, 0), (0, -1, t), (0, 1, t), (0, -1, -t), (0, 1, -t),
                (t, 0, -1), (t, 0, 1), (-t, 0, -1), (-t, 0, 1)]
    faces = [(0, 11, 5), (0, 5, 1), (0, 1, 7), (0, 7, 10), (0, 10, 11), (1, 5, 9), (5, 11, 4), (11, 10, 2),
             (10, 7, 6), (7, 1, 8), (3, 9, 4), (3, 4, 2), (3, 2, 6), (3, 6, 8), (3, 8, 9), (4, 9, 5), (2, 4, 11),
             (6, 2, 10), (8, 6, 7), (9, 8, 1)]
    return [normalise(v) for v in vertices], faces


def normalise(v):
    n = math.sqrt(sum(c * c for c in v))
    return tuple(c / n for c in v)


def subdivide(vertices, faces):
    midpoints = {}
    out = []

    def middle(a, b):
        key = (min(a, b), max(a, b))
        if key not in midpoints:
            midpoints[key] = len(vertices)
            vertices.append(normalise(tuple(0.5 * (p + q) for p, q in zip(vertices[a], vertices[b]))))
        return midpoints[key]

    for a, b, c in faces:
        ab, bc, ca = middle(a, b), middle(b, c), middle(c, a)
        out += [(a, ab, ca), (b, bc, ab), (c, ca, bc), (ab, bc, ca)]
    return vertices, out


def bump(x, y, z):
    return 1.0 + 0.12 * math.sin(3.0 * x + 1.0) * math.cos(2.0 * y) + 0.08 * math.sin(4.0 * z + 2.0 * x) \
        + 0.06 * math.cos(5.0 * y - 3.0 * z)


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("size", type=float, help="length of the rock along x [m]")
    parser.add_argument("out")
    parser.add_argument("--subdivisions", type=int, default=2)
    args = parser.parse_args()
    vertices, faces = icosahedron()
    for _ in range(args.subdivisions):
        vertices, faces = subdivide(vertices, faces)
    stretch = (0.5 * args.size, 0.36 * args.size, 0.26 * args.size)
    placed = [tuple(s * c * bump(*v) for s, c in zip(stretch, v)) for v in vertices]
    with open(args.out, "w") as f:
        f.write("solid rock\n")
        for a, b, c in faces:
            pa, pb, pc = placed[a], placed[b], placed[c]
            u = [q - p for p, q in zip(pa, pb)]
            w = [q - p for p, q in zip(pa, pc)]
            n = normalise((u[1] * w[2] - u[2] * w[1], u[2] * w[0] - u[0] * w[2], u[0] * w[1] - u[1] * w[0]))
            f.write("  facet normal %.9g %.9g %.9g\n    outer loop\n" % n)
            for p in (pa, pb, pc):
                f.write("      vertex %.9g %.9g %.9g\n" % p)
            f.write("    endloop\n  endfacet\n")
        f.write("endsolid rock\n")


if __name__ == "__main__":
    main()
