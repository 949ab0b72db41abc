#!/usr/bin/env python3
"""Checks a Modelica package stored as a directory without a Modelica tool.

Usage: check_modelica.py [--include-dir DIR]... PACKAGE_DIR
       check_modelica.py --parse-only DIR   (only parse every .mo file below DIR)

Every .mo file is parsed with the grammar of the Modelica Language Specification
(scripts/modelica/modelica.lark; Appendix A "Modelica Concrete Syntax"), then the parse
trees are checked. Exit 0 when the package is clean, 1 with one `file:line: what` line per
problem (2 on a usage error). The rules:

1. Files: every .mo file parses; its `within` names the package of its directory; it
   holds one class, named as the file (package.mo: as the directory); a class ends with
   its own name; package.order lists every class and constant of its package exactly
   once and nothing else, the classes defined in package.mo itself in their order there.
2. References: every name used as a base class (extends), a component's type, a short
   class's base or a called function resolves (see scripts/modelica/package_model.py for
   the lookup) to a class of the package, a predefined type, a built-in function or a
   name in a library of the package's `uses` annotation (External: not resolved further,
   except that Modelica.SIunits does not exist from Modelica 4.0.0 on). Every variable
   used in an equation, statement, binding, modifier or condition resolves the same way
   (to a component, through the components' types, or an enumeration literal), unless
   it is a for/comprehension iterator of the class; and uses no conditional component
   (declared with `if`) outside connect equations (section 4.4.5). Modifiers name an
   element of the modified class (or an attribute of a predefined type). A call of a
   function of the package passes at most as many positional arguments as it has inputs,
   named arguments that are inputs, and every input that has no default.
3. External "C" functions: the C function is declared in the header of the external
   clause's Include annotation (or a header that one includes; --include-dir says where
   to look, default PACKAGE_DIR/Resources/Include); a function without a body in the
   header needs a Library annotation; the call passes as many arguments as the prototype
   takes; each argument maps to its C parameter as section 12.9 of the specification
   says: input Real -> double, Integer/Boolean/enumeration -> int, String ->
   const char*, an ExternalObject -> void* (const allowed); an output (or an array) is a
   pointer to the same, const for input arrays and strings, not const for outputs; an
   array of declared length n needs a C array parameter of length n when the C side
   declares one; an array declared with `:` passes its size(a, k) (or is declared with
   a length from other inputs); size(a, k) -> an integer type (the specification says
   size_t; with the Include prototype in scope C converts it; so does an integer
   literal); the assigned result maps the same way as an input scalar (String ->
   const char*). Without an explicit call the default call is
   checked (inputs then outputs, each array followed by its sizes, a single scalar
   output as the result).
4. connect(a, b): both sides are connectors of one connector class or of one of the
   compatible families below (MSL connectors of the same physical domain); the elements
   compare in number when all dimensions and subscripts are literal; two outputs of
   sub-components are never connected together.
5. Units: every `parameter` or `constant` whose type is Real (directly, or through a
   short class of the package) states its unit: either its type is in
   Modelica.Units.SI (MSL 4), or it has a `unit = "..."` modifier (`each unit` for an
   array); "1" states a dimensionless value; every unit string (of any component or
   short type) is a unit expression of chapter 19 ("m/s2", "N.m", not "m/s^2").
   Integer, Boolean, String, enumerations and ExternalObjects are exempt. A parameter
   that holds values of several units (a protocol's generic array) says so with the
   vendor annotation `__DEMLink(mixedUnits = true)`. Parameters of functions (their
   inputs) are exempt.
   An external type outside Modelica.Units.SI must be listed in EXTERNAL_NON_REAL_TYPES
   (its value is not a Real) or is reported.
"""
import argparse
import pathlib
import sys

sys.path.insert(0, str(pathlib.Path(__file__).resolve().parent / "modelica"))

# package_model first: without Lark, its parser module stops with the package to install.
from package_model import (PREDEFINED_TYPES, Builtin, ClassInfo, Component, External, Problem,  # noqa: E402
                           Resolver, annotation_value, child, dotted, line_of, load_package,
                           modification_arguments, reference_parts, reference_text, string_value,
                           walk_expressions)
from c_header import CType, HeaderError, HeaderReader  # noqa: E402
from modelica_parser import ModelicaSyntaxError, parse_file  # noqa: E402
from unit_expression import is_unit_expression  # noqa: E402
from lark import Token, Tree  # noqa: E402

# MSL base classes that add no elements (icons): a lookup may pass through them.
EMPTY_EXTERNAL_BASES = ("Modelica.Icons.",)

# Connector families whose members may be connected to each other (MSL 4.0.0): signal
# connectors of one type, MultiBody frames, flanges of one mechanical domain.
CONNECTOR_FAMILIES = {
    "Real signal": {"Modelica.Blocks.Interfaces.RealInput", "Modelica.Blocks.Interfaces.RealOutput"},
    "Integer signal": {"Modelica.Blocks.Interfaces.IntegerInput", "Modelica.Blocks.Interfaces.IntegerOutput"},
    "Boolean signal": {"Modelica.Blocks.Interfaces.BooleanInput", "Modelica.Blocks.Interfaces.BooleanOutput"},
    "MultiBody frame": {"Modelica.Mechanics.MultiBody.Interfaces.Frame",
                        "Modelica.Mechanics.MultiBody.Interfaces.Frame_a",
                        "Modelica.Mechanics.MultiBody.Interfaces.Frame_b",
                        "Modelica.Mechanics.MultiBody.Interfaces.Frame_resolve"},
    "translational flange": {"Modelica.Mechanics.Translational.Interfaces.Flange_a",
                             "Modelica.Mechanics.Translational.Interfaces.Flange_b",
                             "Modelica.Mechanics.Translational.Interfaces.Support"},
    "rotational flange": {"Modelica.Mechanics.Rotational.Interfaces.Flange_a",
                          "Modelica.Mechanics.Rotational.Interfaces.Flange_b",
                          "Modelica.Mechanics.Rotational.Interfaces.Support"},
}
SIGNAL_OUTPUTS = {"Modelica.Blocks.Interfaces.RealOutput", "Modelica.Blocks.Interfaces.IntegerOutput",
                  "Modelica.Blocks.Interfaces.BooleanOutput"}

# The connectors of the MSL classes the package instantiates (MSL 4.0.0 documentation):
# class -> {connector name: (connector class, number of elements)}.
EXTERNAL_CONNECTORS = {
    "Modelica.Blocks.Sources.Step": {"y": ("Modelica.Blocks.Interfaces.RealOutput", 1)},
    "Modelica.Blocks.Sources.Constant": {"y": ("Modelica.Blocks.Interfaces.RealOutput", 1)},
    "Modelica.Blocks.Sources.RealExpression": {"y": ("Modelica.Blocks.Interfaces.RealOutput", 1)},
    "Modelica.Blocks.Sources.BooleanStep": {"y": ("Modelica.Blocks.Interfaces.BooleanOutput", 1)},
    "Modelica.Blocks.Sources.BooleanExpression": {"y": ("Modelica.Blocks.Interfaces.BooleanOutput", 1)},
    "Modelica.Blocks.Sources.IntegerStep": {"y": ("Modelica.Blocks.Interfaces.IntegerOutput", 1)},
    "Modelica.Mechanics.MultiBody.World": {"frame_b": ("Modelica.Mechanics.MultiBody.Interfaces.Frame_b", 1)},
    "Modelica.Mechanics.MultiBody.Parts.Body": {"frame_a": ("Modelica.Mechanics.MultiBody.Interfaces.Frame_a", 1)},
    "Modelica.Mechanics.MultiBody.Parts.Fixed": {"frame_b": ("Modelica.Mechanics.MultiBody.Interfaces.Frame_b", 1)},
    "Modelica.Mechanics.MultiBody.Joints.Prismatic": {
        "frame_a": ("Modelica.Mechanics.MultiBody.Interfaces.Frame_a", 1),
        "frame_b": ("Modelica.Mechanics.MultiBody.Interfaces.Frame_b", 1),
        "axis": ("Modelica.Mechanics.Translational.Interfaces.Flange_a", 1),
        "support": ("Modelica.Mechanics.Translational.Interfaces.Flange_b", 1)},
    "Modelica.Mechanics.MultiBody.Joints.Revolute": {
        "frame_a": ("Modelica.Mechanics.MultiBody.Interfaces.Frame_a", 1),
        "frame_b": ("Modelica.Mechanics.MultiBody.Interfaces.Frame_b", 1),
        "axis": ("Modelica.Mechanics.Rotational.Interfaces.Flange_a", 1),
        "support": ("Modelica.Mechanics.Rotational.Interfaces.Flange_b", 1)},
    "Modelica.Mechanics.Translational.Components.SpringDamper": {
        "flange_a": ("Modelica.Mechanics.Translational.Interfaces.Flange_a", 1),
        "flange_b": ("Modelica.Mechanics.Translational.Interfaces.Flange_b", 1)},
}

# External types whose value is not a Real (no unit to state).
EXTERNAL_NON_REAL_TYPES = {"Modelica.Mechanics.MultiBody.Types.Color"}

SI_TYPES = "Modelica.Units.SI."


class Checker:
    def __init__(self, package, include_dirs):
        self.package = package
        self.resolver = Resolver(package, EMPTY_EXTERNAL_BASES)
        self.headers = HeaderReader(include_dirs)
        self.problems = list(package.problems)
        self.counts = {"calls": 0, "variable references": 0, "external C functions": 0, "connect equations": 0,
                       "parameters": 0}

    def report(self, info, line, what):
        self.problems.append(Problem(info.file, line, what))

    # --- 2. references ---------------------------------------------------------------------
    def _resolve_class(self, name, scope, line, used_as):
        found = self.resolver.resolve(name, scope)
        if found is None:
            self.report(scope, line, f"{used_as} {name} resolves to no class")
        elif isinstance(found, Component):
            self.report(scope, line, f"{used_as} {name} is a component, not a class")
            return None
        elif isinstance(found, External) and found.name.startswith("Modelica.SIunits.") and \
                self._msl_major() >= 4:
            self.report(scope, line, f"{name}: Modelica.SIunits does not exist in Modelica "
                                     f"{self.package.uses.get('Modelica')} (use Modelica.Units.SI)")
        return found

    def _msl_major(self):
        version = self.package.uses.get("Modelica") or "0"
        try:
            return int(version.split(".")[0])
        except ValueError:
            return 0

    def check_references(self, info):
        for extends in info.extends:
            scope = info.parent if extends.type_name == info.name else info
            base = self._resolve_class(extends.type_name, scope, extends.line, "base class")
            self._check_modifiers(base, extends.modification, info, f"extends {extends.type_name}")
        if info.short_base:
            base = self._resolve_class(info.short_base, info.parent or info, info.line, "base class")
            self._check_modifiers(base, info.short_modification, info, f"type {info.name}")
        for component in info.components.values():
            ctype = self._resolve_class(component.type_name, info, component.line, f"type of {component.name}:")
            modification = component.modification
            class_modification = child(modification, "class_modification") if modification is not None else None
            self._check_modifiers(ctype, class_modification, info, component.name)
        for call in info.calls:
            self.counts["calls"] += 1
            self._check_call(call, info)
        for name, line in info.references:
            if name.split(".")[0] in info.iterators:
                continue
            self.counts["variable references"] += 1
            if self.resolver.resolve(name, info) is None:
                self.report(info, line, f"{name} resolves to nothing (no component, constant or enumeration literal)")
                continue
            conditional = self._conditional_on_path(name, info)
            if conditional is not None:
                self.report(info, line, f"{name}: {conditional.name} is a conditional component (declared with if): "
                                        "it may only be modified and used in connect equations (section 4.4.5)")

    def _conditional_on_path(self, name, info):
        """The first component declared with a condition along the name's components."""
        scope = info
        for ident in name.lstrip(".").split("."):
            element = self.resolver.find_element(scope, ident) if isinstance(scope, ClassInfo) else None
            if not isinstance(element, Component):
                return None
            if element.condition is not None:
                return element
            scope = self.resolver.type_of(element)
        return None

    def _attributes(self, target):
        """Names a modifier may use on target: None when unknown (external)."""
        if isinstance(target, Builtin):
            return PREDEFINED_TYPES.get(target.name)
        if isinstance(target, ClassInfo):
            return target
        return None

    def _check_modifiers(self, target, class_modification, info, where):
        if class_modification is None or target is None:
            return
        for name, modification, _, _ in modification_arguments(class_modification):
            first = name.split(".")[0]
            attributes = self._attributes(target)
            element = None
            if isinstance(attributes, set):
                if first not in attributes:
                    self.report(info, line_of(modification), f"{where}: {target.name} has no attribute {first}")
                continue
            if isinstance(attributes, ClassInfo):
                element = self.resolver.find_element(attributes, first)
                if element is None:
                    self.report(info, line_of(modification), f"{where}: {attributes.full_name} has no element {first}")
                    continue
            inner = child(modification, "modification")
            if isinstance(element, Component) and inner is not None and "." not in name:
                self._check_modifiers(self.resolver.type_of(element), child(inner, "class_modification"), info,
                                      f"{where}.{first}")

    def _check_call(self, call, info):
        target = self.resolver.resolve(call.name, info)
        if target is None:
            self.report(info, call.line, f"call of {call.name}: no such function")
            return
        if isinstance(target, Component):
            self.report(info, call.line, f"call of {call.name}: a component, not a function")
            return
        if not isinstance(target, ClassInfo) or target.kind not in ("function", "record") and \
                not self.resolver.extends_external_object(target):
            if isinstance(target, ClassInfo) and target.kind not in ("function", "record"):
                self.report(info, call.line, f"call of {call.name}: a {target.kind}, not a function")
            return
        function = target.classes.get("constructor") if self.resolver.extends_external_object(target) else target
        if function is None:
            return
        inputs = [c for c in function.components.values() if "input" in c.prefixes]
        arguments = child(call.args, "function_arguments")
        positional, named = [], []
        for argument in (arguments.children if arguments is not None else []):
            if isinstance(argument, Tree) and argument.data == "named_arguments":
                named = [str(n.children[0]) for n in argument.children]
            else:
                positional.append(argument)
        if len(positional) > len(inputs):
            self.report(info, call.line, f"call of {call.name}: {len(positional)} positional arguments, "
                                         f"{function.full_name} has {len(inputs)} inputs")
            return
        given = {c.name for c in inputs[:len(positional)]}
        for name in named:
            if name not in {c.name for c in inputs}:
                self.report(info, call.line, f"call of {call.name}: {function.full_name} has no input {name}")
            given.add(name)
        for component in inputs:
            has_default = component.modification is not None and child(component.modification, "binding") is not None
            if component.name not in given and not has_default:
                self.report(info, call.line, f"call of {call.name}: input {component.name} is not given")

    # --- 3. external C functions ----------------------------------------------------------------
    def check_external(self, info):
        clause = info.external
        if clause is None or info.kind != "function" or clause.language != "C":
            return
        self.counts["external C functions"] += 1
        include = string_value(annotation_value(clause.annotation, "Include"))
        if include is None:
            self.report(info, clause.line, f'{info.name}: external "C" without an Include annotation: '
                                           "the prototype the call is checked against is unknown")
            return
        headers = [part.split('\\"')[1] for part in include.split("#include")[1:] if '\\"' in part]
        visible = set()
        try:
            for header in headers:
                path = self.headers.find(header)
                if path is None:
                    self.report(info, clause.line, f"{info.name}: Include header {header} found in no include "
                                                   f"directory ({', '.join(map(str, self.headers.include_dirs))})")
                    return
                visible |= self.headers.read(path)
        except HeaderError as error:
            self.report(info, clause.line, f"{info.name}: {error}")
            return
        formals = {c.name: c for c in info.components.values()}
        call_name, result, args = clause.function, clause.result, clause.args
        if call_name is None:
            call_name, result, args = self._default_call(info)
        if call_name not in visible:
            self.report(info, clause.line, f"{info.name}: {call_name} is declared in none of {', '.join(headers)}")
            return
        prototype = self.headers.prototypes[call_name]
        if not prototype.has_body and annotation_value(clause.annotation, "Library") is None:
            header = pathlib.Path(prototype.file).name
            self.report(info, clause.line, f"{info.name}: {call_name} is only declared in {header} (its code is in a "
                                           "library): the external clause needs a Library annotation")
        where = f"{info.name} -> {call_name}"
        if result is not None:
            formal = formals.get(result)
            if formal is None or "output" not in formal.prefixes:
                self.report(info, clause.line, f"{where}: the result {result} is no output of {info.name}")
            else:
                want = self._c_type(formal, as_result=True)
                if want is not None and not self._matches(want, prototype.result):
                    self.report(info, clause.line, f"{where}: returns {prototype.result}, {result} needs {want}")
        if len(args) != len(prototype.params):
            self.report(info, clause.line, f"{where}: {len(args)} arguments, {call_name} takes {len(prototype.params)} "
                                           f"({pathlib.Path(prototype.file).name}:{prototype.line})")
            return
        for index, (arg, (pname, ctype)) in enumerate(zip(args, prototype.params), start=1):
            self._check_argument(info, clause, where, index, arg, pname, ctype, formals)
        self._check_sizes_passed(info, clause, where, args, formals)

    def _check_sizes_passed(self, info, clause, where, args, formals):
        """An array formal declared with `:` passes each such dimension's size(a, k): the
        C side has no other way to know its length (declare the length from other inputs,
        e.g. `x[6 * n]`, to pass it as n)."""
        passed = set()
        for arg in args:
            if isinstance(arg, tuple):
                passed.add((arg[1], arg[2]))
            elif isinstance(arg, Tree) and arg.data == "function_call" and isinstance(arg.children[0], Tree) and \
                    reference_text(arg.children[0]) == "size":
                arguments = child(arg.children[1], "function_arguments")
                values = arguments.children if arguments is not None else []
                if len(values) == 2 and isinstance(values[0], Tree) and values[0].data == "component_reference" and \
                        self._literal(values[1]) is not None:
                    passed.add((reference_text(values[0]), self._literal(values[1])))
        for index, arg in enumerate(args, start=1):
            if not (isinstance(arg, Tree) and arg.data == "component_reference"):
                continue
            formal = formals.get(reference_text(arg))
            if formal is None:
                continue
            subscripts = [sub for dims in formal.dims for sub in dims.children]
            for k, subscript in enumerate(subscripts, start=1):
                if isinstance(subscript, Tree) and subscript.data == "colon" and (formal.name, k) not in passed:
                    self.report(info, clause.line, f"{where}: argument {index} '{formal.name}' is declared with ':' "
                                                   f"but size({formal.name}, {k}) is not passed: the C side cannot "
                                                   "know its length")

    def _default_call(self, info):
        """Section 12.9: inputs then outputs, arrays followed by their sizes; a single scalar
        output is the result."""
        inputs = [c for c in info.components.values() if "input" in c.prefixes]
        outputs = [c for c in info.components.values() if "output" in c.prefixes]
        result = None
        if len(outputs) == 1 and not outputs[0].dims:
            result, outputs = outputs[0].name, []
        args = []
        for component in inputs + outputs:
            args.append(Tree("component_reference", [Tree("reference_part", [Token("IDENT", component.name)])]))
            rank = sum(len(d.children) for d in component.dims)
            for k in range(1, rank + 1):
                args.append(("size", component.name, k))
        return info.name, result, args

    def _is_external_object(self, component):
        ctype = self.resolver.type_of(component)
        return isinstance(ctype, ClassInfo) and self.resolver.extends_external_object(ctype)

    def _scalar_base(self, component):
        ctype = self.resolver.type_of(component)
        if isinstance(ctype, Builtin):
            return {"Real": "double", "Integer": "int", "Boolean": "int", "String": "char"}.get(ctype.name)
        if isinstance(ctype, ClassInfo) and ctype.enumeration is not None:
            return "int"
        return None

    def _c_type(self, component, as_result=False):
        """The CType a formal maps to (section 12.9.1), or None when it has no mapping."""
        if self._is_external_object(component):
            return CType("void", 1, None)  # const: either
        base = self._scalar_base(component)
        if base is None:
            return None
        string = base == "char"
        output = "output" in component.prefixes or ("input" not in component.prefixes and not as_result)
        if as_result:
            return CType(base, 1 if string else 0, True if string else None)
        depth = (1 if string else 0) + (1 if component.dims or output else 0)
        if depth == 0:
            return CType(base, 0, None)
        if output:
            return CType(base, depth, True if string else False)
        return CType(base, depth, True)

    @staticmethod
    def _matches(want, got):
        integer_types = {"int", "size_t", "long", "long long", "unsigned", "unsigned int", "unsigned long"}
        if want.base == "size":
            return got.depth == 0 and got.base in integer_types
        if want.base != got.base or want.depth != got.depth:
            return False
        return want.const is None or got.depth == 0 or want.const == got.const

    def _declared_length(self, component):
        if len(component.dims) != 1 or len(component.dims[0].children) != 1:
            return None
        subscript = component.dims[0].children[0]
        if isinstance(subscript, Tree) and subscript.data == "number" and str(subscript.children[0]).isdigit():
            return int(str(subscript.children[0]))
        return None

    def _check_argument(self, info, clause, where, index, arg, pname, ctype, formals):
        label = f"{where}: argument {index}"
        if isinstance(arg, tuple):  # a default call's size argument
            want = CType("size")
        elif isinstance(arg, Tree) and arg.data == "function_call" and isinstance(arg.children[0], Tree) and \
                reference_text(arg.children[0]) == "size":
            want = CType("size")
        elif isinstance(arg, Tree) and arg.data == "component_reference":
            name = reference_text(arg)
            formal = formals.get(name)
            if formal is None:
                self.report(info, clause.line, f"{label} '{name}' is no formal of {info.name}")
                return
            want = self._c_type(formal)
            if want is None:
                self.report(info, clause.line, f"{label} '{name}' ({formal.type_name}) has no C mapping")
                return
            length = self._declared_length(formal)
            if length is not None and ctype.length is not None and length != ctype.length:
                self.report(info, clause.line, f"{label} '{name}' has {length} elements, parameter {pname} "
                                               f"is declared [{ctype.length}]")
            label += f" '{name}'"
        elif isinstance(arg, Tree) and arg.data in ("number", "string", "true", "false"):
            text = str(arg.children[0]) if arg.children else arg.data
            want = {"string": CType("char", 1, True), "true": CType("int"), "false": CType("int")}.get(
                arg.data, CType("size") if text.isdigit() else CType("double"))
            label += f" {text}"
        else:
            self.report(info, clause.line, f"{label}: an external call passes formals, constants and size() only")
            return
        if not self._matches(want, ctype):
            shown = "an integer type" if want.base == "size" else str(want)
            self.report(info, clause.line, f"{label} maps to {shown}, parameter {index} ({pname}) of the prototype "
                                           f"is {ctype}")

    # --- 4. connect ----------------------------------------------------------------------------
    def _connector(self, reference, info):
        """(connector class name, number of elements or None, is a sub-component's) or a
        problem text."""
        parts = reference_parts(reference)
        scope, count, connector = info, 1, None
        for position, (ident, subscripts) in enumerate(parts):
            if isinstance(scope, External):
                table = EXTERNAL_CONNECTORS.get(scope.name)
                if table is None or ident not in table or position != len(parts) - 1:
                    return (f"{reference_text(reference)}: connectors of {scope.name} are not in the table of "
                            "MSL connectors (EXTERNAL_CONNECTORS in scripts/check_modelica.py)")
                name, elements = table[ident]
                count = None if count is None else count * elements
                return name, count, True
            element = self.resolver.find_element(scope, ident)
            if not isinstance(element, Component):
                return f"{reference_text(reference)}: {ident} is no component of {getattr(scope, 'full_name', scope)}"
            count = self._elements(element, subscripts, count)
            connector = self.resolver.type_of(element)
            if connector is None:
                return f"{reference_text(reference)}: the type {element.type_name} resolves to no class"
            scope = connector
        name = connector.name if isinstance(connector, External) else getattr(connector, "full_name", None)
        return name, count, len(parts) > 1

    @staticmethod
    def _literal(node):
        if isinstance(node, Tree) and node.data == "number" and str(node.children[0]).isdigit():
            return int(str(node.children[0]))
        return None

    def _elements(self, component, subscripts, count):
        if count is None:
            return None
        sizes = []
        for dims in component.dims:
            sizes.extend(self._literal(s) for s in dims.children)
        if subscripts is not None:
            picked = []
            for position, subscript in enumerate(subscripts.children):
                size = sizes[position] if position < len(sizes) else None
                if isinstance(subscript, Tree) and subscript.data == "colon":
                    picked.append(size)
                elif isinstance(subscript, Tree) and subscript.data == "range" and len(subscript.children) == 2:
                    low, high = (self._literal(c) for c in subscript.children)
                    picked.append(high - low + 1 if low is not None and high is not None else None)
                elif self._literal(subscript) is None and not (isinstance(subscript, Tree) and
                                                              subscript.data == "component_reference"):
                    picked.append(None)
            sizes = picked + sizes[len(subscripts.children):]
        for size in sizes:
            count = None if size is None or count is None else count * size
        return count

    def _family(self, name):
        for family, members in CONNECTOR_FAMILIES.items():
            if name in members:
                return family
        return name

    def check_connects(self, info):
        for left, right, line in info.connects:
            self.counts["connect equations"] += 1
            sides = [self._connector(left, info), self._connector(right, info)]
            bad = [s for s in sides if isinstance(s, str)]
            for text in bad:
                self.report(info, line, f"connect: {text}")
            if bad:
                continue
            (a, count_a, sub_a), (b, count_b, sub_b) = sides
            where = f"connect({reference_text(left)}, {reference_text(right)})"
            if self._family(a) != self._family(b):
                self.report(info, line, f"{where}: {a} and {b} are not compatible connectors")
            elif sub_a and sub_b and a in SIGNAL_OUTPUTS and b in SIGNAL_OUTPUTS:
                self.report(info, line, f"{where}: two outputs connected")
            if count_a is not None and count_b is not None and count_a != count_b:
                self.report(info, line, f"{where}: {count_a} elements connected to {count_b}")

    # --- 5. units ------------------------------------------------------------------------------
    def _real_without_unit(self, target):
        """True when a value of this type is a Real with no unit stated; None when exempt."""
        if isinstance(target, Builtin):
            return True if target.name == "Real" else None
        if isinstance(target, ClassInfo):
            if target.enumeration is not None or target.kind != "type" or not target.short_base:
                return None
            if self._has_unit(target.short_modification):
                return False
            return self._real_without_unit(self.resolver.resolve(target.short_base, target.parent or target))
        return None

    @staticmethod
    def _unit(class_modification):
        """The string of a `unit = "..."` modifier; None without one (or for "")."""
        for name, modification, _, _ in modification_arguments(class_modification):
            inner = child(modification, "modification")
            binding = child(inner, "binding") if inner is not None else None
            if name == "unit" and binding is not None and string_value(binding.children[0]):
                return string_value(binding.children[0])
        return None

    def _has_unit(self, class_modification):
        return self._unit(class_modification) is not None

    @staticmethod
    def _marked_mixed(component):
        """annotation (__DEMLink(mixedUnits = true))."""
        vendor = annotation_value(component.annotation, "__DEMLink")
        if not isinstance(vendor, Tree) or vendor.data != "modification":
            return False
        flag = annotation_value(Tree("annotation_clause", [child(vendor, "class_modification")]), "mixedUnits")
        return isinstance(flag, Tree) and flag.data == "true"

    def check_units(self, info):
        self._check_unit_strings(info)
        if info.kind == "function":
            return
        for component in info.components.values():
            if not component.prefixes & {"parameter", "constant"}:
                continue
            self.counts["parameters"] += 1
            if self._marked_mixed(component):
                continue
            target = self.resolver.type_of(component)
            where = f"{'parameter' if 'parameter' in component.prefixes else 'constant'} {component.name}"
            if isinstance(target, External):
                if target.name.startswith((SI_TYPES, "Modelica.SIunits.")) or target.name in EXTERNAL_NON_REAL_TYPES:
                    continue  # Modelica.SIunits: reported by the references rule
                self.report(info, component.line, f"{where}: {component.type_name} is outside {SI_TYPES[:-1]}: "
                                                  "use an SI type or Real with unit (EXTERNAL_NON_REAL_TYPES lists "
                                                  "external types that are not Real)")
                continue
            modification = component.modification
            class_modification = child(modification, "class_modification") if modification is not None else None
            if self._real_without_unit(target) and not self._has_unit(class_modification):
                self.report(info, component.line, f"{where}: Real without a unit: use a {SI_TYPES}* type or "
                                                  "unit = \"...\" (\"1\" when dimensionless)")

    def _check_unit_strings(self, info):
        """Every unit modifier of the class's components is a unit expression (chapter 19)."""
        modifications = [(c.line, c.modification) for c in info.components.values() if c.modification is not None]
        if info.short_modification is not None:
            modifications.append((info.line, Tree("modification", [info.short_modification])))
        for line, modification in modifications:
            for node in walk_expressions(modification):
                if node.data != "element_modification" or dotted(child(node, "name")) not in ("unit", "displayUnit"):
                    continue
                inner = child(node, "modification")
                binding = child(inner, "binding") if inner is not None else None
                text = string_value(binding.children[0]) if binding is not None else None
                if text and not is_unit_expression(text):
                    self.report(info, line_of(node) or line, f'unit "{text}" is no unit expression of the '
                                                              "specification (chapter 19; e.g. \"m/s2\", \"N.m\")")

    def run(self):
        if self.package.root is None:
            return self.problems
        for info in self.package.classes():
            try:
                self.check_references(info)
                self.check_external(info)
                self.check_connects(info)
                self.check_units(info)
            except (RecursionError, AttributeError, IndexError, TypeError, ValueError) as error:
                # A construct the checker does not handle: named, never a traceback.
                self.report(info, info.line, f"{info.full_name}: the checker cannot check this class "
                                             f"({type(error).__name__}: {error})")
        return self.problems


def parse_only(directory):
    """Rule 1's parsing alone, for any tree of .mo files."""
    files = sorted(directory.rglob("*.mo"))
    failed = 0
    for path in files:
        try:
            parse_file(path)
        except ModelicaSyntaxError as error:
            failed += 1
            print(error)
    print(f"check_modelica: {len(files)} files parsed, {failed} with syntax errors")
    return 1 if failed or not files else 0


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("package", type=pathlib.Path, help="package directory (holding package.mo)")
    parser.add_argument("--include-dir", action="append", default=[], type=pathlib.Path,
                        help="where the Include annotations' headers are (default PACKAGE/Resources/Include)")
    parser.add_argument("--parse-only", action="store_true",
                        help="only parse every .mo file below the directory (any library layout)")
    args = parser.parse_args(argv)
    if args.parse_only:
        return parse_only(args.package)
    if not (args.package / "package.mo").is_file():
        print(f"check_modelica: {args.package}/package.mo: no such file", file=sys.stderr)
        return 2
    include_dirs = args.include_dir or [args.package / "Resources" / "Include"]
    package = load_package(args.package)
    checker = Checker(package, include_dirs)
    problems = checker.run()
    for problem in problems:
        print(problem)
    classes = sum(1 for _ in package.classes()) if package.root else 0
    counted = ", ".join(f"{n} {what}" for what, n in checker.counts.items())
    print(f"check_modelica: {len(package.files)} files, {classes} classes ({counted}): {len(problems)} problems")
    return 1 if problems else 0


if __name__ == "__main__":
    sys.exit(main())
