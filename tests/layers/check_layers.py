#!/usr/bin/env python3
"""Fails when a project include points against the layers.

The layers, each allowed to include only itself and what it lists (core includes no
server, client or protocol header at all):

    apps -> cosim -> backend -> run -> scene -> core
    net  -> core's top-level headers and core/parallel only (never the engine's folders)
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
        return None
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
        if folder == "net" and len(pieces) > 3 and pieces[2] != "parallel":
            return "net uses core's top-level headers and core/parallel only"
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
