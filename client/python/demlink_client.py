"""A small DEMLink co-simulation client in Python (docs/protocol.md).

Why this module exists: the protocol is meant to be usable from any language that has a
protobuf library, without reading the server's code. This client is the proof: it uses
only the classes protoc generates from proto/demlink/v1/*.proto (Debian's protoc and
python3-protobuf) plus the rules written in docs/protocol.md, and its own ten-line varint
code for the frame length (the protobuf "delimited" convention).

Usage (the generated package `demlink.v1` must be importable, e.g.
PYTHONPATH=<build>/client/python/generated, which the target demlink_python_proto fills):

    with Client("127.0.0.1", port) as c:
        c.hello("my-model")
        for decl in declarations:
            c.declare(decl)
        compiled = c.wait_compiled()
        while c.step < last_step:
            outputs = c.exchange({"bucket": c.rigid_body_input(position=(0, 0, 1))})
        finished = c.bye("done")

Time is kept as the integer step count the wire uses; `time` is step * time_step [s].
"""

import math
import socket
import time

from demlink.v1 import geometry_pb2, protocol_pb2

#: Default largest frame payload either side accepts [bytes] (64 MiB, as the server).
DEFAULT_MAX_FRAME_BYTES = 64 << 20
#: The protocol version this client speaks.
PROTOCOL_VERSION = protocol_pb2.PROTOCOL_VERSION_CURRENT


# --- Framing ------------------------------------------------------------------------


def encode_varint(value):
    """Base-128 varint of a non-negative integer (least significant group first)."""
    if value < 0:
        raise ValueError(f"varint of negative value {value}")
    out = bytearray()
    while value >= 0x80:
        out.append((value & 0x7F) | 0x80)
        value >>= 7
    out.append(value)
    return bytes(out)


def encode_frame(message):
    """One frame: the varint length of the serialised message, then the message."""
    payload = message.SerializeToString()
    return encode_varint(len(payload)) + payload


class FrameError(Exception):
    """The byte stream is not a sequence of valid frames (bad prefix, over the cap)."""


class FrameDecoder:
    """Splits a byte stream that arrives in arbitrary pieces into frame payloads.

    The length prefix is checked before any payload is buffered: more than 10 prefix
    bytes, or a length above the cap, raises FrameError.
    """

    def __init__(self, max_frame_bytes=DEFAULT_MAX_FRAME_BYTES):
        self._buffer = bytearray()
        self.max_frame_bytes = max_frame_bytes

    def feed(self, data):
        self._buffer.extend(data)

    def pending_bytes(self):
        return len(self._buffer)

    def next(self):
        """The next complete payload (bytes), or None when more bytes are needed."""
        length = 0
        for pos, byte in enumerate(self._buffer):
            if pos >= 10:
                raise FrameError("malformed varint length prefix (more than 10 bytes)")
            length |= (byte & 0x7F) << (7 * pos)
            if byte & 0x80 == 0:
                break
        else:
            if len(self._buffer) >= 10:
                raise FrameError("malformed varint length prefix (more than 10 bytes)")
            return None  # prefix incomplete
        if length > self.max_frame_bytes:
            raise FrameError(f"frame of {length} bytes exceeds the cap of {self.max_frame_bytes} bytes")
        start = pos + 1
        if len(self._buffer) - start < length:
            return None  # payload incomplete
        payload = bytes(self._buffer[start:start + length])
        del self._buffer[:start + length]
        return payload


# --- Errors -------------------------------------------------------------------------


class ServerError(Exception):
    """The server sent Error{code, message, component, field, fatal}."""

    def __init__(self, error):
        self.error = error
        self.code = protocol_pb2.Error.Code.Name(error.code)
        self.fatal = error.fatal
        where = ""
        if error.component:
            where += f" component '{error.component}'"
        if error.field:
            where += f" field '{error.field}'"
        kind = "fatal" if error.fatal else "non-fatal"
        super().__init__(f"server error {self.code} ({kind}){where}: {error.message}")


class SimulationEnded(Exception):
    """The server sent Finished while the client still expected outputs."""

    def __init__(self, finished):
        self.finished = finished
        super().__init__(f"simulation ended at step {finished.step} (t = {finished.time} s): {finished.reason}")


# --- Client -------------------------------------------------------------------------


def vec3(xyz):
    """A demlink.v1.Vector3 from a 3-sequence [unit of the field]."""
    return geometry_pb2.Vector3(x=float(xyz[0]), y=float(xyz[1]), z=float(xyz[2]))


def quat(wxyz):
    """A demlink.v1.Quaternion from (w, x, y, z)."""
    return geometry_pb2.Quaternion(w=float(wxyz[0]), x=float(wxyz[1]), y=float(wxyz[2]), z=float(wxyz[3]))


# DataPackage input field for each input message type.
_INPUT_FIELD = {
    protocol_pb2.RigidBodyInput: "rigid_body_input",
    protocol_pb2.SimulationBoxInput: "simulation_box_input",
}


class Client:
    """One TCP connection to a DEMLink server, carrying one or more components.

    Every blocking call waits at most `timeout` seconds and raises TimeoutError then.
    """

    def __init__(self, host, port, timeout=30.0, max_frame_bytes=DEFAULT_MAX_FRAME_BYTES):
        self.timeout = timeout
        self._socket = socket.create_connection((host, port), timeout=timeout)
        self._socket.setsockopt(socket.IPPROTO_TCP, socket.TCP_NODELAY, 1)
        self._decoder = FrameDecoder(max_frame_bytes)
        self.welcome = None
        self.compiled = None
        self.step = 0              # the step the client is at on the sample grid [-]
        self.time_step = 0.0       # [s], from Compiled
        self._components = {}      # name -> CompiledComponent (this connection's)
        self._names = {}           # component id -> name
        self._next_due = {}        # name -> next step the component sends inputs at [-]
        self._waiting = {}         # name -> step its outputs are expected for [-]

    # Context manager: always close the socket.
    def __enter__(self):
        return self

    def __exit__(self, *exc):
        self.close()

    def close(self):
        if self._socket is not None:
            self._socket.close()
            self._socket = None

    @property
    def time(self):
        """Simulated time of the client's current step [s]."""
        return self.step * self.time_step

    # --- Raw messages ---

    def send(self, client_message):
        self._socket.sendall(encode_frame(client_message))

    def receive(self, timeout=None):
        """The next ServerMessage; an Error message is raised as ServerError."""
        message = self._receive_raw(self.timeout if timeout is None else timeout)
        if message.WhichOneof("message") == "error":
            raise ServerError(message.error)
        return message

    def _receive_raw(self, timeout):
        deadline = time.monotonic() + timeout
        while True:
            payload = self._decoder.next()
            if payload is not None:
                message = protocol_pb2.ServerMessage()
                message.ParseFromString(payload)
                return message
            remaining = deadline - time.monotonic()
            if remaining <= 0:
                raise TimeoutError(f"no complete message from the server within {timeout} s")
            self._socket.settimeout(remaining)
            try:
                data = self._socket.recv(65536)
            except socket.timeout:
                raise TimeoutError(f"no complete message from the server within {timeout} s") from None
            if not data:
                raise ConnectionError(
                    f"server closed the connection ({self._decoder.pending_bytes()} bytes of a frame pending)")
            self._decoder.feed(data)

    def _expect(self, kind, timeout=None):
        message = self.receive(timeout)
        got = message.WhichOneof("message")
        if got == "finished" and kind != "finished":
            raise SimulationEnded(message.finished)
        if got != kind:
            raise RuntimeError(f"expected {kind}, server sent {got}")
        return getattr(message, kind)

    # --- The sequence ---

    def hello(self, client_name, access_token="", simulation=""):
        """Hello -> Welcome. `simulation` names the simulation to join (docs/protocol.md)."""
        msg = protocol_pb2.ClientMessage()
        msg.hello.protocol_version = PROTOCOL_VERSION
        msg.hello.client_name = client_name
        msg.hello.access_token = access_token
        msg.hello.simulation = simulation
        self.send(msg)
        self.welcome = self._expect("welcome")
        return self.welcome

    def declare(self, declaration):
        """Declare one component (a demlink.v1.ComponentDeclaration). No answer is sent.

        Settings are the declaration's fields, e.g. for the box
        `decl.simulation_box.restitution_tolerance = 0.05` (unset: 0.01, restitution
        within 1 % at the accepted time step; larger accepts a larger step, trading
        accuracy for speed; docs/physics.md "Critical time step")."""
        msg = protocol_pb2.ClientMessage()
        msg.declare.component.CopyFrom(declaration)
        self.send(msg)

    def declarations_done(self):
        """Tell the server this connection declares nothing more (DeclarationsDone): once every
        connection has, it compiles without an expected count or a quiet period."""
        msg = protocol_pb2.ClientMessage()
        msg.declarations_done.SetInParent()
        self.send(msg)

    def wait_compiled(self, timeout=None):
        """Waits for Compiled; sets up the sample grid of this connection's components."""
        self.compiled = self._expect("compiled", timeout)
        self.time_step = self.compiled.time_step
        self.step = self.compiled.start_step  # 0, or the step of a checkpoint the server restored
        for c in self.compiled.components:
            self._components[c.name] = c
            self._names[c.id] = c.name
            if c.interval_steps > 0:
                self._next_due[c.name] = self.step
        return self.compiled

    def component(self, name):
        """The CompiledComponent of one of this connection's components."""
        return self._components[name]

    def initial_outputs(self):
        """name -> DataPackage of the outputs at the start step (from Compiled)."""
        return {self._names[p.component_id]: p for p in self.compiled.initial_outputs}

    def due(self):
        """Names of this connection's components that send inputs at the current step."""
        return [name for name, step in self._next_due.items() if step == self.step]

    def exchange(self, inputs=None):
        """One sample: send the due components' inputs, receive the next outputs.

        `inputs` maps component names to RigidBodyInput / SimulationBoxInput messages;
        due components without inputs (sensors, views) send an empty DataPackage.
        Returns name -> DataPackage for every component whose interval ends at the
        connection's next sample step; afterwards `step` is that step.
        """
        inputs = dict(inputs or {})
        if not self._next_due:
            raise RuntimeError("no component of this connection is exchanged (all intervals are 0)")
        for name in self.due():
            package = protocol_pb2.ClientMessage()
            package.data.component_id = self._components[name].id
            package.data.step = self.step
            value = inputs.pop(name, None)
            if value is not None:
                getattr(package.data, _INPUT_FIELD[type(value)]).CopyFrom(value)
            self.send(package)
            self._next_due[name] = self.step + self._components[name].interval_steps
            self._waiting[name] = self._next_due[name]
        if inputs:
            raise ValueError(f"inputs for components not due at step {self.step}: {sorted(inputs)}")
        target = min(self._next_due.values())
        expected = {name for name, step in self._waiting.items() if step == target}
        outputs = {}
        while expected - outputs.keys():
            package = self._expect("data")
            name = self._names.get(package.component_id)
            if name is None:
                raise RuntimeError(f"DataPackage for unknown component id {package.component_id}")
            if package.step != self._waiting.get(name):
                raise RuntimeError(f"outputs of '{name}' for step {package.step}, "
                                   f"expected step {self._waiting.get(name)}")
            del self._waiting[name]
            outputs[name] = package
        self.step = target
        return outputs

    def bye(self, reason="", timeout=None):
        """Bye -> Finished (outputs still in flight are skipped)."""
        msg = protocol_pb2.ClientMessage()
        msg.bye.reason = reason
        self.send(msg)
        while True:
            message = self.receive(timeout)
            if message.WhichOneof("message") == "finished":
                return message.finished

    # --- Input helpers ---

    @staticmethod
    def rigid_body_input(position, orientation=(1.0, 0.0, 0.0, 0.0), linear_velocity=(0.0, 0.0, 0.0),
                         angular_velocity=(0.0, 0.0, 0.0)):
        """RigidBodyInput: reference point [m], quaternion (w, x, y, z), twist [m/s, rad/s]."""
        values = list(position) + list(orientation) + list(linear_velocity) + list(angular_velocity)
        if not all(math.isfinite(v) for v in values):
            raise ValueError(f"rigid body input is not finite: {values}")
        return protocol_pb2.RigidBodyInput(position=vec3(position), orientation=quat(orientation),
                                           linear_velocity=vec3(linear_velocity),
                                           angular_velocity=vec3(angular_velocity))
