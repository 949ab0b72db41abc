#!/usr/bin/env python3
"""Fails when the scene reference (docs/reference/) misses a field of the scene schema.

The schema is read from proto/demlink/v1/*.proto: every message with its fields (nested
messages included), then every message reachable from `Scene`. Each kind of
`ComponentDeclaration` has its page docs/reference/<kind>.md, in the fixed form of
sections Syntax, Example, Description, Restrictions, Defaults; the page must name (in
backticks) every field of every message reachable from its kind's message. Messages
several kinds share (geometry.proto, and any message reachable from two kinds) are named
on the page that uses them or on docs/reference/README.md; ComponentDeclaration's own
fields on README.md. An offence is printed as "page: `field` of Message missing" and the
script exits 1.

Usage: check_reference.py <repository root>
"""
import pathlib
import re
import sys

SECTIONS = ("Syntax", "Example", "Description", "Restrictions", "Defaults")
SCALARS = {
    "double", "float", "int32", "int64", "uint32", "uint64", "sint32", "sint64", "fixed32", "fixed64",
    "sfixed32", "sfixed64", "bool", "string", "bytes",
}
FIELD = re.compile(
    r"^\s*(?:optional\s+|repeated\s+)?(?:map<[^>]+>|[A-Za-z_][\w.]*)\s+([a-z_][a-z0-9_]*)\s*=\s*\d+\s*[;\[]")
TYPE = re.compile(r"^\s*(?:optional\s+|repeated\s+)?([A-Za-z_][\w.]*)\s+[a-z_][a-z0-9_]*\s*=")


def strip_comments(text: str) -> str:
    text = re.sub(r"/\*.*?\*/", "", text, flags=re.DOTALL)
    return re.sub(r"//[^\n]*", "", text)


def parse(proto_dir: pathlib.Path) -> dict[str, list[tuple[str, str]]]:
    """Message name (nested: Outer.Inner) -> [(field, type name as written)]."""
    messages: dict[str, list[tuple[str, str]]] = {}
    for path in sorted(proto_dir.glob("*.proto")):
        stack: list[tuple[str, str]] = []  # (kind, name): "message", "enum", "oneof", "other"
        for line in strip_comments(path.read_text(encoding="utf-8")).splitlines():
            opened = re.match(r"^\s*(message|enum|oneof|service)\s+(\w+)\s*\{", line)
            if opened:
                kind, name = opened.groups()
                if kind == "message":
                    outer = [n for k, n in stack if k == "message"]
                    full = ".".join(outer + [name])
                    messages.setdefault(full, [])
                stack.append((kind, name))
            elif stack and stack[-1][0] in ("message", "oneof"):
                field = FIELD.match(line)
                if field:
                    owner = ".".join(n for k, n in stack if k == "message")
                    type_name = TYPE.match(line).group(1)
                    messages[owner].append((field.group(1), type_name))
            for _ in range(line.count("}")):
                if stack:
                    stack.pop()
    return messages


def resolve(type_name: str, scope: str, messages: dict) -> str | None:
    """The message a field type names, looked up from the innermost scope outwards."""
    if type_name in SCALARS:
        return None
    name = type_name.removeprefix("demlink.v1.")
    parts = scope.split(".")
    for depth in range(len(parts), -1, -1):
        candidate = ".".join(parts[:depth] + [name])
        if candidate in messages:
            return candidate
    return None  # an enum


def reachable(root: str, messages: dict) -> list[str]:
    seen = [root]
    for message in seen:
        for _, type_name in messages[message]:
            target = resolve(type_name, message, messages)
            if target and target not in seen:
                seen.append(target)
    return seen


def named(page_text: str) -> set[str]:
    """Every `word` in backticks, and each dotted part of it."""
    words = set()
    prose = re.sub(r"^```.*?^```", "", page_text, flags=re.DOTALL | re.MULTILINE)  # fenced examples
    for quoted in re.findall(r"`([^`\n]+)`", prose):
        for word in re.findall(r"[A-Za-z_][A-Za-z0-9_]*", quoted):
            words.add(word)
    return words


def main() -> int:
    root = pathlib.Path(sys.argv[1]).resolve()
    messages = parse(root / "proto" / "demlink" / "v1")
    reference = root / "docs" / "reference"
    offences = []
    if "Scene" not in messages or "ComponentDeclaration" not in messages:
        print("no Scene / ComponentDeclaration in proto/demlink/v1: wrong root?")
        return 1
    kinds = [(field, resolve(t, "ComponentDeclaration", messages))
             for field, t in messages["ComponentDeclaration"]]
    kinds = [(field, message) for field, message in kinds if message]
    index = reference / "README.md"
    index_words = named(index.read_text(encoding="utf-8")) if index.exists() else set()
    if not index.exists():
        offences.append("docs/reference/README.md: missing")
    for field, _ in messages["ComponentDeclaration"]:
        if resolve(dict(messages["ComponentDeclaration"])[field], "ComponentDeclaration", messages) is None \
                and field not in index_words:
            offences.append(f"docs/reference/README.md: `{field}` of ComponentDeclaration missing")
    # Messages reachable from more than one kind may be named on README.md instead.
    owners: dict[str, set[str]] = {}
    for kind, message in kinds:
        for reached in reachable(message, messages):
            owners.setdefault(reached, set()).add(kind)
    fields_checked = 0
    for kind, message in kinds:
        page = reference / f"{kind}.md"
        if kind not in index_words:
            offences.append(f"docs/reference/README.md: the kind `{kind}` is not listed")
        if not page.exists():
            offences.append(f"docs/reference/{kind}.md: missing (the page of ComponentDeclaration.{kind})")
            continue
        text = page.read_text(encoding="utf-8")
        headings = re.findall(r"^## (\w+)", text, flags=re.MULTILINE)
        if tuple(headings[:len(SECTIONS)]) != SECTIONS:
            offences.append(f"docs/reference/{kind}.md: sections {headings} (the form is {', '.join(SECTIONS)})")
        words = named(text)
        for reached in reachable(message, messages):
            shared = len(owners[reached]) > 1
            for field, _ in messages[reached]:
                fields_checked += 1
                if field in words or (shared and field in index_words):
                    continue
                offences.append(f"docs/reference/{kind}.md: `{field}` of {reached} missing")
    for line in offences:
        print(line)
    print(f"{len(kinds)} component kinds, {fields_checked} fields checked, {len(offences)} missing")
    return 1 if offences else 0


if __name__ == "__main__":
    sys.exit(main())
