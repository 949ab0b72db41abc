#!/usr/bin/env python3
"""Runs the shell commands that README.md and docs/tutorial.md show, against a build.

Why: a newcomer types these commands in this order; a renamed option, a moved file or an
output the demo does not write should fail a test, not the newcomer.

Commands are the lines of ```sh blocks and of indented (4-space) blocks, continuation
lines joined, trailing "# ..." comments dropped. Every command must match one RULE below,
which says how it is run; a command no rule knows fails the test (add a rule with it).
What the rules change, honestly:
- scripts/demo.sh runs as scripts/demo_cosim.sh OUT 1 --view 0: the build is the one ctest
  runs on (demo.sh would install and build first), and one dig-dump cycle instead of two
  (about half the time). The commands that read the demo's outputs read this run's. The
  view costs the demo nothing while no page is open; while the demo runs, its server's
  live view must serve the page and greet a WebSocket (docs/view.md).
- demlink-run gets --end-time 0.02 (the scene is the same, the run shorter) and writes
  below the scratch folder instead of out/.
- demlink-server gets --port 0 and --listen 127.0.0.1 (tests never listen elsewhere); it
  must start listening and stop with exit 0 on SIGINT.
- the C compile line builds tests/client/modelica_sequence.c in place of my_model.c.
- scripts/build.sh, scripts/run_tests.sh and `git clone` are not re-run (ctest runs on
  the build they make; git clone names a placeholder URL); the client examples are run
  by the ctest cases named in their rule.
Usage: check_doc_commands.py REPO BUILD_DIR SCRATCH [--no-demo]
"""
import base64
import os
import re
import shlex
import shutil
import signal
import socket
import subprocess
import sys
import time
import urllib.request

PAGES = ["README.md", "docs/tutorial.md"]


def commands_of(text):
    """Shell command lines of ```sh/```bash blocks and indented blocks, in page order."""
    found = []
    lines = text.split("\n")
    fenced, language, previous_blank = False, "", True
    block = []
    for line in lines + [""]:
        if line.startswith("```"):
            if fenced and language in ("sh", "bash", "shell", "console"):
                found.extend(block)
            fenced, language, block = (not fenced), line[3:].strip(), []
            previous_blank = False
            continue
        if fenced:
            block.append(line)
        elif line.startswith("    ") and (previous_blank or block):
            block.append(line[4:])
        else:
            if block and not fenced:
                found.extend(block)
            block = []
        previous_blank = line.strip() == "" and not fenced
    joined, pending = [], ""
    for line in found:
        if line.rstrip().endswith("\\"):
            pending += line.rstrip()[:-1] + " "
            continue
        command = re.sub(r"\s+#\s.*$", "", pending + line).strip()
        pending = ""
        if command and not command.startswith("#"):
            joined.append(re.sub(r"\s+", " ", command))
    return joined


class Runner:
    def __init__(self, repo, build, scratch, demo):
        self.repo, self.build, self.scratch, self.demo = repo, build, scratch, demo
        self.demo_dir = os.path.join(scratch, "demo")
        self.demo_ran = False

    def shell(self, command, timeout=600):
        print(f"  $ {command}", flush=True)
        result = subprocess.run(["bash", "-c", command], cwd=self.repo, timeout=timeout,
                                stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
        if result.returncode != 0:
            raise RuntimeError(f"exit {result.returncode}:\n{result.stdout[-3000:]}")
        return result.stdout

    def needs_demo(self):
        if not self.demo:
            raise SkipDemo()
        if not self.demo_ran:
            run_demo_with_view(self.repo, [self.demo_dir, "1"], timeout=1500)
            self.demo_ran = True

    def in_demo(self, command):
        """The command with the demo's default folder (or bare demo file names) moved to this run's."""
        self.needs_demo()
        command = command.replace("out/cosim_demo", self.demo_dir)
        command = re.sub(r"(?<![/\w])excavator\.csv", f"{self.demo_dir}/excavator/excavator.csv", command)
        command = re.sub(r"(?<![/\w])truck\.csv", f"{self.demo_dir}/truck/truck.csv", command)
        command = re.sub(r"--output-dir plots", f"--output-dir {self.scratch}/plots", command)
        return command

    def server(self, command):
        command = re.sub(r"--port \d+", "--port 0", command).replace("--listen 0.0.0.0", "--listen 127.0.0.1")
        command = command.replace("--once &", "--once").rstrip("& ")
        if "--port 0" not in command:
            command += " --port 0"
        print(f"  $ {command}  (stopped with SIGINT once listening)", flush=True)
        process = subprocess.Popen(shlex.split(command), cwd=self.repo, stdout=subprocess.PIPE,
                                   stderr=subprocess.STDOUT, text=True)
        line = process.stdout.readline()
        if "listening on" not in line:
            process.kill()
            raise RuntimeError(f"server did not listen: {line}{process.stdout.read()[-2000:]}")
        process.send_signal(signal.SIGINT)
        code = process.wait(timeout=60)
        if code != 0:
            raise RuntimeError(f"server exited {code} on SIGINT")

    def headless(self, command):
        command = re.sub(r"--output out/", f"--output {self.scratch}/", command) + " --end-time 0.02"
        self.shell(command)


class SkipDemo(Exception):
    pass


def check_view(url):
    """The live view at `url` serves its page and greets a WebSocket with its hello."""
    with urllib.request.urlopen(url, timeout=10) as page:
        body = page.read().decode()
        if page.status != 200 or '<script type="module" src="view.js">' not in body:
            raise RuntimeError(f"the demo's view at {url} did not serve the page: {page.status}\n{body[:500]}")
    host, port = re.match(r"http://([^:/]+):(\d+)/", url).groups()
    with socket.create_connection((host, int(port)), timeout=10) as ws:
        key = base64.b64encode(os.urandom(16)).decode()
        ws.sendall((f"GET /ws HTTP/1.1\r\nHost: {host}\r\nUpgrade: websocket\r\nConnection: Upgrade\r\n"
                    f"Sec-WebSocket-Key: {key}\r\nSec-WebSocket-Version: 13\r\n\r\n").encode())
        received = b""
        while b'"kind":"hello","live":true' not in received and len(received) < 1 << 22:
            chunk = ws.recv(65536)
            if not chunk:
                break
            received += chunk
    if b"101 Switching Protocols" not in received or b'"kind":"hello","live":true' not in received:
        raise RuntimeError(f"the demo's view at {url} did not greet a WebSocket: {received[:300]!r}")
    print(f"  the demo's live view at {url} serves its page and greets a WebSocket", flush=True)


def run_demo_with_view(repo, arguments, timeout):
    """scripts/demo_cosim.sh ARGUMENTS --view 0; checks the view while the demo runs."""
    out = arguments[0]
    command = ["scripts/demo_cosim.sh", *arguments, "--view", "0"]
    print(f"  $ {shlex.join(command)}", flush=True)
    demo = subprocess.Popen(command, cwd=repo, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True,
                            start_new_session=True)
    try:
        log = os.path.join(repo, out, "server.log")
        url = None
        deadline = time.monotonic() + 120
        while url is None and time.monotonic() < deadline and demo.poll() is None:
            if os.path.exists(log):
                found = re.search(r"view at (http://\S+/)", open(log, errors="replace").read())
                url = found.group(1) if found else None
            time.sleep(0.2)
        if url is None:
            raise RuntimeError("the demo's server announced no view within 120 s")
        check_view(url)
        output, _ = demo.communicate(timeout=timeout)
    except BaseException:
        os.killpg(demo.pid, signal.SIGTERM)
        demo.wait()
        raise
    if demo.returncode != 0:
        raise RuntimeError(f"exit {demo.returncode}:\n{output[-3000:]}")
    return output


def skip(reason):
    return lambda runner, command: print(f"  not run: {reason}")


RULES = [
    (r"^git clone <url> demlink && cd demlink$", skip("placeholder URL; this test runs inside the clone")),
    (r"^scripts/install_deps\.sh$", lambda r, c: r.shell(c)),
    (r"^scripts/build\.sh$", skip("ctest runs on the build it makes")),
    (r"^cmake --preset release -G Ninja && cmake --build --preset release --target demlink_c$",
     skip("ctest runs on the build it makes")),
    (r"^cmake --install build/release --prefix /opt/demlink --component c_abi$",
     skip("ctest install.client_consumers installs into a temporary prefix and uses the tree")),
    (r"^scripts/run_tests\.sh$", skip("it is what runs this test")),
    (r"^scripts/demo\.sh( \[OUT_DIR\] \[CYCLES\])?$", lambda r, c: r.needs_demo()),
    (r"^\.?/?build/release/server/demlink-run \S+\.json --output out/\S+$", lambda r, c: r.headless(c)),
    (r"^\.?/?build/release/server/demlink-server( .*)?$", lambda r, c: r.server(c)),
    (r"^build/release/tests/tutorial/weigh_grains ", skip("ctest tutorial_weigh_grains_cpp runs it")),
    (r"^export PYTHONPATH=build/release/client/python/generated:client/python$",
     skip("ctest tutorial_weigh_grains_py sets it")),
    (r"^/usr/bin/python3 docs/tutorial/weigh_grains\.py ", skip("ctest tutorial_weigh_grains_py runs it")),
    (r"^cc -std=c99 my_model\.c ", lambda r, c: r.shell(
        c.replace("my_model.c", "tests/client/modelica_sequence.c").replace("-o my_model", f"-o {r.scratch}/my_model"))),
    (r"^/usr/bin/python3 scripts/plot_cosim\.py ", lambda r, c: r.shell(r.in_demo(c))),
    (r"^/usr/bin/python3 scripts/cosim_summary\.py ", lambda r, c: r.shell(r.in_demo(c))),
]


def main():
    args = [a for a in sys.argv[1:] if a != "--no-demo"]
    if len(args) != 3:
        print(__doc__, file=sys.stderr)
        return 2
    repo, build, scratch = (os.path.abspath(a) for a in args)
    shutil.rmtree(scratch, ignore_errors=True)
    os.makedirs(scratch)
    runner = Runner(repo, build, scratch, demo="--no-demo" not in sys.argv)
    failures, count = [], 0
    for page in PAGES:
        with open(os.path.join(repo, page)) as f:
            commands = commands_of(f.read())
        for command in commands:
            count += 1
            print(f"{page}: {command}", flush=True)
            rule = next((action for pattern, action in RULES if re.search(pattern, command)), None)
            if rule is None:
                failures.append(f"{page}: no rule for `{command}` (add one to tests/docs/check_doc_commands.py)")
                continue
            try:
                rule(runner, command)
            except SkipDemo:
                print("  not run: --no-demo")
            except (RuntimeError, subprocess.TimeoutExpired) as error:
                failures.append(f"{page}: `{command}` failed: {error}")
    for failure in failures:
        print(f"FAIL: {failure}", file=sys.stderr)
    print(f"check_doc_commands: {count} commands, {len(failures)} failed")
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
