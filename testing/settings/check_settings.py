"""The settings table (plugin/vtkWhittedSettings.h) against what states a setting by hand, from the sources: runs in
the VTK build (vtk.settings.Sources) and in the ParaView build (paraview.settings.sources), so a disagreement fails
both suites.

  python3 check_settings.py [--wrapped]

- xml/WhittedView.xml, the Whitted view's proxy: for every row a property of the row's name, label (the name
  spaced) and element (IntVectorProperty for int and bool, DoubleVectorProperty for double), command Set<Name>,
  one element, the table's default_values (the view's, where VTK_WHITTED_VIEW_DEFAULTS lists one), a range domain of the table's range (a boolean domain for booleans),
  the table's documentation as its tooltip, in one of the view's Whitted property groups; and those groups hold
  nothing else.
- vtkPVWhittedView: the Pass rows' forwarders and the View rows' members and accessors are generated from the
  table (the expansions must be there, and no Pass row forwarded by hand); each View boolean has its own setter.
- vtkWhittedPass: its accessors and members are generated from the table. With --wrapped (the VTK build: Python
  sees the module `whitted`): the Python-wrapped pass has every Pass row's Set/Get (numbers: Get<Name>MinValue and
  MaxValue equal to the table's range; booleans: On/Off) and the table's defaults, i.e. VTK's wrapper saw the
  macro-generated methods.
- plugin/README.md: every setting's row, default and range.
The ParaView build also runs testing/paraview/test_settings.py: the view's behaviour (defaults, clamps, forwarding)
and the XML as ParaView's server manager reads it.
"""
import argparse
import os
import re
import sys
import xml.etree.ElementTree as ET

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from settings_table import ROOT, label, read_table, readme_problems, same, words  # noqa: E402


def xml_problems(rows):
    problems = []
    tree = ET.parse(os.path.join(ROOT, "xml", "WhittedView.xml"))
    view = tree.find(".//RenderViewProxy[@name='WhittedRayTraceView']")
    kinds = {"bool": "IntVectorProperty", "int": "IntVectorProperty", "double": "DoubleVectorProperty"}
    domains = {"bool": "BooleanDomain", "int": "IntRangeDomain", "double": "DoubleRangeDomain"}
    for row in rows:
        props = view.findall("*[@name='%s']" % row.name)
        if len(props) != 1:
            problems.append("%s: %d properties of this name in the view's XML" % (row.name, len(props)))
            continue
        p = props[0]
        for what, got, expected in (("element", p.tag, kinds[row.type]), ("command", p.get("command"), "Set" + row.name),
                                    ("label", p.get("label"), label(row.name)),
                                    ("number_of_elements", p.get("number_of_elements"), "1")):
            if got != expected:
                problems.append("%s: XML %s %s, expected %s" % (row.name, what, got, expected))
        default = p.get("default_values")
        if default is None or not same(default, row.view_default):
            problems.append("%s: XML default %s, table (view default) %s" % (row.name, default, row.view_default))
        domain = p.find(domains[row.type])
        if domain is None:
            problems.append("%s: no %s in the XML" % (row.name, domains[row.type]))
        elif row.type != "bool" and not (same(domain.get("min"), row.minimum) and same(domain.get("max"), row.maximum)):
            problems.append("%s: XML range %s - %s, table %s - %s" % (
                row.name, domain.get("min"), domain.get("max"), row.minimum, row.maximum))
        doc = p.find("Documentation")
        if doc is None or words(doc.text or "") != words(row.doc):
            problems.append("%s: XML documentation\n    %s\n  differs from the table's\n    %s" % (
                row.name, words(doc.text or "") if doc is not None else None, words(row.doc)))
    # The view's Whitted groups: every setting in one, nothing else in them
    names = [row.name for row in rows]
    grouped = []
    for group in view.findall("PropertyGroup"):
        if group.get("label", "").startswith("Whitted"):
            for p in group.findall("Property"):
                grouped.append(p.get("name"))
                if p.get("name") not in names:
                    problems.append("%s: in the XML group '%s' but not in the settings table" % (
                        p.get("name"), group.get("label")))
    for name in names:
        if grouped.count(name) != 1:
            problems.append("%s: in %d of the view's Whitted property groups" % (name, grouped.count(name)))
    return problems


def source(*parts):
    return open(os.path.join(ROOT, *parts)).read()


def expands(text, macro):
    return re.search(r"^\s*VTK_WHITTED_SETTINGS\(%s\)" % macro, text, re.M) is not None


def view_problems(rows):
    problems = []
    header = source("plugin", "paraview", "Views", "vtkPVWhittedView.h")
    body = source("plugin", "paraview", "Views", "vtkPVWhittedView.cxx")
    for text, macro, what in ((header, "VTK_WHITTED_VIEW_FORWARDERS", "the Pass rows' forwarders (declarations)"),
                              (body, "VTK_WHITTED_VIEW_FORWARD", "the Pass rows' forwarders (definitions)"),
                              (header, "VTK_WHITTED_VIEW_ACCESSORS", "the View rows' accessors"),
                              (header, "VTK_WHITTED_VIEW_MEMBERS", "the View rows' members"),
                              (body, "VTK_WHITTED_VIEW_PRINT", "the View rows' PrintSelf")):
        if not expands(text, macro):
            problems.append("vtkPVWhittedView: %s not generated (no VTK_WHITTED_SETTINGS(%s))" % (what, macro))
    for row in rows:
        by_hand = re.search(r"(void Set%s\(|vtkSet\w*Macro\(\s*%s\s*,)" % (row.name, row.name), header)
        if row.type == "bool" and row.owner == "View":
            if not by_hand:
                problems.append("%s: vtkPVWhittedView declares no setter (View booleans have their own)" % row.name)
        elif by_hand:
            problems.append("%s: vtkPVWhittedView declares Set%s by hand; it is generated from the table" % (
                row.name, row.name))
    return problems


def pass_problems(rows, wrapped):
    problems = []
    header = source("plugin", "vtkWhittedPass.h")
    for macro in ("VTK_WHITTED_PASS_ACCESSORS", "VTK_WHITTED_PASS_MEMBERS"):
        if not expands(header, macro):
            problems.append("vtkWhittedPass: no VTK_WHITTED_SETTINGS(%s)" % macro)
    if not wrapped:
        return problems
    from whitted import vtkWhittedPass
    p = vtkWhittedPass()
    for row in rows:
        n = row.name
        needed = ["Set" + n, "Get" + n]
        needed += [n + "On", n + "Off"] if row.type == "bool" else ["Get%sMinValue" % n, "Get%sMaxValue" % n]
        if row.owner != "Pass":
            if hasattr(p, "Set" + n):
                problems.append("%s: a View row, but the wrapped pass has Set%s" % (n, n))
            continue
        missing = [m for m in needed if not hasattr(p, m)]
        if missing:
            problems.append("%s: the Python-wrapped pass lacks %s" % (n, ", ".join(missing)))
            continue
        if not same(getattr(p, "Get" + n)(), row.default):
            problems.append("%s: the wrapped pass's default is %s, table %s" % (n, getattr(p, "Get" + n)(), row.default))
        if row.type != "bool" and not (same(getattr(p, "Get%sMinValue" % n)(), row.minimum)
                                       and same(getattr(p, "Get%sMaxValue" % n)(), row.maximum)):
            problems.append("%s: the wrapped pass's range %s - %s, table %s - %s" % (
                n, getattr(p, "Get%sMinValue" % n)(), getattr(p, "Get%sMaxValue" % n)(), row.minimum, row.maximum))
    return problems


ap = argparse.ArgumentParser()
ap.add_argument("--wrapped", action="store_true", help="also check the Python-wrapped vtkWhittedPass (module whitted)")
args = ap.parse_args()
rows = read_table()
problems = xml_problems(rows) + view_problems(rows) + pass_problems(rows, args.wrapped) + readme_problems(rows)
if problems:
    print("FAILED: %d disagreements with the settings table:\n  %s" % (len(problems), "\n  ".join(problems)))
    sys.exit(1)
print("OK: %d settings (%d of the pass, %d of the view) agree in the table, xml/WhittedView.xml, vtkPVWhittedView, "
      "vtkWhittedPass%s and plugin/README.md" % (len(rows), sum(r.owner == "Pass" for r in rows),
                                                 sum(r.owner == "View" for r in rows),
                                                 " (Python-wrapped)" if args.wrapped else ""))
