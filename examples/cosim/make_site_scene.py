#!/usr/bin/env python3
"""Writes the server's part of the excavator-and-truck site as a scene file.

Why generated: the ground around the pit and the pit's walls are 26 triangles whose
corners all follow from a handful of numbers in site_layout.hpp (the single source of the
site geometry); writing them by hand would let the JSON and the header drift apart. The
numbers are read from the header, so changing the pit there and re-running this script
keeps both in step.

    make_site_scene.py                      -> examples/cosim/site_scene.json (no box)
    make_site_scene.py --test-box OUT.json  -> also a copy with a simulation_box
    make_site_scene.py --pit-half-x 1.2 ... -> a narrower pit (the ctest's small scene)
    make_site_scene.py --clods 0.3 0.3 --output examples/cosim/site_scene_clods.json
                                            -> a bed with clods (30 % of the gravel, 0.3 m)
"""
import argparse
import json
import pathlib
import re

HERE = pathlib.Path(__file__).resolve().parent


def layout():
    """The `inline constexpr double kName = value;` constants of site_layout.hpp."""
    text = (HERE / "site_layout.hpp").read_text()
    return {m.group(1): float(m.group(2))
            for m in re.finditer(r"inline constexpr double (k\w+) = ([-0-9.eE+]+);", text)}


def v(x, y, z):
    return {"x": x, "y": y, "z": z}


def quad(a, b, c, d):
    """Two triangles, counter-clockwise seen from the normal's side."""
    return [{"a": a, "b": b, "c": c}, {"a": a, "b": c, "c": d}]


def up_rect(x0, x1, y0, y1, z):
    return quad(v(x0, y0, z), v(x1, y0, z), v(x1, y1, z), v(x0, y1, z))


def fixed(name, triangles):
    return {"name": name, "facet_body": {"role": "FIXED", "material": "gravel",
                                         "triangles": {"triangles": triangles}}}


def box_sensor(name, lo, hi, interval):
    centre = v(*[(a + b) / 2 for a, b in zip(lo, hi)])
    size = v(*[b - a for a, b in zip(lo, hi)])
    return {"name": name, "region_sensor": {"region": {"box": {"centre": centre, "size": size}},
                                            "sample_interval": interval}}


def clay(k):
    """Parallel bonds of a clay binder for the clods. Stiffness: the bonded gravel's
    critical time step (docs/physics.md, "Parallel bonds") stays near half the site's
    kTimeStep limit; strength: a clod carries its weight, a bucket breaks it."""
    return {"name": "clay", "parallel_bonds": {
        "materials": ["gravel"], "normal_stiffness_per_area": 5e7, "shear_stiffness_per_area": 5e7,
        "tensile_strength": 5e4, "shear_strength": 5e4, "gap_tolerance": 0.15 * k["kGravelRadiusMin"]}}


def scene(k, pit_half_x, ground, clods=None):
    px, py, d = pit_half_x, k["kPitHalfY"], k["kPitDepth"]
    gx0, gx1, gy0, gy1 = ground
    c = []
    # Materials: gravel from the database as it is; the bucket's and the truck body's steel
    # with the same DEM modulus as gravel (a stiffer wall would shorten the critical step).
    c.append({"name": "gravel", "material": {"database_name": "gravel"}})
    c.append({"name": "steel", "material": {"density": 7800.0, "youngs_modulus": 5e7, "poisson_ratio": 0.3,
                                            "restitution": 0.5, "sliding_friction": 0.4}})
    c.append({"name": "gravel_on_steel", "material_pair": {"material_a": "gravel", "material_b": "steel",
                                                           "restitution": 0.4, "sliding_friction": 0.45}})
    # The pit: floor and four walls (normals into the pit), open top.
    c.append(fixed("pit_floor", up_rect(-px, px, -py, py, -d)))
    c.append(fixed("pit_wall_x_minus", quad(v(-px, -py, -d), v(-px, py, -d), v(-px, py, 0), v(-px, -py, 0))))
    c.append(fixed("pit_wall_x_plus", quad(v(px, py, -d), v(px, -py, -d), v(px, -py, 0), v(px, py, 0))))
    c.append(fixed("pit_wall_y_minus", quad(v(px, -py, -d), v(-px, -py, -d), v(-px, -py, 0), v(px, -py, 0))))
    c.append(fixed("pit_wall_y_plus", quad(v(-px, py, -d), v(px, py, -d), v(px, py, 0), v(-px, py, 0))))
    # The ground at z = 0 out to the domain bounds, the pit cut out (four rectangles).
    c.append(fixed("ground", up_rect(gx0, gx1, gy0, -py, 0.0) + up_rect(gx0, gx1, py, gy1, 0.0) +
                   up_rect(gx0, -px, -py, py, 0.0) + up_rect(px, gx1, -py, py, 0.0)))
    c.append({"name": "pit", "pit_generator": {
        "material": "gravel",
        "sizes": {"uniform": {"r_min": k["kGravelRadiusMin"], "r_max": k["kGravelRadiusMax"]}},
        "lower": v(-px, -py, -d), "upper": v(px, py, 0.0), "target_height": d, "seed": "5",
        # The gravel settles at a solid fraction of about 0.465 (rolling resistance keeps it
        # loose); raining 15 % more than that fills the target height with a margin of about
        # one diameter, where the defaults (0.6 x 1.25) rained 1.6 times the kept bed.
        "packing_fraction": 0.47, "overfill": 1.15}})
    if clods:
        c[-1]["pit_generator"].update({"clod_fraction": clods[0], "clod_radius": clods[1], "clod_bonds": "clay"})
        c.append(clay(k))
    # Where the gravel is: in the pit (up to a heap of 0.75 m), spilled on the ground
    # (centres up to 0.5 m above it, outside the pit; the truck bed is higher).
    interval = 0.01
    c.append(box_sensor("pit_contents", (-px, -py, -d), (px, py, 0.75), interval))
    c.append(box_sensor("spill_south", (gx0, gy0, 0.0), (gx1, -py, 0.5), interval))
    c.append(box_sensor("spill_north", (gx0, py, 0.0), (gx1, gy1, 0.5), interval))
    c.append(box_sensor("spill_west", (gx0, -py, 0.0), (-px, py, 0.5), interval))
    c.append(box_sensor("spill_east", (px, -py, 0.0), (gx1, py, 0.5), interval))
    return c


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--output", default=str(HERE / "site_scene.json"))
    ap.add_argument("--pit-half-x", type=float, help="half length of the pit along x [m] (default: site_layout.hpp)")
    ap.add_argument("--test-box", help="also write this copy with a simulation_box for the excavator alone")
    ap.add_argument("--ground", type=float, nargs=4, default=[-6.0, 9.0, -7.0, 3.0],
                    metavar=("X0", "X1", "Y0", "Y1"), help="ground and domain footprint [m]")
    ap.add_argument("--clods", type=float, nargs=2, metavar=("FRACTION", "RADIUS"),
                    help="group this fraction of the bed into clods of this radius [m], bonded by 'clay'")
    a = ap.parse_args()
    k = layout()
    comps = scene(k, a.pit_half_x or k["kPitHalfX"], a.ground, a.clods)
    pathlib.Path(a.output).write_text(json.dumps({"components": comps}, indent=1) + "\n")
    if a.test_box:
        gx0, gx1, gy0, gy1 = a.ground
        # A 10 % restitution tolerance instead of the default 1 %: trades accuracy for speed.
        box = {"name": "box", "simulation_box": {
            "time_step": k["kTimeStep"], "restitution_tolerance": 0.1, "end_time": 0.0, "max_impact_velocity": 3.0,
            "bounds": {"lower": v(gx0, gy0, -k["kPitDepth"] - 0.5), "upper": v(gx1, gy1, 6.0)},
            "threads": 2, "output": {"vtk_interval": 0.25},
            "coupling": {"expected_names": ["box", "bucket", "bucket_fill"]}}}
        pathlib.Path(a.test_box).write_text(json.dumps({"components": [box] + comps}, indent=1) + "\n")


if __name__ == "__main__":
    main()
