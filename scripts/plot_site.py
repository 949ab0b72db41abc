#!/usr/bin/env python3
"""Snapshots of a simulation's VTK frames as one PNG: top and side views at chosen times.

Why: ParaView is the tool for looking at a run, but a first check (is the gravel where it
should be, is the bucket in the pit and over the truck, did the load stay in the body)
should not need it. This reads the server's own VTK XML (particles_NNNNNN.vtp and
meshes_NNNNNN.vtp, raw appended binary, as core's writer produces them; the .pvd files map
frames to times) with the standard library and draws, per chosen time, the particles
(coloured by speed) and the mesh bodies' triangle edges, seen from above (x-y) and from
the side (x-z). matplotlib from Debian (python3-matplotlib), Agg backend.

    plot_site.py SIM_DIR --times 5,12.5,end [--output site.png]

The frame nearest each time is used (its time is in the panel's title); `end` is the last
frame. Exit code 2 with
a message naming the file for a missing or malformed file.
"""

import argparse
import math
import os
import re
import struct
import sys
import xml.etree.ElementTree as ET

TYPES = {"Float64": "d", "Float32": "f", "Int64": "q", "UInt64": "Q", "Int32": "i", "UInt32": "I"}


class SiteInputError(Exception):
    """A missing or malformed file; the message names it."""


def read_pvd(path):
    """[(time, vtp path)] of a .pvd collection, by time."""
    try:
        root = ET.parse(path).getroot()
    except (OSError, ET.ParseError) as e:
        raise SiteInputError(f"{path}: cannot read ({e})") from None
    frames = [(float(d.get("timestep")), os.path.join(os.path.dirname(path), d.get("file")))
              for d in root.iter("DataSet")]
    if not frames:
        raise SiteInputError(f"{path}: no DataSet entries")
    return sorted(frames)


def read_vtp(path):
    """{array name: flat list} of a VTK XML PolyData file with raw appended data."""
    try:
        with open(path, "rb") as f:
            raw = f.read()
    except OSError as e:
        raise SiteInputError(f"{path}: cannot read ({e.strerror})") from None
    marker = re.search(rb'<AppendedData encoding="raw">\s*_', raw)
    if marker is None:
        raise SiteInputError(f"{path}: no raw AppendedData section")
    data_start = marker.end()
    header = raw[:marker.start()].decode("utf-8", "replace")
    arrays = {}
    for m in re.finditer(r'<DataArray type="(\w+)" Name="(\w+)" NumberOfComponents="\d+" format="appended" '
                         r'offset="(\d+)"', header):
        kind, name, offset = m.group(1), m.group(2), int(m.group(3))
        if kind not in TYPES:
            raise SiteInputError(f"{path}: array '{name}' has unsupported type {kind}")
        at = data_start + offset
        if at + 8 > len(raw):
            raise SiteInputError(f"{path}: array '{name}' starts past the end of the file")
        (size,) = struct.unpack_from("<Q", raw, at)
        width = struct.calcsize(TYPES[kind])
        if size % width or at + 8 + size > len(raw):
            raise SiteInputError(f"{path}: array '{name}' has a bad byte count {size}")
        arrays[name] = struct.unpack_from(f"<{size // width}{TYPES[kind]}", raw, at + 8)
    if "position" not in arrays:
        raise SiteInputError(f"{path}: no 'position' array")
    return arrays


def nearest(frames, t):
    """The frame closest to t; the last for t = inf ('end')."""
    return frames[-1] if math.isinf(t) else min(frames, key=lambda f: abs(f[0] - t))


def triangles_of(mesh):
    """Polygons of a meshes_*.vtp as lists of (x, y, z)."""
    p, conn, offsets = mesh["position"], mesh.get("connectivity", ()), mesh.get("offsets", ())
    polys, begin = [], 0
    for end in offsets:
        polys.append([(p[3 * i], p[3 * i + 1], p[3 * i + 2]) for i in conn[begin:end]])
        begin = end
    return polys


def particle_bounds(shots, margin):
    """(lo, hi) per axis over every shot's particles, widened by margin [m]."""
    lo, hi = [math.inf] * 3, [-math.inf] * 3
    for _, particles, _ in shots:
        pos = particles["position"]
        for k in range(3):
            values = pos[k::3]
            if values:
                lo[k], hi[k] = min(lo[k], min(values)), max(hi[k], max(values))
    return [(lo[k] - margin, hi[k] + margin) for k in range(3)]


def draw(ax, particles, polys, axes, speed_max, bounds):
    a, b = axes
    pos = particles["position"]
    n = len(pos) // 3
    xs = [pos[3 * i + a] for i in range(n)]
    ys = [pos[3 * i + b] for i in range(n)]
    vel = particles.get("velocity")
    speed = [math.sqrt(sum(vel[3 * i + k] ** 2 for k in range(3))) for i in range(n)] if vel else [0.0] * n
    # Marker area in points^2 is not in data units; a fixed small dot keeps 5,000 readable.
    scatter = ax.scatter(xs, ys, c=speed, s=2.0, cmap="viridis", vmin=0.0, vmax=speed_max, linewidths=0)
    for poly in polys:
        ring = poly + poly[:1]
        ax.plot([q[a] for q in ring], [q[b] for q in ring], color="0.35", linewidth=0.4)
    ax.set_xlim(*bounds[a])
    ax.set_ylim(*bounds[b])
    ax.set_aspect("equal")
    ax.set_xlabel("xyz"[a] + " [m]")
    ax.set_ylabel("xyz"[b] + " [m]")
    return scatter


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0],
                                     formatter_class=argparse.RawDescriptionHelpFormatter, epilog=__doc__)
    parser.add_argument("sim_dir", help="the simulation folder (particles.pvd, meshes.pvd)")
    parser.add_argument("--times", required=True,
                        type=lambda s: [math.inf if v == "end" else float(v) for v in s.split(",") if v],
                        help="comma-separated times [s] or 'end'")
    parser.add_argument("--output", default=None, help="PNG path (default SIM_DIR/site.png)")
    parser.add_argument("--speed-max", type=float, default=2.0, help="top of the colour scale [m/s]")
    parser.add_argument("--margin", type=float, default=1.0, help="space around the particles in the views [m]")
    args = parser.parse_args()
    output = args.output or os.path.join(args.sim_dir, "site.png")
    try:
        particle_frames = read_pvd(os.path.join(args.sim_dir, "particles.pvd"))
        mesh_pvd = os.path.join(args.sim_dir, "meshes.pvd")
        mesh_frames = read_pvd(mesh_pvd) if os.path.exists(mesh_pvd) else []
        shots = []
        for t in args.times:
            ft, path = nearest(particle_frames, t)
            polys = triangles_of(read_vtp(nearest(mesh_frames, ft)[1])) if mesh_frames else []
            shots.append((ft, read_vtp(path), polys))
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
    except SiteInputError as e:
        print(f"plot_site: error: {e}", file=sys.stderr)
        return 2
    except ImportError as e:
        print(f"plot_site: error: matplotlib is missing ({e}); install Debian's python3-matplotlib", file=sys.stderr)
        return 2
    # The same window in every panel: where the particles are (the ground mesh reaches the
    # domain bounds and would shrink the site to a corner).
    bounds = particle_bounds(shots, args.margin)
    fig, axes = plt.subplots(len(shots), 2, figsize=(13, 3.6 * len(shots)), squeeze=False)
    scatter = None
    for row, (t, particles, polys) in enumerate(shots):
        scatter = draw(axes[row][0], particles, polys, (0, 1), args.speed_max, bounds)
        axes[row][0].set_title(f"t = {t:g} s, from above")
        draw(axes[row][1], particles, polys, (0, 2), args.speed_max, bounds)
        axes[row][1].set_title(f"t = {t:g} s, from the side (looking along +y)")
    fig.colorbar(scatter, ax=axes, shrink=0.8, label="particle speed [m/s]")
    fig.savefig(output, dpi=100)
    plt.close(fig)
    print(f"plot_site: {output}: {len(shots)} snapshot(s) at t = {', '.join(f'{t:g}' for t, _, _ in shots)} s")
    return 0


if __name__ == "__main__":
    sys.exit(main())
