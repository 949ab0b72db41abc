"""Soak run of demlink-server on loopback: clients that behave and clients that misbehave.

For --seconds S (default 600) several client threads connect to one demlink-server, each
time picking a behaviour at random: run a short simulation to its end, leave with Bye,
stop reading while packages stream, send garbage bytes, announce a huge frame before
Hello, connect and say nothing, hang in the middle of an assembly, disconnect in the
middle of a run; and the attacks: an interval of the 1e8-step cap over 1,000 spheres left
after a few seconds (which must cut it short), a particle-source rate of 1e30 declared or
sent at run time, gravity -1e10 sent at run time, 100,000 expected names, a 60,000-byte
Hello.simulation, a component name with '/'. Beside them a probe times Hello -> Welcome. Once a second the server's resident memory (VmRSS) and open file
descriptors (/proc/<pid>/fd) are sampled. At the end the clients stop, the server gets
time to close what they left (timeouts, grace), a last client must still run a
simulation, and the figures are printed: start (after a warm-up), end, max.

The bar is "flat": exit 1 when the end figures exceed the start by more than
--rss-slack-mb (default 64) or --fd-slack (default 8), when the server died, when the
last client could not run its simulation, when any client got INTERNAL, when an attack
was not refused as documented or an Error was longer than 4,096 bytes, or when a Hello
waited longer than --hello-bound-s (default 1) for its Welcome; 0 otherwise.

    PYTHONPATH=<build>/client/python/generated:client/python \\
        python3 bench/soak_server.py --server build/release/server/demlink-server --seconds 600

Loopback only; the server writes into a temporary folder that is removed at the end.
"""

import argparse
import os
import random
import re
import shutil
import socket
import subprocess
import sys
import tempfile
import threading
import time

from demlink.v1 import protocol_pb2, scene_pb2
from demlink_client import Client, ServerError, SimulationEnded, encode_frame
from google.protobuf import json_format


def scene(expected_count=4, end_time=2e-3, view=False, n=3, interval=1e-4, extra=()):
    """A small scene: the box (exchanged every `interval` s), glass, a floor, n^3 spheres."""
    components = [
        {"name": "box", "communication_interval": interval,
         "simulation_box": {"time_step": 1e-5, "end_time": end_time,
                            "coupling": {"expected_count": expected_count}}},
        {"name": "glass", "material": {"density": 2500, "youngs_modulus": 5e6}},
        {"name": "floor", "plane": {"normal": {"z": 1}, "material": "glass"}},
        {"name": "spheres", "particle_lattice": {"material": "glass", "radius": 0.002, "spacing": 0.006,
                                                 "origin": {"x": 0.01, "y": 0.01, "z": 0.003},
                                                 "counts": {"nx": n, "ny": n, "nz": n}}},
    ]
    if view:
        components.append({"name": "view", "communication_interval": 1e-4, "particle_view": {}})
    components.extend(extra)
    out = []
    for c in components:
        declaration = scene_pb2.ComponentDeclaration()
        json_format.ParseDict(c, declaration)
        out.append(declaration)
    return out


class Tally:
    def __init__(self):
        self.lock = threading.Lock()
        self.counts = {}

    def add(self, key):
        with self.lock:
            self.counts[key] = self.counts.get(key, 0) + 1


def connect_raw(port, timeout=5.0):
    sock = socket.create_connection(("127.0.0.1", port), timeout=timeout)
    sock.settimeout(timeout)
    return sock


def drain_until_closed(sock, limit_s=15.0):
    """Reads and discards until the server closes (bounded)."""
    end = time.monotonic() + limit_s
    try:
        while time.monotonic() < end:
            if not sock.recv(65536):
                return True
    except (socket.timeout, OSError):
        return False
    return False


def run_simulation(port, group, bye_after=None, drop_after=None, view=False):
    """Runs the small scene as simulation `group`; returns the outcome's name."""
    with Client("127.0.0.1", port, timeout=10.0) as c:
        c.hello("soak-good", simulation=group)
        for d in scene(expected_count=5 if view else 4, view=view):
            c.declare(d)
        c.wait_compiled()
        exchanges = 0
        while True:
            if drop_after is not None and exchanges >= drop_after:
                c.close()
                return "dropped mid-run"
            if bye_after is not None and exchanges >= bye_after:
                c.bye("soak")
                return "bye"
            try:
                c.exchange()
            except SimulationEnded as ended:
                return "completed" if ended.finished.reason == "end time reached" else "ended"
            exchanges += 1


def good(port, rng, group):
    return run_simulation(port, group, view=rng.random() < 0.3)


def bye_early(port, rng, group):
    return run_simulation(port, group, bye_after=rng.randint(1, 5))


def drop_mid_run(port, rng, group):
    return run_simulation(port, group, drop_after=rng.randint(1, 5))


def stop_reading(port, rng, group):
    """Declares a view with the box and sends its packages without reading any answer."""
    hello = protocol_pb2.ClientMessage()
    hello.hello.protocol_version = 1
    hello.hello.client_name = "soak-stop-reading"
    hello.hello.simulation = group
    burst = encode_frame(hello)
    for d in scene(expected_count=5, end_time=0.05, view=True, n=10):  # views of ~18 kB
        m = protocol_pb2.ClientMessage()
        m.declare.component.CopyFrom(d)
        burst += encode_frame(m)
    for step in range(0, 5000, 10):  # ids by declaration order: box 1, view 5
        for component in (1, 5):
            m = protocol_pb2.ClientMessage()
            m.data.component_id = component
            m.data.step = step
            burst += encode_frame(m)
    send_then_drain(port, burst, pause_s=rng.uniform(1.0, 4.0))
    return "stopped reading"


def send_then_drain(port, data, pause_s=0.0):
    """Sends `data` on a new connection, reads nothing for `pause_s`, then reads until the
    server closes the connection."""
    sock = connect_raw(port)
    try:
        sock.sendall(data)
        time.sleep(pause_s)
    except OSError:
        pass
    drain_until_closed(sock)
    sock.close()


def garbage(port, rng, group):
    send_then_drain(port, bytes(rng.getrandbits(8) for _ in range(rng.randint(1, 4096))))
    return "garbage"


def huge_frame_before_hello(port, rng, group):
    send_then_drain(port, b"\x80\x80\x80\x1e" + b"x" * (1 << 20))  # announces 60 MiB
    return "huge frame before Hello"


def silent(port, rng, group):
    send_then_drain(port, b"")  # the Hello timeout closes it
    return "silent"


def hang_mid_assembly(port, rng, group):
    """Declares part of a set that expects more, then waits without a word."""
    try:
        with Client("127.0.0.1", port, timeout=15.0) as c:
            c.hello("soak-hang", simulation=group)
            for d in scene(expected_count=50)[:2]:
                c.declare(d)
            c.receive(timeout=15.0)  # the assembly timeout's Error
    except ServerError as error:
        return "hung, ended by " + protocol_pb2.Error.Code.Name(error.error.code)
    return "hung"


def refused_as(expected_code, run):
    """Runs `run`; the outcome says whether the server refused it with `expected_code`
    (and a bounded message) or answered otherwise."""
    try:
        run()
    except ServerError as error:
        code = protocol_pb2.Error.Code.Name(error.error.code)
        size = len(error.error.message.encode())
        if size > 4096:
            return f"UNBOUNDED error of {size} bytes"
        if code == "SERVER_BUSY" or (code == "OUT_OF_ORDER" and error.error.field == "hello.simulation"):
            return "not tried: server busy (" + code + ")"  # every slot held by other clients' simulations
        return "refused as documented" if code == expected_code else "WRONG code " + code + " " + error.error.message[:120]
    except SimulationEnded as ended:
        return "WRONG: ended " + ended.finished.reason
    return "WRONG: accepted"


SOURCE = {"name": "pour", "communication_interval": 1e-4,
          "particle_source": {"material": "glass", "sizes": {"uniform": {"r_min": 0.0019, "r_max": 0.002}},
                              "box": {"lower": {"x": 0.03, "y": -0.01, "z": 0.01},
                                      "upper": {"x": 0.05, "y": 0.01, "z": 0.02}},
                              "rate_particles_per_s": 100, "seed": 3}}


def huge_interval(port, rng, group):
    """One interval of the 1e8-step cap over 1,000 spheres; the client leaves after a few
    seconds, which cuts the interval short (else it would step for hours)."""
    with Client("127.0.0.1", port, timeout=30.0) as c:
        c.hello("soak-huge", simulation=group)
        for d in scene(end_time=0, n=10, interval=1000.0):
            c.declare(d)
        c.wait_compiled()
        package = protocol_pb2.ClientMessage()
        package.data.component_id = c.component("box").id
        package.data.step = 0
        c.send(package)
        time.sleep(rng.uniform(1.0, 4.0))
    return "left a 1e8-step interval"


def source_rate_declared(port, rng, group):
    """A particle source declared with a rate of 1e30 particles/s."""
    def run():
        with Client("127.0.0.1", port, timeout=15.0) as c:
            c.hello("soak-rate", simulation=group)
            for d in scene(expected_count=5, extra=[dict(SOURCE, particle_source=dict(
                    SOURCE["particle_source"], rate_particles_per_s=1e30))]):
                c.declare(d)
            c.wait_compiled()
    return refused_as("INVALID_DECLARATION", run)


def runtime_input_past_limit(port, rng, group):
    """A valid simulation whose client sends a source rate of 1e30 or gravity -1e10 at run time."""
    def run():
        with Client("127.0.0.1", port, timeout=15.0) as c:
            c.hello("soak-runtime", simulation=group)
            for d in scene(expected_count=5, end_time=0.01, extra=[SOURCE]):
                c.declare(d)
            c.wait_compiled()
            c.exchange()
            gravity = rng.random() < 0.5
            for name in c.due():
                m = protocol_pb2.ClientMessage()
                m.data.component_id = c.component(name).id
                m.data.step = c.step
                if name == "box" and gravity:
                    m.data.simulation_box_input.gravity.z = -1e10
                if name == "pour" and not gravity:
                    m.data.particle_source_input.rate_particles_per_s = 1e30
                c.send(m)
            c.receive()
    return refused_as("INVALID_INPUT", run)


def many_expected_names(port, rng, group):
    """A box that expects 100,000 names: the assembly timeout's Error names a few and the count."""
    # Built before the Hello: under the soak's 0.5 s quiet period a Declare that comes later
    # than that after the Hello finds an empty simulation compiled (docs/cosim.md).
    box = scene()[0]
    box.simulation_box.coupling.expected_count = 0
    box.simulation_box.coupling.expected_names.extend(f"part-{k:06d}" for k in range(100000))

    def run():
        with Client("127.0.0.1", port, timeout=15.0) as c:
            c.hello("soak-names", simulation=group)
            c.declare(box)
            c.receive(timeout=15.0)
    return refused_as("TIMEOUT", run)


def long_simulation_name(port, rng, group):
    """A 60,000-byte Hello.simulation: welcomed (logged cut), then the client leaves."""
    with Client("127.0.0.1", port, timeout=10.0) as c:
        c.hello("soak-long", simulation=group + "x" * 60000)
    return "long simulation name welcomed"


def slash_in_name(port, rng, group):
    def run():
        with Client("127.0.0.1", port, timeout=10.0) as c:
            c.hello("soak-slash", simulation=group)
            declaration = scene()[1]
            declaration.name = "../glass/x"
            c.declare(declaration)
            c.receive(timeout=10.0)
    return refused_as("INVALID_DECLARATION", run)


class HelloProbe:
    """Times Hello -> Welcome on fresh connections, whatever the simulations do."""

    def __init__(self):
        self.lock = threading.Lock()
        self.waits = []

    def run(self, port, stop):
        k = 0
        while not stop.is_set():
            k += 1
            try:
                with Client("127.0.0.1", port, timeout=10.0) as c:
                    started = time.monotonic()
                    c.hello("soak-probe", simulation=f"probe-{k}")
                    waited = time.monotonic() - started
                with self.lock:
                    self.waits.append(waited)
            except ServerError:
                pass  # every simulation slot taken: not a wait
            except Exception:  # noqa: BLE001 - a probe that fails is counted as the bound
                with self.lock:
                    self.waits.append(float("inf"))
            stop.wait(0.5)


BEHAVIOURS = [
    (good, 4), (bye_early, 1), (drop_mid_run, 1), (stop_reading, 1), (garbage, 1),
    (huge_frame_before_hello, 1), (silent, 1), (hang_mid_assembly, 1),
    (huge_interval, 1), (source_rate_declared, 1), (runtime_input_past_limit, 1), (many_expected_names, 1),
    (long_simulation_name, 1), (slash_in_name, 1),
]


def worker(port, stop, tally, seed):
    rng = random.Random(seed)
    names = [b for b, w in BEHAVIOURS for _ in range(w)]
    attempt = 0
    while not stop.is_set():
        behaviour = rng.choice(names)
        attempt += 1
        try:
            # Each attempt names its own simulation: an attack's simulation may still be
            # assembling or stepping (until its timeout) when the worker moves on.
            outcome = behaviour(port, rng, f"soak-{seed}-{attempt}")
        except ServerError as error:
            outcome = "refused " + protocol_pb2.Error.Code.Name(error.error.code)
            time.sleep(rng.uniform(0.05, 0.3))  # busy with another simulation: retry later
        except Exception as error:  # noqa: BLE001 - any client-side failure is an outcome to count
            outcome = "client error " + type(error).__name__
        tally.add(f"{behaviour.__name__}: {outcome}")


def sample(pid):
    with open(f"/proc/{pid}/status") as f:
        rss = int(re.search(r"VmRSS:\s+(\d+)", f.read()).group(1)) * 1024
    return rss, len(os.listdir(f"/proc/{pid}/fd"))


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--server", required=True, help="the demlink-server executable")
    parser.add_argument("--seconds", type=float, default=600.0)
    parser.add_argument("--clients", type=int, default=6)
    parser.add_argument("--rss-slack-mb", type=float, default=64.0)
    parser.add_argument("--fd-slack", type=int, default=8)
    parser.add_argument("--seed", type=int, default=1)
    parser.add_argument("--hello-bound-s", type=float, default=1.0)
    args = parser.parse_args()

    work = tempfile.mkdtemp(prefix="demlink_soak_")
    log_path = os.path.join(work, "server.log")
    log = open(log_path, "w")
    server = subprocess.Popen(
        [args.server, "--port", "0", "--output", os.path.join(work, "out"), "--overwrite",
         "--timeout", "2", "--assembly-timeout", "3", "--hello-timeout", "2", "--quiet-period", "0.5",
         "--max-queued-bytes", "1048576", "--progress", "5"],
        stdout=log, stderr=subprocess.STDOUT)
    try:
        port = None
        for _ in range(100):
            with open(log_path) as f:
                m = re.search(r"listening on 127\.0\.0\.1:(\d+)", f.read())
            if m:
                port = int(m.group(1))
                break
            time.sleep(0.1)
        if port is None:
            print("the server did not start; its log:\n" + open(log_path).read())
            return 1

        stop = threading.Event()
        tally = Tally()
        threads = [threading.Thread(target=worker, args=(port, stop, tally, args.seed + k), daemon=True)
                   for k in range(args.clients)]
        samples = []
        started = time.monotonic()
        probe = HelloProbe()
        threads.append(threading.Thread(target=probe.run, args=(port, stop), daemon=True))
        for t in threads:
            t.start()
        while time.monotonic() - started < args.seconds and server.poll() is None:
            samples.append((time.monotonic() - started, *sample(server.pid)))
            time.sleep(1.0)
        stop.set()
        for t in threads:
            t.join(timeout=60)
        if server.poll() is not None:
            print(f"FAIL: the server exited with {server.returncode}; log in {log_path}")
            return 1
        time.sleep(5.0)  # Hello timeout, assembly timeout, close grace: what clients left is closed
        end_rss, end_fds = sample(server.pid)
        last = "not tried"
        for _ in range(30):  # a simulation the clients left may still be ending
            try:
                last = run_simulation(port, "soak-last")
                break
            except ServerError as error:
                last = f"refused: {error}"
                time.sleep(1.0)
            except Exception as error:  # noqa: BLE001 - reported as the failure
                last = f"failed: {error!r}"
                break

        warm = [s for s in samples if s[0] >= min(10.0, args.seconds / 6)] or samples
        start_rss, start_fds = warm[0][1], warm[0][2]
        max_rss = max(s[1] for s in samples + [(0, end_rss, end_fds)])
        max_fds = max(s[2] for s in samples + [(0, end_rss, end_fds)])
        mb = 1.0 / (1 << 20)
        print(f"soak: {args.seconds:.0f} s, {args.clients} clients, {len(samples)} samples")
        for key in sorted(tally.counts):
            print(f"  {tally.counts[key]:6d}  {key}")
        print(f"RSS [MiB]: start {start_rss * mb:.1f} (at {warm[0][0]:.0f} s), end {end_rss * mb:.1f}, "
              f"max {max_rss * mb:.1f}")
        print(f"open fds:  start {start_fds}, end {end_fds}, max {max_fds}")
        print(f"last client after the soak: {last}")
        waits = sorted(probe.waits)
        if waits:
            print(f"Hello -> Welcome [ms]: {len(waits)} probes, median {1e3 * waits[len(waits) // 2]:.1f}, "
                  f"max {1e3 * waits[-1]:.1f}")
        with open(log_path) as f:
            server_log = f.read()
        for what, marker in (("output held back", "not taken by the client"),
                             ("client timeouts", "timeout: no package"),
                             ("assembly timeouts", "was not compiled within"),
                             ("no Hello in time", "closed: no Hello within"),
                             ("large frames before Hello", "allowed before Hello"),
                             ("bad frames", "closed: bad frame")):
            print(f"server log: {server_log.count(marker):6d}  {what}")
        failed = []
        if end_rss > start_rss + args.rss_slack_mb * (1 << 20):
            failed.append(f"RSS grew by {(end_rss - start_rss) * mb:.1f} MiB")
        if end_fds > start_fds + args.fd_slack:
            failed.append(f"open fds grew by {end_fds - start_fds}")
        if last != "completed":
            failed.append("the last client could not run its simulation")
        if sum(v for k, v in tally.counts.items() if k.startswith("good: completed")) == 0:
            failed.append("no good client completed a simulation")
        wrong = [k for k in tally.counts if "INTERNAL" in k or "WRONG" in k or "UNBOUNDED" in k]
        if wrong:
            failed.append("attacks answered wrongly: " + ", ".join(wrong))
        if waits and waits[-1] > args.hello_bound_s:
            failed.append(f"a Hello waited {waits[-1]:.3f} s for its Welcome")
        print("PASS" if not failed else "FAIL: " + "; ".join(failed))
        return 0 if not failed else 1
    finally:
        server.terminate()
        try:
            server.wait(timeout=30)
        except subprocess.TimeoutExpired:
            server.kill()
        log.close()
        shutil.rmtree(work, ignore_errors=True)


if __name__ == "__main__":
    sys.exit(main())
