#!/usr/bin/env python3
"""Writes an ASCII STL of a square plate (side L, at z = 0) with a circular
orifice (diameter D, centred at the origin), for the hopper-discharge examples.

The hole is a regular polygon of n sides (n a multiple of 4) whose vertices sit
on the circle; the outer ring takes the points where the same rays meet the
square, so the square's corners are ring vertices and the plate is exactly the
square minus the polygon. Quads between the rings are split into two triangles.
Normals point to +z (the side the particles rest on).

usage: make_orifice_plate.py SIDE_M DIAMETER_M OUT.stl [--sides N]
"""
import argparse
import math


def ring_points(side, diameter, sides):
    inner, outer = [], []
    half = 0.5 * side
    for k in range(sides):
        angle = 2.0 * math.pi * k / sides
        c, s = math.cos(angle), math.sin(angle)
        inner.append((0.5 * diameter * c, 0.5 * diameter * s))
        scale = half / max(abs(c), abs(s))  # ray meets the square boundary
        outer.append((scale * c, scale * s))
    return inner, outer


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("side", type=float)
    parser.add_argument("diameter", type=float)
    parser.add_argument("out")
    parser.add_argument("--sides", type=int, default=48)
    args = parser.parse_args()
    if args.sides % 4 != 0 or args.sides < 8:
        parser.error("--sides must be a multiple of 4 and >= 8")
    if not 0.0 < args.diameter < args.side:
        parser.error("need 0 < diameter < side")
    inner, outer = ring_points(args.side, args.diameter, args.sides)
    lines = ["solid orifice_plate"]
    for k in range(args.sides):
        n = (k + 1) % args.sides
        for tri in ((inner[k], outer[k], outer[n]), (inner[k], outer[n], inner[n])):
            lines.append("  facet normal 0 0 1")
            lines.append("    outer loop")
            for x, y in tri:
                lines.append(f"      vertex {x:.9g} {y:.9g} 0")
            lines.append("    endloop")
            lines.append("  endfacet")
    lines.append("endsolid orifice_plate")
    with open(args.out, "w", encoding="ascii") as f:
        f.write("\n".join(lines) + "\n")


if __name__ == "__main__":
    main()
