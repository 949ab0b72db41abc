#!/usr/bin/env python3
"""Runs a row of bonded spheres cut by a blade against a running demlink-server.

Why: parallel bonds are declarable from every client; this Python client (like the
C++ and C ones) declares the rule as the proto message it is, and reads the bond counts
a region sensor reports. What is known without the server:

- A row of N spheres 10 um apart with a bond rule whose gap tolerance is 20 um gets the
  N - 1 neighbour bonds, all intact, and a region sensor over the row counts them.
- A thin blade (a PREDICTED rigid body) comes down between the middle two spheres and
  pushes them apart: the middle bond's tensile strength (1 kPa over a 5 mm bond radius:
  0.08 N) is far below the blade's push, so at least that bond breaks. No bond breaks
  before the blade touches a sphere (the row lies still on the floor).
- A bond is never made or lost, only broken: intact + broken = N - 1 at every answer.

It starts nothing itself. Exit code 0: all checks passed; 1: a check failed or the
server refused something.

Usage: run_bonded_row.py --host 127.0.0.1 --port PORT [--token T]
with PYTHONPATH holding the generated demlink/v1/*_pb2.py (or --generated DIR).
"""

import sys

from script_support import Checks, client_arguments, finish, import_client, run_guarded

TIME_STEP = 1e-5            # [s]
INTERVAL = 5e-4             # [s]
SAMPLES = 60                # exchanges: 30 ms
RADIUS = 0.005              # [m]
SPACING = 0.01001           # centre distance: a 10 um gap [m]
COUNT = 6                   # spheres in the row
BLADE_SIZE = (0.001, 0.03, 0.02)   # thin in x [m]
BLADE_X = 2.5 * SPACING     # between the third and fourth sphere [m]
BLADE_START = 0.025         # blade centre height at t = 0: its edge 5 mm above the row [m]
BLADE_SPEED = 0.5           # downwards [m/s]
BLADE_LOWEST = 0.006        # its edge stops 1 mm above the row's centre line [m]


def blade_z(t):
    return max(BLADE_LOWEST + BLADE_SIZE[2] / 2, BLADE_START - BLADE_SPEED * t)


def blade_touches(t):
    """The blade's edge is at or below the spheres' tops (it meets them there)."""
    return blade_z(t) - BLADE_SIZE[2] / 2 <= 2 * RADIUS


def declarations(pb):
    scene, coupling, geometry, bonds = pb["scene"], pb["coupling"], pb["geometry"], pb["bonds"]
    vec = lambda v: geometry.Vector3(x=v[0], y=v[1], z=v[2])
    box = scene.ComponentDeclaration(name="box", communication_interval=INTERVAL)
    box.simulation_box.time_step = TIME_STEP
    box.simulation_box.gravity.CopyFrom(vec((0.0, 0.0, -9.81)))
    box.simulation_box.coupling.expected_count = 7
    grain = scene.ComponentDeclaration(name="grain")
    grain.material.density = 2500.0
    grain.material.youngs_modulus = 1e7
    floor = scene.ComponentDeclaration(name="floor")
    floor.plane.normal.CopyFrom(vec((0.0, 0.0, 1.0)))
    floor.plane.material = "grain"
    row = scene.ComponentDeclaration(name="row")
    row.particle_lattice.material = "grain"
    row.particle_lattice.radius = RADIUS
    row.particle_lattice.origin.CopyFrom(vec((0.0, 0.0, RADIUS)))
    row.particle_lattice.spacing = SPACING
    row.particle_lattice.counts.nx, row.particle_lattice.counts.ny, row.particle_lattice.counts.nz = COUNT, 1, 1
    glue = scene.ComponentDeclaration(name="glue")
    rule = bonds.ParallelBonds(normal_stiffness_per_area=1e9, shear_stiffness_per_area=1e9, tensile_strength=1e3,
                               shear_strength=1e3, gap_tolerance=2e-5)
    glue.parallel_bonds.CopyFrom(rule)
    blade = scene.ComponentDeclaration(name="blade", communication_interval=INTERVAL)
    blade.rigid_body.box.size.CopyFrom(vec(BLADE_SIZE))
    blade.rigid_body.material = "grain"
    blade.rigid_body.position.CopyFrom(vec((BLADE_X, 0.0, blade_z(0.0))))
    blade.rigid_body.motion = coupling.RigidBody.PREDICTED
    watch = scene.ComponentDeclaration(name="watch", communication_interval=INTERVAL)
    watch.region_sensor.region.box.centre.CopyFrom(vec(((COUNT - 1) * SPACING / 2, 0.0, RADIUS)))
    watch.region_sensor.region.box.size.CopyFrom(vec((COUNT * SPACING + 0.02, 0.04, 0.04)))
    return [box, grain, floor, row, glue, blade, watch]


def run(args):
    imported = import_client(args.generated, ("scene", "coupling", "geometry", "bonds"))
    if imported is None:
        return 1
    dc, pb = imported
    checks = Checks()
    made = COUNT - 1
    history = []  # (time, blade touching, intact, broken)
    with dc.Client(args.host, args.port, timeout=args.timeout) as client:
        client.hello("run_bonded_row.py", access_token=args.token)
        for decl in declarations(pb):
            client.declare(decl)
        client.wait_compiled()
        for _ in range(SAMPLES):
            t = client.time
            velocity = (blade_z(t + INTERVAL) - blade_z(t)) / INTERVAL
            outputs = client.exchange({"blade": client.rigid_body_input(
                position=(BLADE_X, 0.0, blade_z(t)), linear_velocity=(0.0, 0.0, velocity))})
            sensor = outputs["watch"].region_sensor
            history.append((client.time, blade_touches(client.time), sensor.bonds_intact, sensor.bonds_broken))
        client.bye("run_bonded_row.py done")

    for t, touching, intact, broken in history:
        checks.expect(intact + broken == made, f"t = {t:.4f} s: intact {intact} + broken {broken} != {made}")
        if not touching:
            checks.expect(broken == 0, f"t = {t:.4f} s: {broken} bond(s) broken before the blade touched the row")
    checks.expect(history[0][2] == made, f"first answer: {history[0][2]} intact bonds, expected {made}")
    final_broken = history[-1][3]
    checks.expect(final_broken >= 1, f"the blade broke no bond ({history[-1]})")
    print(f"bonds: {made} made; broken by the blade: {final_broken}; "
          f"first break at t = {next((t for t, _, _, b in history if b > 0), float('nan')):.4f} s")
    return finish("run_bonded_row", checks, "")


def main():
    return run_guarded("run_bonded_row", run, client_arguments(__doc__.splitlines()[0]).parse_args())


if __name__ == "__main__":
    sys.exit(main())
