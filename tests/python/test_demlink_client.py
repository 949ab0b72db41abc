"""Unit tests of the Python client (client/python/demlink_client.py) without a server.

Why: the client's framing must produce exactly the bytes the C++ codec produces (golden
frames, also checked by test_golden_frames.cpp and by protoc --encode), and its sample
grid logic (who is due when, which outputs come back at which step) must follow
docs/protocol.md. The grid is checked against a scripted fake server on 127.0.0.1.

Run: PYTHONPATH=<build>/client/python/generated:client/python python3 -m unittest \
         tests/python/test_demlink_client.py
Environment: DEMLINK_PROTOC (optional) names the protoc to compare with.
"""

import os
import shutil
import socket
import subprocess
import threading
import unittest

from google.protobuf import text_format

import demlink_client as dc
from demlink.v1 import protocol_pb2, scene_pb2

GOLDEN_DIR = os.path.join(os.path.dirname(os.path.abspath(__file__)), "golden")
PROTO_DIR = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "proto")
TIMEOUT_S = 5.0


def golden_frames():
    frames = {}
    with open(os.path.join(GOLDEN_DIR, "frames.hex")) as f:
        for line in f:
            if line.strip() and not line.startswith("#"):
                name, hexdigits = line.split()
                frames[name] = bytes.fromhex(hexdigits)
    return frames


def golden_message(name):
    with open(os.path.join(GOLDEN_DIR, name + ".txtpb")) as f:
        return text_format.Parse(f.read(), protocol_pb2.ClientMessage())


class Framing(unittest.TestCase):
    def test_varint_known_values(self):
        cases = {0: "00", 1: "01", 127: "7f", 128: "8001", 300: "ac02", 2**64 - 1: "ffffffffffffffffff01"}
        for value, expected in cases.items():
            self.assertEqual(dc.encode_varint(value).hex(), expected, value)
        with self.assertRaises(ValueError):
            dc.encode_varint(-1)

    def test_encoder_produces_the_golden_frames(self):
        frames = golden_frames()
        self.assertEqual(sorted(frames), ["hello", "rigid_body_data"])
        for name, frame in frames.items():
            self.assertEqual(dc.encode_frame(golden_message(name)).hex(), frame.hex(), name)

    def test_protoc_encode_gives_the_golden_payloads(self):
        protoc = os.environ.get("DEMLINK_PROTOC") or shutil.which("protoc")
        if not protoc:
            self.skipTest("protoc not found (set DEMLINK_PROTOC)")
        for name, frame in golden_frames().items():
            with open(os.path.join(GOLDEN_DIR, name + ".txtpb"), "rb") as text:
                payload = subprocess.run(
                    [protoc, "-I" + PROTO_DIR, "--encode=demlink.v1.ClientMessage",
                     os.path.join(PROTO_DIR, "demlink", "v1", "protocol.proto")],
                    stdin=text, capture_output=True, check=True, timeout=30).stdout
            self.assertEqual(dc.encode_varint(len(payload)) + payload, frame, name)

    def test_decoder_splits_a_stream_fed_byte_by_byte(self):
        frames = golden_frames()
        decoder = dc.FrameDecoder()
        payloads = []
        for byte in frames["hello"] + frames["rigid_body_data"]:
            decoder.feed(bytes([byte]))
            while (payload := decoder.next()) is not None:
                payloads.append(payload)
        self.assertEqual(len(payloads), 2)
        self.assertEqual(decoder.pending_bytes(), 0)
        data = protocol_pb2.ClientMessage.FromString(payloads[1])
        self.assertEqual(data, golden_message("rigid_body_data"))
        self.assertEqual(data.data.step, 1000)

    def test_decoder_refuses_a_frame_over_the_cap_before_its_payload(self):
        decoder = dc.FrameDecoder(max_frame_bytes=100)
        decoder.feed(golden_frames()["rigid_body_data"][:2])  # prefix only: 135 bytes announced
        with self.assertRaisesRegex(dc.FrameError, "135 bytes exceeds the cap of 100"):
            decoder.next()

    def test_decoder_refuses_a_prefix_longer_than_ten_bytes(self):
        decoder = dc.FrameDecoder()
        decoder.feed(b"\xff" * 11)
        with self.assertRaisesRegex(dc.FrameError, "more than 10 bytes"):
            decoder.next()

    def test_decoder_waits_for_an_incomplete_frame(self):
        frame = golden_frames()["hello"]
        decoder = dc.FrameDecoder()
        decoder.feed(frame[:-1])
        self.assertIsNone(decoder.next())
        decoder.feed(frame[-1:])
        self.assertEqual(decoder.next(), frame[1:])


class FakeServer:
    """Accepts one connection on 127.0.0.1 and runs `script(conn)` in a thread."""

    def __init__(self, script):
        self._listener = socket.create_server(("127.0.0.1", 0))
        self._listener.settimeout(TIMEOUT_S)
        self.port = self._listener.getsockname()[1]
        self.failure = None
        self._script = script
        self._thread = threading.Thread(target=self._run, daemon=True)
        self._thread.start()

    def _run(self):
        try:
            conn, _ = self._listener.accept()
            conn.settimeout(TIMEOUT_S)
            with conn:
                self._script(ServerSide(conn))
        except Exception as e:  # reported to the test by join()
            self.failure = e
        finally:
            self._listener.close()

    def join(self):
        self._thread.join(TIMEOUT_S)
        if self._thread.is_alive():
            raise AssertionError("fake server did not finish")
        if self.failure:
            raise self.failure


class ServerSide:
    def __init__(self, conn):
        self.conn = conn
        self.decoder = dc.FrameDecoder()

    def receive_frame(self):
        while (payload := self.decoder.next()) is None:
            data = self.conn.recv(65536)
            if not data:
                raise ConnectionError("client closed the connection")
            self.decoder.feed(data)
        return payload

    def receive(self):
        return protocol_pb2.ClientMessage.FromString(self.receive_frame())

    def send(self, message):
        self.conn.sendall(dc.encode_frame(message))


class SampleGrid(unittest.TestCase):
    """A rigid body every 2 steps and a sensor every 3 steps, up to step 12."""

    INTERVALS = {"rb": (7, 2), "sensor": (9, 3)}  # name -> (id, interval steps)
    END = 12

    def fake_scheduler(self, server):
        self.assertEqual(dc.encode_varint(len(hello := server.receive_frame())) + hello, golden_frames()["hello"])
        welcome = protocol_pb2.ServerMessage()
        welcome.welcome.protocol_version = 1
        server.send(welcome)
        self.assertEqual(server.receive().WhichOneof("message"), "declare")
        compiled = protocol_pb2.ServerMessage()
        compiled.compiled.time_step = 1e-3
        for name, (cid, interval) in self.INTERVALS.items():
            compiled.compiled.components.add(name=name, id=cid, interval_steps=interval, remote=True)
            compiled.compiled.initial_outputs.add(component_id=cid, step=0)
        compiled.compiled.components.add(name="steel", id=8, interval_steps=0, remote=True)
        server.send(compiled)
        next_due = {name: 0 for name in self.INTERVALS}
        step = 0
        while step < self.END:
            due = {name for name, s in next_due.items() if s == step}
            while due:
                data = server.receive().data
                name = {cid: n for n, (cid, _) in self.INTERVALS.items()}[data.component_id]
                self.received.append((data.step, name, data.WhichOneof("input")))
                self.assertIn(name, due)
                self.assertEqual(data.step, step)
                due.remove(name)
                next_due[name] = step + self.INTERVALS[name][1]
            step = min(next_due.values())
            for name, s in next_due.items():
                if s == step:
                    out = protocol_pb2.ServerMessage()
                    out.data.component_id = self.INTERVALS[name][0]
                    out.data.step = step
                    out.data.region_sensor.count = step
                    server.send(out)
        self.assertEqual(server.receive().WhichOneof("message"), "bye")
        finished = protocol_pb2.ServerMessage()
        finished.finished.step = step
        finished.finished.reason = "all clients said Bye"
        server.send(finished)

    def test_each_component_sends_at_its_own_steps_and_is_answered_at_the_end_of_its_interval(self):
        self.received = []
        server = FakeServer(self.fake_scheduler)
        answered = []
        with dc.Client("127.0.0.1", server.port, timeout=TIMEOUT_S) as client:
            client.hello("golden-client", access_token="secret")
            client.declare(scene_pb2.ComponentDeclaration(name="steel", material=scene_pb2.Material()))
            client.wait_compiled()
            self.assertEqual(sorted(client.initial_outputs()), ["rb", "sensor"])
            while client.step < self.END:
                inputs = {}
                if "rb" in client.due():
                    inputs["rb"] = client.rigid_body_input(position=(0.0, 0.0, client.time))
                outputs = client.exchange(inputs)
                answered.append((client.step, sorted(outputs)))
                for package in outputs.values():
                    self.assertEqual(package.step, client.step)
            finished = client.bye("test done")
        server.join()
        self.assertEqual(finished.step, self.END)
        self.assertEqual(answered, [(2, ["rb"]), (3, ["sensor"]), (4, ["rb"]), (6, ["rb", "sensor"]),
                                    (8, ["rb"]), (9, ["sensor"]), (10, ["rb"]), (12, ["rb", "sensor"])])
        sent = sorted(self.received)
        self.assertEqual([(s, n) for s, n, _ in sent],
                         [(0, "rb"), (0, "sensor"), (2, "rb"), (3, "sensor"), (4, "rb"), (6, "rb"),
                          (6, "sensor"), (8, "rb"), (9, "sensor"), (10, "rb")])
        self.assertTrue(all(kind == ("rigid_body_input" if n == "rb" else None) for _, n, kind in sent))


class DeclarationsDone(unittest.TestCase):
    def test_declarations_done_follows_the_declares_as_an_empty_field_5(self):
        received = []

        def script(server):
            for _ in range(2):
                received.append(server.receive_frame())

        fake = FakeServer(script)
        with dc.Client("127.0.0.1", fake.port, timeout=TIMEOUT_S) as client:
            client.declare(scene_pb2.ComponentDeclaration(name="steel", material=scene_pb2.Material()))
            client.declarations_done()
            fake.join()
        self.assertEqual(protocol_pb2.ClientMessage.FromString(received[0]).WhichOneof("message"), "declare")
        self.assertEqual(received[1].hex(), "2a00")  # field 5, length-delimited, empty
        self.assertEqual(protocol_pb2.ClientMessage.FromString(received[1]).WhichOneof("message"),
                         "declarations_done")


class ServerErrors(unittest.TestCase):
    def test_an_error_answer_is_raised_with_its_code_and_field(self):
        def refuse(server):
            server.receive()
            error = protocol_pb2.ServerMessage()
            error.error.code = protocol_pb2.Error.PROTOCOL_VERSION
            error.error.message = "protocol version 1 expected"
            error.error.field = "hello.protocol_version"
            error.error.fatal = True
            server.send(error)

        server = FakeServer(refuse)
        with dc.Client("127.0.0.1", server.port, timeout=TIMEOUT_S) as client:
            with self.assertRaises(dc.ServerError) as caught:
                client.hello("x")
        server.join()
        self.assertEqual(caught.exception.code, "PROTOCOL_VERSION")
        self.assertTrue(caught.exception.fatal)
        self.assertIn("hello.protocol_version", str(caught.exception))

    def test_a_silent_server_raises_timeout_instead_of_hanging(self):
        done = threading.Event()
        server = FakeServer(lambda s: (s.receive(), done.wait(TIMEOUT_S)))
        with dc.Client("127.0.0.1", server.port, timeout=0.2) as client:
            with self.assertRaises(TimeoutError):
                client.hello("x")
        done.set()
        server.join()


if __name__ == "__main__":
    unittest.main()
