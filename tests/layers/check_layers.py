#!/usr/bin/env python3
"""Fails when a project include points against the layers.

The layers, each allowed to include only itself and what it lists (core includes no
server, client or protocol header at all). Inside core, a folder includes only itself and
the folders before it in CORE_ORDER (the top-level files belong to "settings" or "world"):

    parallel base geometry state materials particles step walls contact deformable
    settings regions bonds output components world setup

    apps -> cosim -> backend -> run -> scene -> core
    net  -> core/base and core/parallel only (never the engine)
    view -> net's transport helpers (asio.hpp, same_token.hpp) and core; apps include it
    client -> core/parallel only
    cli  -> nothing of the server

Every "demlink/..." include of every source and header under core/, server/ and
client/ is checked, and every library of server/CMakeLists.txt must compile sources of
one folder only (a file compiled into another folder's library hides an edge). An
offence is printed as file:line: what (rule) and the script exits 1.

Usage: check_layers.py <repository root>
"""
import pathlib
import re
import sys

INCLUDE = re.compile(r'^\s*#\s*include\s+"(demlink/[^"]+)"', re.MULTILINE)

# server/ folders: what each may include besides itself and core.
SERVER_ALLOWED = {
    "scene": set(),
    "run": {"scene"},
    "backend": {"run", "scene"},
    "cosim": {"backend", "run", "scene", "net/session_handler.hpp"},
    "net": set(),
    "view": {"net/asio.hpp", "net/same_token.hpp"},
    "apps": {"cosim", "backend", "run", "scene", "net", "view", "cli"},
}


# core's layers, lowest first.
CORE_ORDER = ["parallel", "base", "geometry", "state", "materials", "particles", "step", "walls", "contact",
              "deformable", "settings", "regions", "bonds", "output", "components", "world", "setup"]
# core's top-level files and the layer each belongs to.
CORE_TOP = {"simulation_settings": "settings", "world_state": "settings", "world": "world",
            "world_checkpoint": "world", "checkpoint_file": "world"}


def core_layer_of_file(path: pathlib.Path, root: pathlib.Path) -> str | None:
    """The core layer a file under core/ belongs to."""
    parts = path.relative_to(root / "core").parts
    if parts[0] == "parallel":
        return "parallel"
    if parts[:3] == ("include", "demlink", "core"):
        parts = parts[3:]
    elif parts[0] == "src":
        parts = parts[1:]
    else:
        return None
    if len(parts) == 1:
        return CORE_TOP.get(pathlib.Path(parts[0]).name.split(".")[0])
    return parts[0] if parts[0] in CORE_ORDER else None


def core_layer_of_include(target: str) -> str | None:
    """The core layer of an include "demlink/core/..."."""
    pieces = target.split("/")
    if len(pieces) == 3:
        return CORE_TOP.get(pieces[2].split(".")[0])
    return pieces[2] if pieces[2] in CORE_ORDER else None


def core_offence(root: pathlib.Path, path: pathlib.Path, target: str) -> str | None:
    """Why a file of core may not include the core header `target`, or None when it may."""
    own = core_layer_of_file(path, root)
    other = core_layer_of_include(target)
    if own is None or other is None:
        return f"{path.relative_to(root)} or {target} is in no core layer (add it to CORE_ORDER or CORE_TOP)"
    if CORE_ORDER.index(other) > CORE_ORDER.index(own):
        return f"core/{own} may not include core/{other} (it is a higher layer)"
    return None


def server_folder(path: pathlib.Path, root: pathlib.Path) -> str | None:
    """The server layer a file belongs to (src/<folder>/... or include/demlink/server/<folder>/...)."""
    parts = path.relative_to(root / "server").parts
    if parts[0] == "src":
        return parts[1]
    if parts[:3] == ("include", "demlink", "server"):
        return parts[3]
    if parts[0] == "cli":
        return "cli"
    return None


def offence(root: pathlib.Path, path: pathlib.Path, target: str) -> str | None:
    """Why `path` may not include `target`, or None when it may."""
    relative = path.relative_to(root)
    pieces = target.split("/")
    area = pieces[1] if len(pieces) > 2 else ""
    if relative.parts[0] == "core":
        if relative.parts[1] == "parallel" and not target.startswith("demlink/core/parallel/"):
            return "core/parallel includes only itself"
        if area in ("server", "client", "v1", "wire", "cli"):
            return "core includes no server, client or protocol header"
        return core_offence(root, path, target) if area == "core" else None
    if relative.parts[0] == "client":
        if area == "core" and not target.startswith("demlink/core/parallel/"):
            return "the client reaches core only through core/parallel"
        if area == "server":
            return "the client includes no server header"
        return None
    folder = server_folder(path, root)
    if folder is None:
        return None
    if folder == "cli":
        return "cli includes nothing of the server" if area in ("server", "core") else None
    if area == "core":
        if folder == "net" and pieces[2] not in ("base", "parallel"):
            return "net uses core/base and core/parallel only"
        return None
    if area == "cli":
        return None if "cli" in SERVER_ALLOWED.get(folder, set()) else f"{folder} may not include cli"
    if area != "server":
        return None
    layer = pieces[2]
    if layer == folder:
        return None
    allowed = SERVER_ALLOWED.get(folder, set())
    if layer in allowed or "/".join(pieces[2:]) in allowed:
        return None
    return f"server/{folder} may not include server/{layer}"


LIBRARY = re.compile(r"add_library\((\w+)([^)]*)\)", re.DOTALL)


def mixed_libraries(root: pathlib.Path) -> list[str]:
    """Libraries of server/CMakeLists.txt whose sources come from more than one folder."""
    cmake = root / "server" / "CMakeLists.txt"
    text = re.sub(r"#[^\n]*", "", cmake.read_text(encoding="utf-8"))  # comments may hold parentheses
    found = []
    for match in LIBRARY.finditer(text):
        folders = sorted(set(re.findall(r"\bsrc/(\w+)/\w+\.cpp", match.group(2))))
        if len(folders) > 1:
            line = text.count("\n", 0, match.start()) + 1
            found.append(f"server/CMakeLists.txt:{line}: {match.group(1)} compiles src/{', src/'.join(folders)} "
                         "(one folder per library)")
    return found


def main() -> int:
    root = pathlib.Path(sys.argv[1]).resolve()
    offences = []
    checked = 0
    for top in ("core", "server", "client"):
        for path in sorted((root / top).rglob("*")):
            if path.suffix not in (".hpp", ".cpp", ".h", ".in") or not path.is_file():
                continue
            text = path.read_text(encoding="utf-8", errors="replace")
            for match in INCLUDE.finditer(text):
                checked += 1
                why = offence(root, path, match.group(1))
                if why:
                    line = text.count("\n", 0, match.start()) + 1
                    offences.append(f"{path.relative_to(root)}:{line}: {match.group(1)} ({why})")
    offences += mixed_libraries(root)
    if checked == 0:
        print(f"no includes found under {root}: wrong root?")
        return 1
    for line in offences:
        print(line)
    print(f"{checked} includes checked, {len(offences)} against the layers")
    return 1 if offences else 0


if __name__ == "__main__":
    sys.exit(main())
