"""Whether a string is a unit expression of the Modelica Language Specification (chapter 19,
"Unit Expressions"): "N.m", "kg.m/s2", "kg.m.s-2", "1/rad", "J/(kg.K)", "m(1/2)"; no blanks.

Only the syntax is checked: whether each unit symbol is one a tool recognises (SI symbols
and prefixes) is not.
"""
from lark import Lark
from lark.exceptions import LarkError

_GRAMMAR = r"""
start: unit_numerator ("/" unit_denominator)?
unit_expression: unit_numerator ("/" unit_denominator)?
unit_numerator: ONE | unit_factors | "(" unit_expression ")"
unit_denominator: unit_factor | "(" unit_expression ")"
unit_factors: unit_factor ("." unit_factor)*
unit_factor: UNIT_OPERAND unit_exponent?
unit_exponent: SIGN? (UNSIGNED_INTEGER | "(" UNSIGNED_INTEGER "/" UNSIGNED_INTEGER ")")
ONE: "1"
SIGN: "+" | "-"
// unit-operand: [ unit-prefix ] unit-symbol, unit-symbol: NON-DIGIT { NON-DIGIT }
UNIT_OPERAND: /[A-Za-z_]+/
UNSIGNED_INTEGER: /[0-9]+/
"""

_parser = None


def is_unit_expression(text):
    global _parser
    if _parser is None:
        _parser = Lark(_GRAMMAR, parser="lalr", lexer="contextual")
    try:
        _parser.parse(text)
        return True
    except LarkError:
        return False
