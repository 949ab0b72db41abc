#!/usr/bin/env python3
"""One of two clients of the multi-host test's stand-in co-simulation (press_scene.json).

Why: the multi-host test (run_netns_test.sh) needs two client processes that declare
their own components into one shared scene, exchange at every sample and finish by
themselves, so that the run can be repeated over loopback and compared bit for bit. The
real clients (demlink-excavator, demlink-truck) take this part once they exist; until
then two instances of this script stand in for them. Each instance declares

- `<name>_ram`: a rigid box (PREDICTED motion) above its half of the particle layer of
  press_scene.json, lowered at a constant speed until it squeezes the layer, then held;
- `<name>_zone`: a region sensor over its half of the layer,

and writes one CSV row per sample (time, step, mean force on the ram, sensor count and
mass) to --csv. The rows hold simulated quantities only (no wall time), so two runs of
the same co-simulation give identical files.

It checks only what makes the run meaningful: the Compiled interval of its components,
a force of zero while the ram is clear of the spheres and an upward force once it
presses; the physics is tested elsewhere (tests/python/run_small_coupled_scene.py).
Exit code 0: done; 1: a check failed or the server refused something (printed).

Usage: press_client.py --host H --port P --name a --x-centre 0.0275 --csv a.csv
(PYTHONPATH must hold the generated demlink/v1/*_pb2.py and client/python).
"""

import argparse
import math
import os
import sys

HERE = os.path.dirname(os.path.abspath(__file__))

# Must agree with press_scene.json [SI units].
TIME_STEP = 1e-5                 # [s]
INTERVAL = 5e-4                  # communication interval of both components [s]
RADIUS = 0.005                   # sphere radius [m]
LAYER_Y_CENTRE = 0.0215          # centre of the layer along y (4 rows, spacing 11 mm) [m]
RAM_SIZE = (0.05, 0.06, 0.01)    # [m]
BOTTOM_START = 0.012             # bottom face of the ram at t = 0 [m] (2 mm above the spheres)
BOTTOM_FINAL = 0.0095            # held from there on [m] (0.5 mm squeeze per sphere)
DESCENT_SPEED = 0.1              # [m/s]
ZONE_SIZE = (0.055, 0.06, 0.03)  # region sensor box [m]


def ram_centre_z(t):
    """Prescribed height of the ram's centre at time t [m]."""
    return max(BOTTOM_FINAL, BOTTOM_START - DESCENT_SPEED * t) + RAM_SIZE[2] / 2


def declarations(pb, name, x_centre):
    scene, coupling, geometry = pb
    vec = lambda v: geometry.Vector3(x=v[0], y=v[1], z=v[2])
    ram = scene.ComponentDeclaration(name=f"{name}_ram", communication_interval=INTERVAL)
    ram.rigid_body.box.size.CopyFrom(vec(RAM_SIZE))
    ram.rigid_body.material = "grain"
    ram.rigid_body.position.CopyFrom(vec((x_centre, LAYER_Y_CENTRE, ram_centre_z(0.0))))
    ram.rigid_body.motion = coupling.RigidBody.PREDICTED

    zone = scene.ComponentDeclaration(name=f"{name}_zone", communication_interval=INTERVAL)
    zone.region_sensor.region.box.centre.CopyFrom(vec((x_centre, LAYER_Y_CENTRE, RADIUS)))
    zone.region_sensor.region.box.size.CopyFrom(vec(ZONE_SIZE))
    # The ram last: run_netns_test.sh may wait for it (CLIENT_A_READY) before it starts
    # the other client, so the declaration order, and with it the world, is the same in
    # every run.
    return [zone, ram]


def run(args):
    sys.path.insert(0, os.path.join(HERE, "..", "..", "client", "python"))
    try:
        import demlink_client as dc
        from demlink.v1 import coupling_pb2, geometry_pb2, scene_pb2
    except ImportError as e:
        print(f"press_client: cannot import the client or the generated classes ({e}); set PYTHONPATH",
              file=sys.stderr)
        return 1
    ram_name, zone_name = f"{args.name}_ram", f"{args.name}_zone"
    failures = []
    with dc.Client(args.host, args.port, timeout=args.timeout) as client, open(args.csv, "w") as csv:
        client.hello(f"press_client {args.name}", access_token=args.token)
        for decl in declarations((scene_pb2, coupling_pb2, geometry_pb2), args.name, args.x_centre):
            client.declare(decl)
        compiled = client.wait_compiled()
        steps = round(INTERVAL / TIME_STEP)
        for name in (ram_name, zone_name):
            if client.component(name).interval_steps != steps:
                failures.append(f"{name}: interval_steps {client.component(name).interval_steps} != {steps}")
        interval = steps * compiled.time_step
        csv.write("time_s,step,force_z_N,zone_count,zone_mass_kg\n")
        forces = []
        for _ in range(args.samples):
            t = client.time
            velocity = (ram_centre_z(t + interval) - ram_centre_z(t)) / interval
            outputs = client.exchange({ram_name: client.rigid_body_input(
                position=(args.x_centre, LAYER_Y_CENTRE, ram_centre_z(t)), linear_velocity=(0.0, 0.0, velocity))})
            force_z = outputs[ram_name].rigid_body.mean_force.z
            zone = outputs[zone_name].region_sensor
            forces.append((client.time, force_z))
            csv.write(f"{client.time!r},{client.step},{force_z!r},{zone.count},{zone.mass!r}\n")
        finished = client.bye(f"press_client {args.name} done")
        print(f"press_client {args.name}: finished at step {finished.step}: {finished.reason}")

    clear = [f for t, f in forces if ram_centre_z(t) - RAM_SIZE[2] / 2 > 2 * RADIUS + 2e-4]
    pressing = [f for t, f in forces[-len(forces) // 5:]]
    if not clear or any(f != 0.0 for f in clear):
        failures.append(f"force on the ram while clear of the spheres: {[f for f in clear if f != 0.0][:5]}")
    if not all(math.isfinite(f) and f > 0.0 for f in pressing):
        failures.append(f"force on the ram while pressing is not positive: {pressing[:5]}")
    for failure in failures:
        print(f"press_client {args.name}: FAIL: {failure}", file=sys.stderr)
    return 1 if failures else 0


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--host", default="127.0.0.1")
    parser.add_argument("--port", type=int, required=True)
    parser.add_argument("--token", default=os.environ.get("DEMLINK_TOKEN", ""))
    parser.add_argument("--name", required=True, help="prefix of the component names")
    parser.add_argument("--x-centre", type=float, required=True, help="x of the ram's centre [m]")
    parser.add_argument("--samples", type=int, default=200, help="exchanges [-] (>= 100)")
    parser.add_argument("--csv", required=True, help="per-sample output file")
    parser.add_argument("--timeout", type=float, default=30.0, help="longest wait for one answer [s]")
    args = parser.parse_args()
    if args.samples < 100:
        parser.error("--samples must be >= 100 (the ram needs 50 samples to reach the layer)")
    try:
        return run(args)
    except Exception as e:  # a refused declaration, a timeout, a closed connection
        print(f"press_client {args.name}: FAILED: {type(e).__name__}: {e}", file=sys.stderr)
        return 1


if __name__ == "__main__":
    sys.exit(main())
