#!/usr/bin/env python3
"""Checks that a Markdown page shows each given source file verbatim in a fenced block.

Why: docs/tutorial.md shows complete client programs that tests build and run
(docs/tutorial/*); this keeps the page and the tested files from drifting apart.
Usage: check_doc_code.py PAGE.md FILE... ; exit 0 when every file's text (without its
trailing newlines) is the body of one fenced code block of the page, 1 otherwise.
"""
import re
import sys


def fenced_blocks(markdown):
    return [m.group(1) for m in re.finditer(r"^```[A-Za-z0-9_+-]*\n(.*?)\n```$", markdown, re.S | re.M)]


def main():
    if len(sys.argv) < 3:
        print(__doc__, file=sys.stderr)
        return 2
    with open(sys.argv[1]) as f:
        blocks = fenced_blocks(f.read())
    missing = []
    for path in sys.argv[2:]:
        with open(path) as f:
            text = f.read().rstrip("\n")
        if text not in blocks:
            missing.append(path)
    for path in missing:
        print(f"check_doc_code: {sys.argv[1]} has no code block equal to {path}; copy the file into the page",
              file=sys.stderr)
    if not missing:
        print(f"check_doc_code: {len(sys.argv) - 2} files shown verbatim in {sys.argv[1]}")
    return 1 if missing else 0


if __name__ == "__main__":
    sys.exit(main())
