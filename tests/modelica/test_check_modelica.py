#!/usr/bin/env python3
"""Tests of scripts/check_modelica.py and the Modelica grammar behind it.

- ParserTest: the constructs of the specification's concrete syntax in
  checker/parser/SpecFeatures.mo parse; operator precedence and the lexical rules come out
  as the specification defines them; invalid text is refused at the right line and column.
- CheckerTest: checker/ValidLib (one of each checked construct) is clean; each snippet of
  checker/broken/, added to a copy of ValidLib, is reported with exactly the problems its
  `// expect: LINE: TEXT` lines name and no other; package.order and header changes are
  seen.
"""
import contextlib
import io
import pathlib
import shutil
import subprocess
import sys
import tempfile
import unittest

HERE = pathlib.Path(__file__).resolve().parent
ROOT = HERE.parents[1]
CHECKER = ROOT / "scripts" / "check_modelica.py"
DATA = HERE / "checker"
sys.path.insert(0, str(ROOT / "scripts" / "modelica"))
sys.path.insert(0, str(ROOT / "scripts"))

from lark import Token, Tree  # noqa: E402

import check_modelica  # noqa: E402
import modelica_parser  # noqa: E402

OPERATOR_RULES = {"logical_expression": "or", "logical_term": "and", "not_expression": "not", "range": ":",
                  "if_expression": "if"}


def sexpr(node):
    """An expression tree as a prefix string: `1 + 2 * 3` -> (+ 1 (* 2 3))."""
    if isinstance(node, Token):
        return str(node)
    if node.data in ("number", "string"):
        return str(node.children[0])
    if node.data == "component_reference":
        return ".".join(str(part.children[0]) for part in node.children)
    if node.data in ("arithmetic_expression", "term", "factor", "relation"):
        items = list(node.children)
        if node.data == "arithmetic_expression" and isinstance(items[0], Tree) and items[0].data == "add_operator":
            left = f"(neg {sexpr(items[1])})" if str(items[0].children[0]) == "-" else sexpr(items[1])
            items = items[2:]
        else:
            left, items = sexpr(items[0]), items[1:]
        for operator, operand in zip(items[::2], items[1::2]):
            left = f"({operator.children[0]} {left} {sexpr(operand)})"
        return left
    if node.data in OPERATOR_RULES:
        return f"({OPERATOR_RULES[node.data]} {' '.join(sexpr(c) for c in node.children)})"
    if node.data == "parenthesized":
        return sexpr(node.children[0].children[0])
    return f"({node.data} {' '.join(sexpr(c) for c in node.children)})"


def binding_of(text):
    """The expression bound to x in `model M Real x = <text>; end M;`."""
    tree = modelica_parser.parse(f"model M Real x = {text}; end M;")
    binding = next(tree.find_data("binding"))
    return sexpr(binding.children[0])


class ParserTest(unittest.TestCase):
    def test_the_specification_features_parse(self):
        tree = modelica_parser.parse_file(DATA / "parser" / "SpecFeatures.mo")
        kinds = {node.data for node in tree.iter_subtrees()}
        for construct in ("import_all", "enumeration_specifier", "der_class_specifier", "extends_class_specifier",
                          "function_partial_application", "comprehension", "matrix", "end_index", "when_statement",
                          "when_equation", "while_statement", "for_equation", "multiple_assignment", "connect_clause",
                          "constraining_clause", "element_redeclaration", "condition_attribute", "external_clause",
                          "if_expression", "named_arguments"):
            self.assertIn(construct, kinds)
        names = {str(t) for t in tree.scan_values(lambda v: isinstance(v, Token) and v.type == "IDENT")}
        self.assertIn("'quoted ident\\'s, with \"quotes\" and $ymbols: +-*/'", names)
        numbers = {str(t) for t in tree.scan_values(lambda v: isinstance(v, Token) and v.type == "UNSIGNED_NUMBER")}
        self.assertTrue({"2.5e-3", "1.5E+3", "2.", "3.0e0", "4E-2", ".5", "06"} <= numbers)

    def test_operator_precedence_follows_the_grammar(self):
        self.assertEqual(binding_of("1 + 2 * 3 ^ 2"), "(+ 1 (* 2 (^ 3 2)))")
        self.assertEqual(binding_of("-2 ^ 2"), "(neg (^ 2 2))")       # unary minus binds looser than ^
        self.assertEqual(binding_of("-a * b + c"), "(+ (neg (* a b)) c)")
        self.assertEqual(binding_of("a - b - c"), "(- (- a b) c)")  # left associative
        self.assertEqual(binding_of("a / b * c"), "(* (/ a b) c)")
        self.assertEqual(binding_of("a .* b .+ c ./ d"), "(.+ (.* a b) (./ c d))")
        self.assertEqual(binding_of("a or b and not c < d"), "(or a (and b (not (< c d))))")
        self.assertEqual(binding_of("(a or b) and c"), "(and (or a b) c)")
        self.assertEqual(binding_of("1 : 2 : 10"), "(: 1 2 10)")
        self.assertEqual(binding_of("if a then 1 elseif b then 2 else 3"), "(if a 1 b 2 3)")

    def test_a_power_is_not_associative(self):
        # factor: primary [ "^" primary ]: a ^ b ^ c needs parentheses.
        with self.assertRaises(modelica_parser.ModelicaSyntaxError):
            modelica_parser.parse("model M Real x = 2 ^ 3 ^ 2; end M;")

    def test_invalid_text_is_refused_where_it_goes_wrong(self):
        cases = [
            ("model M\n  Real end;\nend M;", 2, 8, "unexpected 'end'"),                 # keywords are reserved
            ("model M\n  Real x = 1 \"a\" \"b\";\nend M;", 2, 18, "unexpected"),       # no implicit concatenation
            ("model M\n  String s = \"bad \\q escape\";\nend M;", 2, 14, "no Modelica token"),
            ("model M\n  Real x = 1.2.3;\nend M;", 2, 15, "unexpected"),
            ("model M\n  /* never closed\nend M;", 2, 3, "unexpected '/'"),
            ("model M\n  Real 'a\\z';\nend M;", 2, 8, "no Modelica token"),            # not an S-ESCAPE
            ("model M\n  Real x;\nequation\n  x := 1;\nend M;", 4, 5, "unexpected ':='"),  # := in equations
            ("model M\n  Real x;\nalgorithm\n  x = 1;\nend M;", 4, 5, "unexpected '='"),   # = in algorithms
            ("model M\n  Real x[end];\nend M;", None, None, None),                     # `end` is an index
            ("model M\n  Real x = y[1] end;\nend M;", 2, 17, "unexpected 'end'"),
            ("model M\n  Real x;\nequation\n  if x > 1 then x = 1; end when;\nend M;", 4, 28,
             "unexpected 'when', expected 'if'"),
            ("model M\n  Real x = 1\nend M;", 3, 1, "unexpected 'end'"),
            ("model M\n  final redeclare Real x;\nend M;", 2, 9, "unexpected 'redeclare'"),  # prefix order
            ("model M\n  Real x;", 2, 1, "unexpected end of file"),
        ]
        for text, line, column, what in cases:
            with self.subTest(text=text):
                if line is None:
                    modelica_parser.parse(text)
                    continue
                with self.assertRaises(modelica_parser.ModelicaSyntaxError) as caught:
                    modelica_parser.parse(text, "snippet.mo")
                where = (caught.exception.line, caught.exception.column)
                self.assertEqual(where, (line, column), str(caught.exception))
                self.assertIn(what, caught.exception.what)
                self.assertTrue(str(caught.exception).startswith(f"snippet.mo:{line}:{column}: "))

    def test_initial_and_end_in_both_of_their_roles(self):
        tree = modelica_parser.parse("model M\n Real x[2];\nequation\n x[end] = 1;\n"
                                     " x[1] = if initial() then 1 else 2;\n"
                                     "initial equation\n x[end - 1] = 0;\ninitial algorithm\nend M;")
        self.assertEqual(len(list(tree.find_data("end_index"))), 2)
        self.assertEqual(len(list(tree.find_data("initial"))), 2)
        self.assertEqual(len(list(tree.find_data("function_call"))), 1)


def run_checker(package, *extra, in_process=True):
    """(exit code, problem lines, whole output) of check_modelica.py on package. In process
    by default (the parser is built once); as a program to see its exit status."""
    if in_process:
        output = io.StringIO()
        with contextlib.redirect_stdout(output), contextlib.redirect_stderr(output):
            code = check_modelica.main([str(package), *map(str, extra)])
        text = output.getvalue()
    else:
        result = subprocess.run([sys.executable, str(CHECKER), str(package), *map(str, extra)], capture_output=True,
                                text=True, timeout=120)
        code, text = result.returncode, result.stdout + result.stderr
    problems = [line for line in text.splitlines() if not line.startswith("check_modelica:")]
    return code, problems, text


def expectations(snippet):
    out = []
    for line in snippet.read_text().splitlines():
        if line.startswith("// expect: "):
            number, text = line[len("// expect: "):].split(": ", 1)
            out.append((int(number), text))
    return out


class CheckerTest(unittest.TestCase):
    def setUp(self):
        self.work = pathlib.Path(tempfile.mkdtemp(prefix="check_modelica_"))
        self.package = self.work / "ValidLib"
        shutil.copytree(DATA / "ValidLib", self.package)

    def tearDown(self):
        shutil.rmtree(self.work)

    def test_the_valid_package_is_clean(self):
        code, problems, output = run_checker(self.package, in_process=False)
        self.assertEqual((code, problems), (0, []), output)
        self.assertIn("4 external C functions, 4 connect equations, 10 parameters", output)

    def test_each_broken_snippet_is_reported_with_exactly_its_problems(self):
        snippets = sorted((DATA / "broken").glob("*.mo"))
        self.assertGreaterEqual(len(snippets), 10)
        for snippet in snippets:
            with self.subTest(snippet=snippet.name):
                target = self.package / snippet.name
                shutil.copy(snippet, target)
                order = self.package / "package.order"
                original_order = order.read_text()
                order.write_text(original_order + snippet.stem + "\n")
                try:
                    code, problems, output = run_checker(self.package)
                    if snippet.name == "UnknownClass.mo":  # once as a program: its exit status
                        self.assertEqual(run_checker(self.package, in_process=False)[:2], (code, problems))
                finally:
                    target.unlink()
                    order.write_text(original_order)
                expected = expectations(snippet)
                self.assertTrue(expected, f"{snippet.name} names no expected problem")
                self.assertEqual(code, 1, output)
                self.assertEqual(len(problems), len(expected), output)
                for line, text in expected:
                    prefix = f"{target}:{line}: "
                    self.assertTrue(any(p.startswith(prefix) and text in p for p in problems),
                                    f"missing '{prefix}...{text}' in:\n{output}")

    def test_package_order_must_list_the_classes_exactly(self):
        order = self.package / "package.order"
        order.write_text(order.read_text().replace("scale\n", "") + "Missing\n")
        code, problems, output = run_checker(self.package)
        self.assertEqual(code, 1)
        self.assertEqual(len(problems), 2, output)
        self.assertIn(f"{order}:7: Missing is no class or constant of ValidLib", problems)
        self.assertTrue(any("scale of ValidLib is missing" in p for p in problems), output)

    def test_the_header_is_read_not_a_fixed_list(self):
        header = self.package / "Resources" / "Include" / "validlib.h"
        header.write_text(header.read_text().replace("size_t n, int enabled", "int enabled"))
        code, problems, output = run_checker(self.package)
        self.assertEqual(code, 1)
        self.assertEqual(len(problems), 1, output)
        self.assertIn("exchange -> vl_exchange: 8 arguments, vl_exchange takes 7 (validlib.h:17)", problems[0])
        header.write_text(header.read_text() + "\nVL_API int vl_added_later(vl_handle* handle);\n")
        header.write_text(header.read_text().replace("int enabled", "size_t n, int enabled"))
        self.assertEqual(run_checker(self.package)[0], 0)

    def test_parse_only_reports_each_file_that_does_not_parse(self):
        code, problems, output = run_checker("--parse-only", DATA / "broken")
        self.assertEqual(code, 1)
        self.assertEqual(len(problems), 1, output)
        self.assertTrue(problems[0].startswith(f"{DATA / 'broken' / 'SyntaxError.mo'}:6:11: unexpected ';'"), output)
        self.assertEqual(run_checker("--parse-only", DATA / "parser")[:2], (0, []))

    def test_a_missing_package_is_a_usage_error(self):
        code, _, output = run_checker(self.work / "nowhere", in_process=False)
        self.assertEqual(code, 2)
        self.assertIn("package.mo: no such file", output)


if __name__ == "__main__":
    unittest.main(verbosity=2)
