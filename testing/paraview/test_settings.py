"""The settings table (plugin/vtkWhittedSettings.h) against everything else that states a setting:

  - the Whitted view's proxy (xml/WhittedView.xml): a property of the setting's name with command Set<Name>, the
    table's default, a range domain of the table's range (a boolean domain for booleans) and the table's
    documentation as its tooltip;
  - the view itself: Set<Name>/Get<Name> exist, and a value outside the range comes back clamped to the range's
    nearest end (for a pass setting that clamp is the pass's own, so the view forwarded the value to the pass);
  - the settings tables of plugin/README.md: default and range.

    pvbatch test_settings.py --plugin P

The view is probed through a proxy defined here from the table (one property per setting plus an information
property reading it back), created from the same class as the Whitted view.
"""
import argparse
import math
import os
import re
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import whitted_pvtest as wt  # noqa: E402

ROOT = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..")

ap = argparse.ArgumentParser()
ap.add_argument("--plugin", required=True)
args = ap.parse_args()


def read_table():
    """The rows of VTK_WHITTED_SETTINGS: (owner, type, name, default, minimum, maximum, documentation)."""
    text = open(os.path.join(ROOT, "plugin", "vtkWhittedSettings.h")).read()
    body = text[text.index("#define VTK_WHITTED_SETTINGS(X)"):text.index("// clang-format on")]
    value = {"true": 1.0, "false": 0.0}
    rows = []
    for m in re.finditer(r'X\((\w+), (\w+), (\w+), ([^,]+), ([^,]+), ([^,]+),((?:[\s\\]*"(?:[^"\\]|\\.)*")+)\)', body):
        owner, typ, name = m.group(1), m.group(2), m.group(3)
        numbers = []
        for expr in m.group(4, 5, 6):
            expr = expr.strip()
            numbers.append(value[expr] if expr in value else float(eval(expr, {"__builtins__": {}})))
        doc = "".join(re.findall(r'"((?:[^"\\]|\\.)*)"', m.group(7)))
        rows.append((owner, typ, name, numbers[0], numbers[1], numbers[2], doc))
    if len(rows) != body.count("  X("):
        wt.fail("read %d rows of the settings table, it has %d" % (len(rows), body.count("  X(")))
    return rows


def same(a, b):
    return math.isclose(float(a), float(b), rel_tol=1e-12, abs_tol=1e-15)


def words(text):
    return " ".join(text.split())


problems = []
rows = read_table()
print("settings table: %d rows" % len(rows))

from paraview import servermanager as sm  # noqa: E402
from paraview.simple import CreateView  # noqa: E402

wt.load_plugin(args.plugin)

# 1. The view's XML: command, default, domain, documentation
view = CreateView("WhittedRayTraceView")
for owner, typ, name, default, lo, hi, doc in rows:
    prop = view.SMProxy.GetProperty(name)
    if prop is None:
        problems.append("%s: no property of the Whitted view" % name)
        continue
    if prop.GetCommand() != "Set" + name:
        problems.append("%s: XML command %s" % (name, prop.GetCommand()))
    prop.ResetToXMLDefaults()
    if not same(prop.GetElement(0), default):
        problems.append("%s: XML default %s, table %s" % (name, prop.GetElement(0), default))
    if typ == "bool":
        if prop.GetDomain("bool") is None:
            problems.append("%s: no boolean domain in the XML" % name)
    else:
        domain = prop.GetDomain("range")
        if domain is None or not (same(domain.GetMinimum(0), lo) and same(domain.GetMaximum(0), hi)):
            problems.append("%s: XML range %s, table %s - %s" % (
                name, domain and (domain.GetMinimum(0), domain.GetMaximum(0)), lo, hi))
    xml_doc = prop.GetDocumentation().GetDescription() if prop.GetDocumentation() else ""
    if words(xml_doc) != words(doc):
        problems.append("%s: XML documentation\n    %s\n  differs from the table's\n    %s" % (
            name, words(xml_doc), words(doc)))
# and no Whitted setting in the view's XML groups outside the table
names = {r[2] for r in rows}
for group in ("Whitted Ray Tracing", "Whitted Interaction and Parallel"):
    for i in range(view.SMProxy.GetNumberOfPropertyGroups()):
        g = view.SMProxy.GetPropertyGroup(i)
        if g.GetXMLLabel() == group:
            for k in range(g.GetNumberOfProperties()):
                if g.GetPropertyName(k) not in names:
                    problems.append("%s: in the XML group '%s' but not in the settings table" % (
                        g.GetPropertyName(k), group))

# 2. The view's setters and getters: forwarding and clamps, through a probe proxy of the view's class
probe_xml = ['<ServerManagerConfiguration><ProxyGroup name="whitted_tests">',
             '<Proxy name="SettingsProbe" class="vtkPVWhittedView">']
for owner, typ, name, default, lo, hi, doc in rows:
    kind, helper = ("Double", "SimpleDoubleInformationHelper") if typ == "double" else ("Int", "SimpleIntInformationHelper")
    probe_xml.append('<%sVectorProperty name="%s" command="Set%s" number_of_elements="1" default_values="%r" />'
                     % (kind, name, name, default))
    probe_xml.append('<%sVectorProperty name="%sInfo" command="Get%s" information_only="1"><%s /></%sVectorProperty>'
                     % (kind, name, name, helper, kind))
probe_xml.append("</Proxy></ProxyGroup></ServerManagerConfiguration>")
pxm = sm.vtkSMProxyManager.GetProxyManager().GetActiveSessionProxyManager()
pxm.GetProxyDefinitionManager().LoadConfigurationXMLFromString("".join(probe_xml))
probe = pxm.NewProxy("whitted_tests", "SettingsProbe")


def set_and_get(name, v):
    probe.GetProperty(name).SetElement(0, v)
    probe.UpdateVTKObjects()
    probe.UpdatePropertyInformation()
    return probe.GetProperty(name + "Info").GetElement(0)


for owner, typ, name, default, lo, hi, doc in rows:
    probe.UpdatePropertyInformation()
    got = probe.GetProperty(name + "Info").GetElement(0)
    if not same(got, default):
        problems.append("%s: the view's default is %s, the table's %s" % (name, got, default))
    if typ == "bool":
        checks = [(1.0 - default, 1.0 - default), (default, default)]
    else:
        step = 1 if typ == "int" else 0.5 * (hi - lo)
        checks = [(hi + step, hi), (lo - step, lo), (default, default)]
    for value, expected in checks:
        v = int(value) if typ != "double" else value
        got = set_and_get(name, v)
        if not same(got, expected):
            problems.append("%s (%s): set %s through the view, read %s, expected %s" % (
                name, owner, v, got, expected))
print("view: %d settings set and read back" % len(rows))

# 3. plugin/README.md: every setting's row with the table's default and range
readme = open(os.path.join(ROOT, "plugin", "README.md")).read()


def cell_value(cell):
    cell = cell.strip()
    if cell in ("on", "off"):
        return 1.0 if cell == "on" else 0.0
    if "/" in cell:
        a, b = cell.split("/")
        return float(a) / float(b)
    return float(cell)


for owner, typ, name, default, lo, hi, doc in rows:
    m = re.search(r"^\| `%s` \|([^|]*)\|([^|]*)\|" % name, readme, re.M)
    if not m:
        problems.append("%s: no row in the settings tables of plugin/README.md" % name)
        continue
    readme_default, readme_range = m.group(1).strip(), m.group(2).strip()
    if not same(cell_value(readme_default), default):
        problems.append("%s: README default %s, table %s" % (name, readme_default, default))
    expected_range = "on/off" if typ == "bool" else None
    if expected_range:
        ok = readme_range == expected_range
    else:
        parts = readme_range.split(" - ")
        ok = len(parts) == 2 and same(cell_value(parts[0]), lo) and same(cell_value(parts[1]), hi)
    if not ok:
        problems.append("%s: README range %s, table %s - %s" % (name, readme_range, lo, hi))

if problems:
    wt.fail("%d disagreements with the settings table:\n  " % len(problems) + "\n  ".join(problems))
print("OK: %d settings agree in the table, the XML, the view, the pass and plugin/README.md" % len(rows))
