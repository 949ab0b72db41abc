"""Parses Modelica source text with modelica.lark (the specification's concrete syntax).

parse(text, filename) returns the Lark parse tree of one stored definition (a .mo file);
a syntax error raises ModelicaSyntaxError naming the file, line and column, and what was
expected. Needs Lark (Debian package python3-lark, scripts/install_deps.sh).
"""
import pathlib

try:
    import lark
except ImportError as error:  # the message names the package, not a traceback
    raise SystemExit("modelica_parser: needs the Python package lark (Debian: python3-lark, "
                     "scripts/install_deps.sh); with pyenv's python3 run /usr/bin/python3") from error

GRAMMAR = pathlib.Path(__file__).with_name("modelica.lark")


class ModelicaSyntaxError(Exception):
    """A file that is not Modelica: `file:line:column: what`."""

    def __init__(self, filename, line, column, what):
        super().__init__(f"{filename}:{line}:{column}: {what}")
        self.filename, self.line, self.column, self.what = filename, line, column, what


class _OneTokenMoreContext:
    """Token filter for the two places where the specification's grammar needs two tokens of
    lookahead: `end` within square brackets is an index (END_INDEX), elsewhere it closes a
    construct; `initial` followed by `equation` or `algorithm` opens an initial section
    (INITIAL_SECTION), elsewhere it is the operator initial()."""

    always_accept = ()

    def process(self, stream):
        depth = 0
        pending = None
        for token in stream:
            if pending is not None:
                if token.type in ("EQUATION", "ALGORITHM"):
                    pending = lark.Token.new_borrow_pos("INITIAL_SECTION", pending.value, pending)
                yield pending
                pending = None
            if token.type == "LSQB":
                depth += 1
            elif token.type == "RSQB":
                depth = max(depth - 1, 0)
            elif token.type == "END" and depth > 0:
                token = lark.Token.new_borrow_pos("END_INDEX", token.value, token)
            if token.type == "INITIAL":
                pending = token
                continue
            yield token
        if pending is not None:
            yield pending


_parser = None


def _get_parser():
    global _parser
    if _parser is None:
        _parser = lark.Lark(GRAMMAR.read_text(), parser="lalr", lexer="basic", postlex=_OneTokenMoreContext(),
                            propagate_positions=True, maybe_placeholders=False)
    return _parser


def _expected(names):
    """The expected terminals as a reader knows them: keywords and symbols as written."""
    spelled = {t.name: t.pattern.value for t in _get_parser().terminals
               if isinstance(t.pattern, lark.lexer.PatternStr)}
    spelled.update(END_INDEX="end", INITIAL_SECTION="initial")
    described = {"IDENT": "an identifier", "STRING": "a string", "UNSIGNED_NUMBER": "a number"}
    shown = sorted({described.get(n) or f"'{spelled.get(n, n)}'" for n in names})
    return ", ".join(shown[:14]) + (", ..." if len(shown) > 14 else "")


def parse(text, filename="<text>"):
    """The parse tree of `text`, one stored definition; ModelicaSyntaxError when it is none."""
    try:
        return _get_parser().parse(text)
    except lark.exceptions.UnexpectedCharacters as error:
        raise ModelicaSyntaxError(filename, error.line, error.column,
                                  f"no Modelica token starts with {text[error.pos_in_stream]!r}") from None
    except lark.exceptions.UnexpectedToken as error:
        token = error.token
        if token.type == "$END":
            raise ModelicaSyntaxError(filename, text.count("\n") + 1, 1,
                                      f"unexpected end of file, expected {_expected(error.expected)}") from None
        raise ModelicaSyntaxError(filename, token.line, token.column,
                                  f"unexpected {token.value!r}, expected {_expected(error.expected)}") from None
    except lark.exceptions.UnexpectedEOF as error:
        raise ModelicaSyntaxError(filename, text.count("\n") + 1, 1,
                                  f"unexpected end of file, expected {_expected(error.expected)}") from None


def parse_file(path):
    path = pathlib.Path(path)
    try:
        text = path.read_text(encoding="utf-8")
    except UnicodeDecodeError as error:
        raise ModelicaSyntaxError(str(path), 1, 1, f"not UTF-8 ({error.reason} at byte {error.start})") from None
    return parse(text, str(path))
