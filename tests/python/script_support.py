"""What the Python client scripts in this folder share: the imports of the client and
the generated classes, the command line, the collected checks and the exit code."""

import argparse
import importlib
import os
import sys

HERE = os.path.dirname(os.path.abspath(__file__))


class Checks:
    def __init__(self):
        self.failures = []

    def expect(self, condition, what):
        if not condition:
            self.failures.append(what)
            if len(self.failures) <= 20:
                print(f"FAIL: {what}", file=sys.stderr)
        return condition


def import_client(generated, modules):
    """demlink_client and {name: demlink.v1.<name>_pb2}; None (the reason printed) when the
    client or the generated classes cannot be imported."""
    if generated:
        sys.path.insert(0, generated)
    sys.path.insert(0, os.path.join(HERE, "..", "..", "client", "python"))
    try:
        client = importlib.import_module("demlink_client")
        return client, {name: importlib.import_module(f"demlink.v1.{name}_pb2") for name in modules}
    except ImportError as e:
        print(f"cannot import the client or the generated classes ({e}); set PYTHONPATH or --generated",
              file=sys.stderr)
        return None


def client_arguments(description):
    """The options every script takes: the server's address and token, the answer timeout
    and where the generated classes are."""
    parser = argparse.ArgumentParser(description=description)
    parser.add_argument("--host", default="127.0.0.1")
    parser.add_argument("--port", type=int, required=True)
    parser.add_argument("--token", default="", help="access token, if the server requires one")
    parser.add_argument("--timeout", type=float, default=30.0, help="longest wait for one answer [s]")
    parser.add_argument("--generated", help="directory holding demlink/v1/*_pb2.py")
    return parser


def finish(name, checks, passed):
    """The exit code: 0 when every check passed (`passed` printed), else 1."""
    if checks.failures:
        print(f"{name}: {len(checks.failures)} check(s) FAILED", file=sys.stderr)
        return 1
    print(f"{name}: all checks passed{passed}")
    return 0


def run_guarded(name, run, args):
    """run(args), with a refused declaration, a timeout or a closed connection reported as
    a failure (exit 1) rather than a traceback."""
    try:
        return run(args)
    except Exception as e:
        print(f"{name}: FAILED: {type(e).__name__}: {e}", file=sys.stderr)
        return 1
