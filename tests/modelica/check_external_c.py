#!/usr/bin/env python3
"""Checks every `external "C"` call of the Modelica package against the C prototypes.

Usage: check_external_c.py PACKAGE_DIR HEADER [HEADER...]

For each Modelica function with an external "C" clause: the C function must be declared
in one of the headers; the call must pass as many arguments as the prototype takes; and
each argument's Modelica type must map to the C parameter type as Modelica tools pass it
(Modelica Language Specification, section 12.9: Real -> double, Integer -> int,
String -> const char*, ExternalObject -> void*; input arrays -> const pointers, outputs
and output arrays -> pointers; size(a, 1) -> int). Declared array sizes must agree.
Exit 0 when all match; 1 with one line per mismatch.
"""
import pathlib
import re
import sys

# --- C side ---------------------------------------------------------------------------
PROTO = re.compile(r"(?:DL_API|static(?:\s+inline)?)\s+([\w\s\*]+?)\s*\b(\w+)\s*\(([^)]*)\)\s*[;{]", re.S)


def c_param(text):
    """(base, pointer depth, const, array size or None) of one C parameter."""
    text = " ".join(text.split())
    size = None
    m = re.search(r"\[(\d*)\]$", text)
    depth = 0
    if m:
        size = int(m.group(1)) if m.group(1) else None
        text = text[: m.start()].strip()
        depth += 1
    text = re.sub(r"\s+\w+$", "", text) if not text.endswith("*") else text
    depth += text.count("*")
    const = text.startswith("const ") or " const" in text.split("*")[0]
    base = text.replace("const", "").replace("*", "").strip()
    if base in ("dl_client", "dl_package"):
        base, depth = "void", depth  # void typedefs: dl_client* is void*
    return base, depth, const, size


def read_prototypes(headers):
    out = {}
    for header in headers:
        text = re.sub(r"/\*.*?\*/", "", pathlib.Path(header).read_text(), flags=re.S)
        for ret, name, params in PROTO.findall(text):
            params = params.strip()
            plist = [] if params in ("", "void") else [p.strip() for p in params.split(",")]
            out[name] = (" ".join(ret.split()), [c_param(p) for p in plist])
    return out


# --- Modelica side ----------------------------------------------------------------------
FUNCTION = re.compile(r"\bfunction\s+(\w+)\b(.*?)\bend\s+\1\s*;", re.S)
DECL = re.compile(r"^\s*(input|output)\s+([\w.]+)\s+(\w+)\s*(\[[^\]]*\])?", re.M)
EXTERNAL = re.compile(r'external\s+"C"\s*(?:(\w+)\s*=\s*)?(\w+)\s*\(', re.S)


def call_arguments(text, start):
    """The text between the '(' before `start` and its matching ')'."""
    depth = 1
    for i in range(start, len(text)):
        depth += text[i] == "("
        depth -= text[i] == ")"
        if depth == 0:
            return text[start:i]
    raise ValueError("unbalanced external call")


def split_args(text):
    args, depth, cur = [], 0, ""
    for ch in text:
        if ch == "," and depth == 0:
            args.append(cur.strip())
            cur = ""
            continue
        depth += ch == "("
        depth -= ch == ")"
        cur += ch
    if cur.strip():
        args.append(cur.strip())
    return args


def expected(kind, mtype, dims):
    """The C (base, pointer depth, const rule) a Modelica formal maps to; the const rule is
    "required" (input arrays and strings: the C side must not write them), "forbidden"
    (outputs: the C side writes them) or "any" (by value, or an ExternalObject)."""
    base = {"Real": "double", "Integer": "int", "Boolean": "int", "String": "char"}.get(mtype, "void")
    if base == "void":  # ExternalObject
        return "void", 1, "any"
    depth = (1 if dims or kind == "output" else 0) + (1 if base == "char" else 0)
    if kind == "output":
        return base, depth, "forbidden"
    return base, depth, "required" if depth > 0 else "any"


def main():
    package, headers = pathlib.Path(sys.argv[1]), sys.argv[2:]
    prototypes = read_prototypes(headers)
    problems, checked = [], 0
    for mo in sorted(package.rglob("*.mo")):
        text = re.sub(r"//[^\n]*", "", mo.read_text())
        for fname, body in FUNCTION.findall(text):
            ext = EXTERNAL.search(body)
            if not ext:
                continue
            checked += 1
            where = f"{mo.relative_to(package)}: {fname}"
            result, cname = ext.groups()
            argtext = call_arguments(body, ext.end())
            formals = {name: (kind, mtype, dims) for kind, mtype, name, dims in DECL.findall(body)}
            if cname not in prototypes:
                problems.append(f"{where}: {cname} is declared in no header")
                continue
            ret, params = prototypes[cname]
            if result:
                kind, mtype, dims = formals[result]
                want = {"Integer": "int", "Real": "double", "String": "const char*"}.get(mtype, "void*")
                got = ret.replace("dl_client*", "void*").replace(" *", "*")
                if got != want:
                    problems.append(f"{where}: returns {ret}, Modelica expects {want}")
            args = split_args(argtext)
            if len(args) != len(params):
                problems.append(f"{where}: {len(args)} arguments, {cname} takes {len(params)}")
                continue
            for i, (arg, (base, depth, const, size)) in enumerate(zip(args, params)):
                if arg.startswith("size("):
                    want = ("int", 0, "any")
                    dims = None
                elif arg in formals:
                    kind, mtype, dims = formals[arg]
                    want = expected(kind, mtype, dims)
                else:
                    problems.append(f"{where}: argument {i + 1} '{arg}' is no formal of the function")
                    continue
                if (base, depth) != want[:2] or (want[2] == "required" and not const) or (
                        want[2] == "forbidden" and const):
                    problems.append(f"{where}: argument {i + 1} '{arg}' maps to {want}, {cname} takes "
                                    f"{(base, depth, const)}")
                if size is not None and dims and dims.strip("[]").strip().isdigit() and int(dims.strip("[]")) != size:
                    problems.append(f"{where}: argument {i + 1} '{arg}' has {dims}, {cname} takes [{size}]")
    for p in problems:
        print(p)
    print(f"check_external_c: {checked} external functions, {len(problems)} mismatches")
    return 1 if problems or checked == 0 else 0


if __name__ == "__main__":
    sys.exit(main())
