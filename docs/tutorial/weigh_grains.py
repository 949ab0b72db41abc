#!/usr/bin/env python3
"""Tutorial client (docs/tutorial.md): pour grains into a tray and weigh them.

The Python twin of weigh_grains.cpp, on client/python/demlink_client.py. Needs the
generated demlink/v1/*_pb2.py and client/python on PYTHONPATH.
Usage: weigh_grains.py [--host H] [--port P] [--token T]; exit 0 when the force on the
tray equals the weight of the grains in it within 3 %.
"""
import argparse
import sys

import demlink_client as dc
from demlink.v1 import coupling_pb2, geometry_pb2, scene_pb2

INTERVAL = 1e-3  # communication interval [s]
GRAVITY = 9.81   # [m/s^2]


def vec(x=0.0, y=0.0, z=0.0):
    return geometry_pb2.Vector3(x=x, y=y, z=z)


def declarations():
    box = scene_pb2.ComponentDeclaration(name="box")
    box.simulation_box.time_step = 1e-5
    # 10 % instead of the default 1 %: trades restitution accuracy for speed (at 1 % these
    # grains (e = 0.3) need a step below 7.4e-6 s).
    box.simulation_box.restitution_tolerance = 0.1
    box.simulation_box.end_time = 0.8
    box.simulation_box.gravity.CopyFrom(vec(z=-GRAVITY))
    box.simulation_box.bounds.lower.CopyFrom(vec(-0.1, -0.1, -0.02))
    box.simulation_box.bounds.upper.CopyFrom(vec(0.1, 0.1, 0.3))
    box.simulation_box.coupling.expected_count = 6

    grain = scene_pb2.ComponentDeclaration(name="grain")
    grain.material.density = 2500
    grain.material.youngs_modulus = 1e7
    grain.material.poisson_ratio = 0.3
    grain.material.restitution = 0.3
    grain.material.sliding_friction = 0.5

    floor = scene_pb2.ComponentDeclaration(name="floor")
    floor.plane.normal.CopyFrom(vec(z=1.0))
    floor.plane.material = "grain"

    # An open-top tray 8 x 8 x 4 cm whose centre is 5 cm above the floor.
    tray = scene_pb2.ComponentDeclaration(name="tray", communication_interval=INTERVAL)
    tray.rigid_body.box.size.CopyFrom(vec(0.08, 0.08, 0.04))
    tray.rigid_body.box.open_top = True
    tray.rigid_body.material = "grain"
    tray.rigid_body.position.CopyFrom(vec(z=0.05))
    tray.rigid_body.motion = coupling_pb2.RigidBody.PREDICTED

    pour = scene_pb2.ComponentDeclaration(name="pour")
    source = pour.particle_source
    source.material = "grain"
    source.sizes.radius = 0.004
    source.box.centre.CopyFrom(vec(z=0.12))
    source.box.half_extents.CopyFrom(vec(0.025, 0.025, 0.01))
    source.rate_particles_per_s = 1000
    source.stop_time = 0.1
    source.velocity.CopyFrom(vec(z=-0.5))
    source.seed = 1

    inside = scene_pb2.ComponentDeclaration(name="in_tray", communication_interval=INTERVAL)
    inside.region_sensor.region.box.size.CopyFrom(vec(0.08, 0.08, 0.04))  # centred on the tray
    inside.region_sensor.region.attached_to = "tray"
    return [box, grain, floor, tray, pour, inside]


def main():
    parser = argparse.ArgumentParser(description="pour grains into a tray and weigh them")
    parser.add_argument("--host", default="127.0.0.1")
    parser.add_argument("--port", type=int, default=47000)
    parser.add_argument("--token", default="")
    args = parser.parse_args()

    with dc.Client(args.host, args.port) as client:
        client.hello("weigh_grains.py", access_token=args.token)
        for declaration in declarations():
            client.declare(declaration)
        compiled = client.wait_compiled()
        print(compiled.report.text, end="")
        outputs = client.initial_outputs()
        try:
            while True:
                held = client.rigid_body_input(position=(0.0, 0.0, 0.05))  # held still
                outputs = client.exchange({"tray": held})
                if client.step % 10000 == 0:  # every 0.1 s
                    print(f"t = {client.time:.3f} s: {outputs['in_tray'].region_sensor.count} grains in the tray")
        except dc.SimulationEnded as ended:
            reason = ended.finished.reason
        sensor = outputs["in_tray"].region_sensor
        weight = sensor.mass * GRAVITY
        force = -outputs["tray"].rigid_body.mean_force.z  # ON the tray BY the grains: downwards
        print(f"{reason} at t = {client.time:.3f} s: {sensor.count} grains, weight {weight:.5f} N, "
              f"force on the tray {force:.5f} N")
    return 0 if sensor.count > 0 and abs(force - weight) < 0.03 * weight else 1


if __name__ == "__main__":
    sys.exit(main())
