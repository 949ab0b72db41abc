"""Reads the function prototypes of C headers without a C compiler.

A small declaration parser, enough for the headers of a C ABI: comments are removed, the
preprocessor lines are read for `#include "..."` (followed in the include directories) and
object-like `#define NAME ...` (a macro used as a qualifier, e.g. an export attribute, is
dropped from declarations); conditionals are not evaluated, so every branch is read.
Top-level declarations are split at `;` and at function bodies; typedefs of plain types
(`typedef void dl_client;`) are resolved. Each parameter becomes a CType: base type
words, pointer depth (an array parameter `double x[3]` is a pointer of known length 3)
and whether the pointed-to value is const.
"""
import dataclasses
import pathlib

QUALIFIERS = {"static", "inline", "extern", "__inline", "__inline__", "register", "volatile", "restrict",
              "__restrict", "__extension__"}


@dataclasses.dataclass(frozen=True)
class CType:
    base: str            # "double", "int", "char", "void", "unsigned long", ...
    depth: int = 0       # pointer depth
    const: bool = False  # the pointed-to value (or the value itself when depth == 0) is const
    length: int = None   # declared length of an array parameter `x[3]`

    def __str__(self):
        text = ("const " if self.const else "") + self.base + "*" * self.depth
        return text + (f" [{self.length}]" if self.length is not None else "")


@dataclasses.dataclass
class Prototype:
    name: str
    result: CType
    params: list         # [(parameter name or "", CType)]
    has_body: bool       # defined in the header (static inline), needs no library
    file: str
    line: int


class HeaderError(Exception):
    pass


def _strip_comments(text):
    """The text with comments replaced by blanks (newlines kept: line numbers stay right)."""
    out, i, n = [], 0, len(text)
    while i < n:
        c = text[i]
        if c in "\"'":
            j = i + 1
            while j < n and text[j] != c:
                j += 2 if text[j] == "\\" else 1
            out.append(text[i:j + 1])
            i = j + 1
        elif text.startswith("/*", i):
            j = text.find("*/", i + 2)
            if j < 0:
                raise HeaderError("unterminated comment")
            out.append("".join(ch if ch == "\n" else " " for ch in text[i:j + 2]))
            i = j + 2
        elif text.startswith("//", i):
            j = text.find("\n", i)
            i = n if j < 0 else j
        else:
            out.append(c)
            i += 1
    return "".join(out)


def _tokens(code):
    """(kind, text, line) tokens of C code: 'id', 'num', 'str', or the punctuation itself."""
    i, n, line = 0, len(code), 1
    while i < n:
        c = code[i]
        if c == "\n":
            line += 1
            i += 1
        elif c.isspace():
            i += 1
        elif c.isalpha() or c == "_":
            j = i
            while j < n and (code[j].isalnum() or code[j] == "_"):
                j += 1
            yield "id", code[i:j], line
            i = j
        elif c.isdigit():
            j = i
            while j < n and (code[j].isalnum() or code[j] in "._"):
                j += 1
            yield "num", code[i:j], line
            i = j
        elif c in "\"'":
            j = i + 1
            while j < n and code[j] != c:
                j += 2 if code[j] == "\\" else 1
            yield "str", code[i:j + 1], line
            line += code.count("\n", i, j + 1)
            i = j + 1
        else:
            yield c, c, line
            i += 1


class HeaderReader:
    """Prototypes and typedefs of headers, following `#include "..."` in include_dirs."""

    def __init__(self, include_dirs):
        self.include_dirs = [pathlib.Path(d) for d in include_dirs]
        self.prototypes = {}
        self.typedefs = {}
        self.macros = set()
        self._visible = {}  # header path -> names of the functions declared through it

    def find(self, name, relative_to=None):
        candidates = ([relative_to / name] if relative_to else []) + [d / name for d in self.include_dirs]
        for path in candidates:
            if path.is_file():
                return path.resolve()
        return None

    def read(self, path):
        """Reads one header (and the quoted headers it includes); returns the set of
        function names visible through it."""
        path = pathlib.Path(path).resolve()
        if path in self._visible:  # read already (or being read: an include cycle)
            return self._visible[path]
        self._visible[path] = visible = set()
        code_lines = []
        for number, raw in enumerate(self._joined_lines(_strip_comments(path.read_text())), start=1):
            stripped = raw.strip()
            if stripped.startswith("#"):
                words = stripped[1:].split(None, 2)
                if words and words[0] == "include" and len(words) > 1 and words[1].startswith('"'):
                    included = self.find(words[1].strip('"'), path.parent)
                    if included is None:
                        raise HeaderError(f"{path}:{number}: {words[1]} found in no include directory")
                    visible |= self.read(included)
                elif words and words[0] == "define" and len(words) > 1 and "(" not in words[1]:
                    self.macros.add(words[1])
                code_lines.append("")
            else:
                code_lines.append(raw)
        for declaration in self._declarations("\n".join(code_lines), str(path)):
            visible.add(declaration)
        return visible

    @staticmethod
    def _joined_lines(text):
        """Lines with backslash continuations joined (the joined lines left empty)."""
        lines = text.split("\n")
        out, i = [], 0
        while i < len(lines):
            line, extra = lines[i], 0
            while line.endswith("\\") and i + extra + 1 < len(lines):
                extra += 1
                line = line[:-1] + " " + lines[i + extra]
            out.append(line)
            out.extend([""] * extra)
            i += extra + 1
        return out

    def _declarations(self, code, filename):
        """Splits the code into top-level declarations; records prototypes and typedefs;
        yields the function names declared."""
        tokens = list(_tokens(code))
        current, i = [], 0
        while i < len(tokens):
            kind, text, line = tokens[i]
            if kind == "id" and text == "extern" and i + 2 < len(tokens) and tokens[i + 1][0] == "str" \
                    and tokens[i + 2][0] == "{":
                i += 3  # extern "C" { ... }: its contents are top-level declarations
                continue
            if kind == "{":
                depth, j = 1, i + 1
                while j < len(tokens) and depth:
                    depth += {"{": 1, "}": -1}.get(tokens[j][0], 0)
                    j += 1
                if current and current[-1][0] == ")":  # a function definition
                    name = self._record(current, filename, has_body=True)
                    if name:
                        yield name
                    current = []
                else:  # struct/enum/union body: part of the declaration
                    current.append(("body", "{...}", line))
                i = j
                continue
            if kind == "}":  # the closing brace of extern "C" {
                i += 1
                continue
            if kind == ";":
                if current:
                    name = self._record(current, filename, has_body=False)
                    if name:
                        yield name
                current = []
            else:
                current.append(tokens[i])
            i += 1

    def _drop_attributes(self, tokens):
        """Without macros used as qualifiers and __attribute__((...)) groups."""
        out, i = [], 0
        while i < len(tokens):
            kind, text, line = tokens[i]
            if kind == "id" and text in ("__attribute__", "__declspec"):
                depth, j = 0, i + 1
                while j < len(tokens):
                    depth += {"(": 1, ")": -1}.get(tokens[j][0], 0)
                    j += 1
                    if depth == 0:
                        break
                i = j
                continue
            if not (kind == "id" and (text in self.macros or text in QUALIFIERS)):
                out.append(tokens[i])
            i += 1
        return out

    def _record(self, tokens, filename, has_body):
        line = tokens[0][2]
        tokens = self._drop_attributes(tokens)
        if not tokens:
            return None
        if tokens[0][1] == "typedef":
            names = [t for t in tokens[1:] if t[0] == "id"]
            if names and "(" not in [t[0] for t in tokens] and "body" not in [t[0] for t in tokens]:
                target = self._type(tokens[1:-1]) if len(names) > 1 else None
                if target is not None:
                    self.typedefs[names[-1][1]] = target
            return None
        kinds = [t[0] for t in tokens]
        if "(" not in kinds:
            return None
        open_at = kinds.index("(")
        if open_at == 0 or tokens[open_at - 1][0] != "id":
            return None  # a function pointer variable or something else: not a prototype
        name = tokens[open_at - 1][1]
        result = self._type(tokens[:open_at - 1])
        depth, close_at = 0, None
        for j in range(open_at, len(tokens)):
            depth += {"(": 1, ")": -1}.get(tokens[j][0], 0)
            if depth == 0:
                close_at = j
                break
        if result is None or close_at is None:
            return None
        params, part, depth = [], [], 0
        for t in tokens[open_at + 1:close_at]:
            depth += {"(": 1, ")": -1, "[": 1, "]": -1}.get(t[0], 0)
            if t[0] == "," and depth == 0:
                params.append(part)
                part = []
            else:
                part.append(t)
        if part:
            params.append(part)
        if len(params) == 1 and [t[1] for t in params[0]] == ["void"]:
            params = []
        parsed = [self._parameter(p, filename, line, name) for p in params]
        self.prototypes[name] = Prototype(name, result, parsed, has_body, filename, line)
        return name

    def _parameter(self, tokens, filename, line, function):
        length, depth_extra = None, 0
        if tokens and tokens[-1][0] == "]":
            start = max(i for i, t in enumerate(tokens) if t[0] == "[")
            inside = tokens[start + 1:-1]
            if len(inside) == 1 and inside[0][0] == "num" and inside[0][1].isdigit():
                length = int(inside[0][1])
            tokens, depth_extra = tokens[:start], 1
        if "(" in [t[0] for t in tokens]:
            return "", CType("function pointer", 1)
        words = [t for t in tokens if t[0] == "id"]
        name = ""
        type_words = [w[1] for w in words if w[1] not in ("const", "volatile", "restrict")]
        if len(type_words) >= 2 and words[-1][1] not in ("const",) and tokens[-1][0] == "id" \
                and not self._is_type_word(words[-1][1], type_words):
            name = words[-1][1]
            tokens = tokens[:-1]
        ctype = self._type(tokens)
        if ctype is None:
            raise HeaderError(f"{filename}:{line}: {function}: cannot read parameter "
                              f"'{' '.join(t[1] for t in tokens)}'")
        return name, dataclasses.replace(ctype, depth=ctype.depth + depth_extra, length=length)

    @staticmethod
    def _is_type_word(word, type_words):
        builtin = {"void", "char", "short", "int", "long", "float", "double", "signed", "unsigned", "_Bool"}
        return word in builtin and all(w in builtin for w in type_words)

    def _type(self, tokens):
        """CType of declaration specifiers and pointers, typedefs resolved; None if none."""
        depth, const_before_star, base = 0, False, []
        for kind, text, _ in tokens:
            if kind == "*":
                depth += 1
            elif text == "const":
                if depth == 0:
                    const_before_star = True
            elif kind == "id" and text not in ("volatile", "restrict", "struct", "enum", "union"):
                base.append(text)
            elif kind not in ("id",):
                return None
        if not base:
            return None
        name = " ".join(base)
        if name in self.typedefs:
            target = self.typedefs[name]
            return CType(target.base, target.depth + depth, target.const or const_before_star)
        return CType(name, depth, const_before_star)
