#!/usr/bin/env python3
"""Checks an FMU's modelDescription.xml against the FMI 2.0 rules a master relies on.

Usage: check_model_description.py FMU_OR_XML [...]. Exit 0 when every file passes, 1 with
one line per violation otherwise. Rules (FMI 2.0 standard, section 2.2 "FMU Description
Schema"):
  - fmiVersion is "2.0"; the guid and a CoSimulation modelIdentifier are present;
  - variable names are unique;
  - value references are unique within each base type (Real, Integer, Boolean, String);
  - causality and variability form one of the allowed combinations of the standard's
    table of causality x variability, and initial is one of those allowed for that
    combination (absent means the combination's default);
  - a start value is given exactly when initial is exact or approx, or causality is input,
    and never when initial is calculated or causality is independent;
  - every unit a Real uses is declared in UnitDefinitions, each unit once;
  - ModelStructure's Outputs list exactly the output variables (1-based indices), and
    every InitialUnknowns index points at a variable.
"""
import sys
import xml.etree.ElementTree as ET
import zipfile

CAUSALITIES = ("parameter", "calculatedParameter", "input", "output", "local", "independent")
VARIABILITIES = ("constant", "fixed", "tunable", "discrete", "continuous")

# Allowed initial values per (variability, causality); the first is the default. A pair
# missing here is not an allowed combination. An empty tuple: initial must be absent.
INITIAL = {
    ("fixed", "parameter"): ("exact",),
    ("tunable", "parameter"): ("exact",),
    ("fixed", "calculatedParameter"): ("calculated", "approx"),
    ("tunable", "calculatedParameter"): ("calculated", "approx"),
    ("discrete", "input"): (),
    ("continuous", "input"): (),
    ("constant", "output"): ("exact",),
    ("discrete", "output"): ("calculated", "exact", "approx"),
    ("continuous", "output"): ("calculated", "exact", "approx"),
    ("constant", "local"): ("exact",),
    ("fixed", "local"): ("calculated", "approx"),
    ("tunable", "local"): ("calculated", "approx"),
    ("discrete", "local"): ("calculated", "exact", "approx"),
    ("continuous", "local"): ("calculated", "exact", "approx"),
    ("continuous", "independent"): (),
}
TYPES = ("Real", "Integer", "Boolean", "String", "Enumeration")


def model_description(path):
    if path.endswith(".xml"):
        return ET.parse(path).getroot()
    with zipfile.ZipFile(path) as archive:
        return ET.fromstring(archive.read("modelDescription.xml"))


def check(root):
    errors = []
    if root.get("fmiVersion") != "2.0":
        errors.append("fmiVersion is %r, not '2.0'" % root.get("fmiVersion"))
    if not root.get("guid"):
        errors.append("no guid")
    cs = root.find("CoSimulation")
    if cs is None or not cs.get("modelIdentifier"):
        errors.append("no CoSimulation modelIdentifier")

    declared_units = []
    unit_definitions = root.find("UnitDefinitions")
    if unit_definitions is not None:
        declared_units = [u.get("name") for u in unit_definitions.findall("Unit")]
    for name in set(declared_units):
        if declared_units.count(name) > 1:
            errors.append("unit %r declared %d times" % (name, declared_units.count(name)))

    variables = root.find("ModelVariables")
    if variables is None:
        return errors + ["no ModelVariables"]
    names = set()
    references = {}
    outputs = []
    scalars = variables.findall("ScalarVariable")
    for index, v in enumerate(scalars, start=1):
        name = v.get("name")
        where = "variable %d %r" % (index, name)
        if not name:
            errors.append("%s has no name" % where)
        elif name in names:
            errors.append("%s: name used twice" % where)
        names.add(name)
        typed = [child for child in v if child.tag in TYPES]
        if len(typed) != 1:
            errors.append("%s: needs exactly one type element, has %d" % (where, len(typed)))
            continue
        element = typed[0]
        base = "Integer" if element.tag == "Enumeration" else element.tag
        reference = v.get("valueReference")
        if reference is None or not reference.isdigit():
            errors.append("%s: valueReference %r is not an unsigned integer" % (where, reference))
        elif (base, reference) in references:
            errors.append("%s: %s value reference %s already used by %r" % (where, base, reference,
                                                                             references[(base, reference)]))
        else:
            references[(base, reference)] = name
        causality = v.get("causality", "local")
        variability = v.get("variability", "continuous")
        if causality not in CAUSALITIES or variability not in VARIABILITIES:
            errors.append("%s: unknown causality %r or variability %r" % (where, causality, variability))
            continue
        if element.tag != "Real" and variability == "continuous":
            errors.append("%s: only a Real may be continuous (%s)" % (where, element.tag))
        allowed = INITIAL.get((variability, causality))
        if allowed is None:
            errors.append("%s: variability %r with causality %r is not an allowed combination" %
                          (where, variability, causality))
            continue
        initial = v.get("initial")
        if initial is not None and initial not in allowed:
            errors.append("%s: initial %r not allowed for %s/%s (allowed: %s)" %
                          (where, initial, variability, causality, ", ".join(allowed) or "none"))
            continue
        effective = initial if initial is not None else (allowed[0] if allowed else None)
        has_start = element.get("start") is not None
        needs_start = effective in ("exact", "approx") or causality == "input"
        forbids_start = effective == "calculated" or causality == "independent"
        if needs_start and not has_start:
            errors.append("%s: needs a start value (initial %s, causality %s)" % (where, effective, causality))
        if forbids_start and has_start:
            errors.append("%s: must not have a start value (initial %s, causality %s)" % (where, effective, causality))
        unit = element.get("unit")
        if element.tag == "Real" and unit is not None and unit not in declared_units:
            errors.append("%s: unit %r is not in UnitDefinitions" % (where, unit))
        if causality == "output":
            outputs.append(index)

    structure = root.find("ModelStructure")
    listed = []
    if structure is not None and structure.find("Outputs") is not None:
        listed = [int(u.get("index")) for u in structure.find("Outputs").findall("Unknown")]
    if sorted(listed) != outputs:
        errors.append("ModelStructure/Outputs lists %s, the outputs are %s" % (listed, outputs))
    if structure is not None and structure.find("InitialUnknowns") is not None:
        for u in structure.find("InitialUnknowns").findall("Unknown"):
            if not 1 <= int(u.get("index")) <= len(scalars):
                errors.append("InitialUnknowns index %s names no variable" % u.get("index"))
    return errors


def main(paths):
    failed = False
    for path in paths:
        errors = check(model_description(path))
        for error in errors:
            print("%s: %s" % (path, error))
        failed = failed or bool(errors)
        if not errors:
            print("%s: valid FMI 2.0 model description" % path)
    return 1 if failed or not paths else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
