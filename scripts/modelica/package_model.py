"""A Modelica package directory as classes, from the parse trees of its files.

load_package(directory) reads a package stored as a directory (Modelica Language
Specification, section 13.4: `package.mo` defines the package, each other `X.mo` the
class X, each subdirectory with a package.mo a sub-package) and returns a Package: every
class with its kind, extends clauses, components (type, prefixes, dimensions,
modification, condition), imports, external clause, function calls, connect equations
and the line of each, plus the layout problems found on the way (a file that does not
parse, a `within` that names another package, a file whose class has another name, a
package.order that does not list the package's classes exactly).

Names are looked up as in the specification's chapter 5, simplified: a name's first
identifier is searched in the class, its inherited elements and imports, then in the
enclosing classes, then among the top-level packages; the remaining identifiers are
searched inside what was found (a class, or a component's type). A name under a library
the package `uses` (annotation uses(...)) is External: it is not resolved further.
"""
import dataclasses
import pathlib

from modelica_parser import ModelicaSyntaxError, parse_file  # first: it names the package when Lark is missing

from lark import Token, Tree  # noqa: E402

# Section 4.9 and chapter 12: predefined types, and the attributes each may be modified with.
PREDEFINED_TYPES = {
    "Real": {"value", "quantity", "unit", "displayUnit", "min", "max", "start", "fixed", "nominal", "unbounded",
             "stateSelect"},
    "Integer": {"value", "quantity", "min", "max", "start", "fixed"},
    "Boolean": {"value", "quantity", "start", "fixed"},
    "String": {"value", "quantity", "start", "fixed"},
    "ExternalObject": set(),
    "StateSelect": set(), "AssertionLevel": set(), "Clock": set(),
}
# Chapters 3 and 10-12 and 16: built-in operators and functions callable by their plain name.
BUILTIN_FUNCTIONS = set("""
abs sign sqrt div mod rem ceil floor integer Integer String Boolean Real der delay cardinality homotopy
semiLinear inStream actualStream spatialDistribution getInstanceName initial terminal noEvent smooth sample
pre edge change reinit assert terminate ndims size scalar vector matrix identity diagonal zeros ones fill
linspace min max sum product transpose outerProduct symmetric cross skew cat array sin cos tan asin acos atan
atan2 sinh cosh tanh exp log log10 previous hold subSample superSample shiftSample backSample noClock interval
firstTick transition initialState activeState ticksInState timeInState Clock""".split())
BUILTIN_VARIABLES = {"time"}
BUILTIN_PACKAGES = {"Connections": {"branch", "root", "potentialRoot", "isRoot", "rooted"},
                    "StateSelect": {"never", "avoid", "default", "prefer", "always"},
                    "AssertionLevel": {"error", "warning"}}


@dataclasses.dataclass
class External:
    """A name in a library the package uses but does not contain (not resolved further)."""
    name: str


@dataclasses.dataclass
class Builtin:
    name: str


@dataclasses.dataclass
class Component:
    name: str
    type_name: str
    prefixes: set          # parameter, constant, input, output, flow, stream, discrete, inner, outer, final, ...
    dims: list             # array_subscripts trees (type's and declaration's) or []
    modification: Tree     # the `modification` tree or None
    condition: Tree        # the condition attribute's expression or None
    annotation: Tree       # the description's annotation_clause or None
    protected: bool
    owner: "ClassInfo"
    line: int


@dataclasses.dataclass
class Extends:
    type_name: str
    modification: Tree     # class_modification or None
    line: int


@dataclasses.dataclass
class Call:
    name: str
    args: Tree             # function_call_args
    line: int


@dataclasses.dataclass
class ExternalClause:
    language: str
    result: str            # the formal assigned from the return value, or None
    function: str          # the C function's name, or None for the default call
    args: list             # argument expression trees
    annotation: Tree
    line: int


@dataclasses.dataclass
class ClassInfo:
    name: str
    full_name: str
    kind: str              # class model record block connector type package function operator
    prefixes: set          # partial, encapsulated, expandable, pure, impure, operator
    file: pathlib.Path
    line: int
    parent: "ClassInfo"
    classes: dict = dataclasses.field(default_factory=dict)
    components: dict = dataclasses.field(default_factory=dict)
    extends: list = dataclasses.field(default_factory=list)
    imports: dict = dataclasses.field(default_factory=dict)       # identifier -> full name
    wildcard_imports: list = dataclasses.field(default_factory=list)
    calls: list = dataclasses.field(default_factory=list)
    references: list = dataclasses.field(default_factory=list)    # (dotted name, line) of variables used
    iterators: set = dataclasses.field(default_factory=set)       # names bound by for / comprehensions
    connects: list = dataclasses.field(default_factory=list)      # (left ref tree, right ref tree, line)
    external: ExternalClause = None
    short_base: str = None                                         # type X = Base(...)
    short_dims: list = dataclasses.field(default_factory=list)
    short_modification: Tree = None
    enumeration: list = None                                       # literal names
    annotation: Tree = None                                        # the class's own annotation


@dataclasses.dataclass
class Problem:
    file: pathlib.Path
    line: int
    what: str

    def __str__(self):
        return f"{self.file}:{self.line}: {self.what}"


def line_of(node):
    if isinstance(node, Token):
        return node.line
    return getattr(node.meta, "line", 0) if not node.meta.empty else 0


def dotted(node):
    """'A.B.C' of a name or type_specifier tree ('.A.B' when global)."""
    if node.data == "type_specifier":
        return "".join("." if isinstance(c, Tree) and c.data == "global_prefix" else dotted(c) for c in node.children)
    return ".".join(str(t) for t in node.children)


def reference_parts(node):
    """[(identifier, array_subscripts tree or None)] of a component_reference."""
    parts = []
    for child in node.children:
        if isinstance(child, Tree) and child.data == "reference_part":
            parts.append((str(child.children[0]), child.children[1] if len(child.children) > 1 else None))
    return parts


def reference_text(node):
    return ".".join(name for name, _ in reference_parts(node))


def children(node, data):
    return [c for c in node.children if isinstance(c, Tree) and c.data == data]


def child(node, data):
    found = children(node, data)
    return found[0] if found else None


def walk_expressions(node, skip=("annotation_clause", "class_definition")):
    """Every subtree, not entering annotations and nested class definitions."""
    stack = [node]
    while stack:
        current = stack.pop()
        if not isinstance(current, Tree):
            continue
        yield current
        for c in reversed(current.children):
            if isinstance(c, Tree) and c.data not in skip:
                stack.append(c)


def modification_arguments(class_modification):
    """[(name, element_modification tree, each, final)] of a class_modification."""
    out = []
    if class_modification is None:
        return out
    argument_list = child(class_modification, "argument_list")
    for argument in (argument_list.children if argument_list else []):
        if argument.data == "element_modification_or_replaceable":
            modification = child(argument, "element_modification")
            if modification is not None:
                out.append((dotted(child(modification, "name")), modification,
                            child(argument, "each") is not None, child(argument, "final") is not None))
    return out


def string_value(node):
    """The text of a STRING literal expression, escapes kept; None if not a literal."""
    if isinstance(node, Tree) and node.data == "string":
        return str(node.children[0])[1:-1]
    return None


def annotation_value(annotation_clause, name):
    """The binding expression of `name = ...` in an annotation clause, or None."""
    if annotation_clause is None:
        return None
    for argument_name, modification, _, _ in modification_arguments(child(annotation_clause, "class_modification")):
        if argument_name == name:
            inner = child(modification, "modification")
            binding = child(inner, "binding") if inner is not None else None
            return binding.children[0] if binding is not None else inner
    return None


class _ClassBuilder:
    def __init__(self, file):
        self.file = file
        self.problems = []

    def build(self, node, parent, full_prefix):
        prefixes_node = child(node, "class_prefixes")
        words = [str(t) for t in prefixes_node.children]
        kind = words[-1]
        prefixes = set(words[:-1])
        if child(node, "encapsulated") is not None:
            prefixes.add("encapsulated")
        spec = node.children[-1]
        name_token = spec.children[0]
        name = str(name_token)
        info = ClassInfo(name, f"{full_prefix}.{name}" if full_prefix else name, kind, prefixes, self.file,
                         name_token.line, parent)
        if spec.data in ("long_class_specifier", "extends_class_specifier"):
            end_name = str(spec.children[-1])
            if end_name != name:
                self.problems.append(Problem(self.file, spec.children[-1].line,
                                             f"class {name} closed by 'end {end_name}'"))
            if spec.data == "extends_class_specifier":
                info.extends.append(Extends(name, child(spec, "class_modification"), name_token.line))
            self._composition(child(spec, "composition"), info)
        elif spec.data == "short_class_specifier":
            info.short_base = dotted(child(spec, "type_specifier"))
            info.short_dims = children(spec, "array_subscripts")
            info.short_modification = child(spec, "class_modification")
            info.annotation = child(child(spec, "description"), "annotation_clause")
            self._calls(spec, info)
        elif spec.data == "enumeration_specifier":
            enum_list = child(spec, "enum_list")
            info.enumeration = [str(lit.children[0]) for lit in enum_list.children] if enum_list else []
            info.annotation = child(child(spec, "description"), "annotation_clause")
        elif spec.data == "der_class_specifier":
            info.short_base = dotted(child(spec, "type_specifier"))
        return info

    def _composition(self, composition, info):
        protected = False
        for part in composition.children:
            if part.data == "element_list":
                self._elements(part, info, protected)
            elif part.data == "public_section":
                protected = False
                self._elements(child(part, "element_list"), info, protected)
            elif part.data == "protected_section":
                protected = True
                self._elements(child(part, "element_list"), info, protected)
            elif part.data in ("equation_section", "algorithm_section"):
                self._calls(part, info)
                for node in walk_expressions(part):
                    if node.data == "connect_clause":
                        info.connects.append((node.children[0], node.children[1], line_of(node)))
            elif part.data == "external_clause":
                info.external = self._external(part)
            elif part.data == "composition_annotation":
                info.annotation = part.children[0]

    def _external(self, node):
        language = child(node, "language_specification")
        call = child(node, "external_function_call")
        result, function, args = None, None, []
        if call is not None:
            reference = child(call, "component_reference")
            result = reference_text(reference) if reference is not None else None
            function = str([c for c in call.children if isinstance(c, Token)][0])
            expression_list = child(call, "expression_list")
            args = list(expression_list.children) if expression_list is not None else []
        return ExternalClause(str(language.children[0])[1:-1] if language else "C", result, function, args,
                              child(node, "annotation_clause"), line_of(node))

    def _calls(self, node, info):
        """The calls, variable references and iterator names in node (not in annotations)."""
        not_variables = set()
        for sub in walk_expressions(node):
            if sub.data in ("function_call", "call_statement", "call_equation", "multiple_assignment"):
                callee = sub.children[-2]
                not_variables.add(id(callee))
                name = reference_text(callee) if isinstance(callee, Tree) else str(callee)
                if isinstance(callee, Tree) and child(callee, "global_prefix") is not None:
                    name = "." + name
                info.calls.append(Call(name, sub.children[-1], line_of(sub)))
            elif sub.data == "connect_clause":  # connectors: checked by the connect rule
                not_variables.update(id(c) for c in sub.children)
            elif sub.data == "for_index":
                info.iterators.add(str(sub.children[0]))
            elif sub.data == "component_reference" and id(sub) not in not_variables:
                name = reference_text(sub)
                info.references.append(("." + name if child(sub, "global_prefix") is not None else name,
                                        line_of(sub)))

    def _elements(self, element_list, info, protected):
        for element in element_list.children:
            if element.data == "import_clause":
                self._import(element, info)
            elif element.data == "extends_clause":
                info.extends.append(Extends(dotted(child(element, "type_specifier")),
                                            child(element, "class_modification"), line_of(element)))
                self._calls(element, info)
            elif element.data == "declared_element":
                prefixes = {str(c.children[0]) for c in element.children[:-1]}  # redeclare final inner outer
                target = element.children[-1]
                if target.data == "replaceable_element":
                    prefixes.add("replaceable")
                    target = target.children[0]
                if target.data == "class_definition":
                    nested = self.build(target, info, info.full_name)
                    if nested.name in info.classes or nested.name in info.components:
                        self.problems.append(Problem(self.file, nested.line,
                                                     f"{nested.name} declared twice in {info.name}"))
                    info.classes[nested.name] = nested
                else:
                    self._component_clause(target, info, prefixes, protected)

    def _import(self, element, info):
        target = element.children[0]
        if isinstance(target, Token):  # import A = B.C
            info.imports[str(target)] = dotted(element.children[1])
            return
        parts = [str(t) for t in target.children if isinstance(t, Token)]
        tail = child(target, "import_tail") or child(target, "import_all")
        if tail is None:
            info.imports[parts[-1]] = ".".join(parts)
        elif tail.data == "import_all":
            info.wildcard_imports.append(".".join(parts))
        else:
            for ident in child(tail, "import_list").children:
                info.imports[str(ident)] = ".".join(parts + [str(ident)])

    def _component_clause(self, clause, info, prefixes, protected):
        prefixes = set(prefixes) | {str(t) for t in child(clause, "type_prefix").children}
        type_name = dotted(child(clause, "type_specifier"))
        type_dims = children(clause, "array_subscripts")
        for declaration_node in child(clause, "component_list").children:
            declaration = child(declaration_node, "declaration")
            name = str(declaration.children[0])
            condition = child(declaration_node, "condition_attribute")
            description = child(declaration_node, "description")
            component = Component(name, type_name, prefixes, type_dims + children(declaration, "array_subscripts"),
                                  child(declaration, "modification"), condition.children[0] if condition else None,
                                  child(description, "annotation_clause"), protected, info,
                                  declaration.children[0].line)
            if name in info.components or name in info.classes:
                self.problems.append(Problem(self.file, component.line, f"{name} declared twice in {info.name}"))
            info.components[name] = component
        self._calls(clause, info)


@dataclasses.dataclass
class Package:
    root: ClassInfo
    directory: pathlib.Path
    uses: dict                    # library name -> version string
    problems: list
    files: list

    def classes(self):
        """Every class of the package, outermost first."""
        stack = [self.root]
        while stack:
            info = stack.pop(0)
            yield info
            stack.extend(info.classes.values())


def _read_order(path):
    return [line.strip() for line in path.read_text().splitlines() if line.strip()]


def load_package(directory):
    directory = pathlib.Path(directory)
    problems, files = [], []
    root = _load_directory(directory, None, "", problems, files)
    uses = {}
    if root is not None:
        uses_tree = annotation_value(root.annotation, "uses")
        if isinstance(uses_tree, Tree):
            for library, modification, _, _ in modification_arguments(child(uses_tree, "class_modification")):
                inner = child(modification, "modification")
                arguments = child(inner, "class_modification") if inner is not None else None
                version = annotation_value(Tree("annotation_clause", [arguments]), "version") if arguments else None
                uses[library] = string_value(version) if version is not None else None
    return Package(root, directory, uses, problems, files)


def _parse_stored(path, expected_within, problems, files):
    """The class defined by one file, or None (the problem recorded)."""
    files.append(path)
    try:
        tree = parse_file(path)
    except ModelicaSyntaxError as error:
        problems.append(Problem(path, error.line, f"syntax error at column {error.column}: {error.what}"))
        return None
    stored = tree.children[0]
    within = child(stored, "within_clause")
    within_name = dotted(within.children[0]) if within is not None and within.children else ""
    if within_name != expected_within:
        problems.append(Problem(path, line_of(within) if within is not None else 1,
                                f"'within {within_name}' but the file lies in "
                                f"{expected_within or 'no package (the top level)'}"))
    classes = children(stored, "stored_class")
    if len(classes) != 1:
        problems.append(Problem(path, 1, f"{len(classes)} class definitions; a file of a package holds exactly one"))
        if not classes:
            return None
    builder = _ClassBuilder(path)
    info = builder.build(child(classes[0], "class_definition"), None, expected_within)
    problems.extend(builder.problems)
    return info


def _load_directory(directory, parent, prefix, problems, files):
    package_file = directory / "package.mo"
    info = _parse_stored(package_file, prefix, problems, files)
    if info is None:
        return None
    info.parent = parent
    if info.name != directory.name:
        problems.append(Problem(package_file, info.line, f"package {info.name} stored in directory {directory.name}"))
    if info.kind != "package":
        problems.append(Problem(package_file, info.line, f"package.mo defines a {info.kind}, not a package"))
    in_package_file = list(info.classes)
    unreadable = set()  # classes whose file did not parse (already reported): not missing
    for entry in sorted(directory.iterdir()):
        if entry.is_dir() and (entry / "package.mo").is_file():
            sub = _load_directory(entry, info, info.full_name, problems, files)
        elif entry.is_file() and entry.suffix == ".mo" and entry.name != "package.mo":
            sub = _parse_stored(entry, info.full_name, problems, files)
            if sub is not None and sub.name != entry.stem:
                problems.append(Problem(entry, sub.line, f"class {sub.name} stored in {entry.name}"))
        else:
            continue
        if sub is None:
            unreadable.add(entry.stem)
            continue
        sub.parent = info
        if sub.name in info.classes:
            problems.append(Problem(entry, sub.line, f"{sub.name} defined twice in {info.full_name}"))
        info.classes[sub.name] = sub
    order_file = directory / "package.order"
    if order_file.is_file():
        order = _read_order(order_file)
        named = set(info.classes) | {n for n, c in info.components.items() if "constant" in c.prefixes} | unreadable
        for index, name in enumerate(order, start=1):
            if name not in named:
                problems.append(Problem(order_file, index, f"{name} is no class or constant of {info.full_name}"))
            elif order.count(name) > 1 and order.index(name) + 1 != index:
                problems.append(Problem(order_file, index, f"{name} listed twice"))
        for name in sorted(named - set(order)):
            problems.append(Problem(order_file, len(order) + 1,
                                    f"{name} of {info.full_name} is missing (the order of unlisted classes is "
                                    "tool-specific)"))
        listed = [name for name in order if name in in_package_file]
        expected = [name for name in in_package_file if name in order]
        if listed != expected:
            problems.append(Problem(order_file, 1, f"the classes of {package_file.name} are listed as "
                                                   f"{', '.join(listed)}; package.mo defines them in the order "
                                                   f"{', '.join(expected)}"))
    return info


class Resolver:
    """Name lookup in a loaded package (see the module docstring)."""

    def __init__(self, package, empty_external_bases=()):
        self.package = package
        self.roots = {package.root.name: package.root} if package.root else {}
        self.external_roots = set(package.uses)
        # External base classes known to add no elements (icons): lookups may pass them.
        self.empty_external_bases = tuple(empty_external_bases)

    def _base(self, info, extends):
        scope = info.parent if extends.type_name == info.name else info
        return self.resolve(extends.type_name, scope, through_inherited=False)

    def find_element(self, info, ident, seen=None):
        """The class, component or enumeration literal `ident` declared in or inherited by
        info; External when it may come from an external base; None when absent."""
        seen = seen or set()
        if id(info) in seen:
            return None
        seen.add(id(info))
        if ident in info.classes:
            return info.classes[ident]
        if ident in info.components:
            return info.components[ident]
        if info.enumeration is not None and ident in info.enumeration:
            return Builtin(f"{info.full_name}.{ident}")
        bases = [self._base(info, e) for e in info.extends]
        if info.short_base:
            bases.append(self.resolve(info.short_base, info.parent))
        for base in bases:
            if isinstance(base, ClassInfo):
                found = self.find_element(base, ident, seen)
                if found is not None:
                    return found
            elif isinstance(base, External) and not base.name.startswith(self.empty_external_bases):
                return External(f"{base.name}.{ident}")
        return None

    def lookup_first(self, ident, scope, through_inherited=True):
        current = scope
        while current is not None:
            found = self.find_element(current, ident) if through_inherited else (
                current.classes.get(ident) or current.components.get(ident))
            if found is not None:
                return found
            if ident in current.imports:
                return self.resolve(current.imports[ident], None)
            for wildcard in current.wildcard_imports:
                target = self.resolve(wildcard, None)
                if isinstance(target, ClassInfo) and self.find_element(target, ident) is not None:
                    return self.find_element(target, ident)
                if isinstance(target, External):
                    return External(f"{wildcard}.{ident}")
            current = current.parent
            through_inherited = True
        if ident in self.roots:
            return self.roots[ident]
        if ident in self.external_roots:
            return External(ident)
        if ident in PREDEFINED_TYPES or ident in BUILTIN_FUNCTIONS or ident in BUILTIN_VARIABLES:
            return Builtin(ident)
        if ident in BUILTIN_PACKAGES:
            return Builtin(ident)
        return None

    def type_of(self, component):
        return self.resolve(component.type_name, component.owner)

    def resolve(self, name, scope, through_inherited=True):
        """What `name` (dotted, '.'-prefixed when global) denotes seen from class `scope`:
        a ClassInfo, a Component, External, Builtin, or None when it does not exist."""
        if name.startswith("."):
            name, scope = name[1:], None
        parts = name.split(".")
        found = self.lookup_first(parts[0], scope, through_inherited)
        for index, ident in enumerate(parts[1:], start=1):
            if found is None:
                return None
            if isinstance(found, External):
                return External(".".join([found.name] + parts[index:]))
            if isinstance(found, Builtin):
                members = BUILTIN_PACKAGES.get(found.name)
                return Builtin(f"{found.name}.{ident}") if members and ident in members and index == len(parts) - 1 \
                    else None
            if isinstance(found, Component):
                found = self.type_of(found)
                if found is None or isinstance(found, Builtin):
                    return None if found is None else Builtin(".".join([found.name] + parts[index:]))
                if isinstance(found, External):
                    return External(".".join([found.name] + parts[index:]))
            found = self.find_element(found, ident)
        return found

    def extends_external_object(self, info):
        return any(self._base(info, e) == Builtin("ExternalObject") for e in info.extends)
