"""The settings table (plugin/vtkWhittedSettings.h) against everything else that states a setting:

  - the Whitted view's proxy (xml/WhittedView.xml): a property of the setting's name with command Set<Name>, the
    table's default, a range domain of the table's range (a boolean domain for booleans) and the table's
    documentation as its tooltip;
  - the view itself: Set<Name>/Get<Name> exist, and a value outside the range comes back clamped to the range's
    nearest end (for a pass setting that clamp is the pass's own, so the view forwarded the value to the pass).
The sources (the XML as text, the view's and the pass's generated accessors, plugin/README.md) are checked against
the same table in both builds by testing/settings/check_settings.py.

    pvbatch test_settings.py --plugin P

The view is probed through a proxy defined here from the table (one property per setting plus an information
property reading it back), created from the same class as the Whitted view.
"""
import argparse
import os
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)
sys.path.insert(0, os.path.join(HERE, "..", "settings"))
import whitted_pvtest as wt  # noqa: E402
from settings_table import read_table, same, words  # noqa: E402

ap = argparse.ArgumentParser()
ap.add_argument("--plugin", required=True)
args = ap.parse_args()

problems = []
try:
    rows = read_table()
except ValueError as e:
    wt.fail(str(e))
print("settings table: %d rows" % len(rows))

from paraview import servermanager as sm  # noqa: E402
from paraview.simple import CreateView  # noqa: E402

wt.load_plugin(args.plugin)

# The view's defaults: the table's, except where VTK_WHITTED_VIEW_DEFAULTS gives the view its own
view_default = {row.name: row.view_default for row in rows}
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
    if not same(prop.GetElement(0), view_default[name]):
        problems.append("%s: XML default %s, table (view default) %s" % (name, prop.GetElement(0), view_default[name]))
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
# 2. The view's setters and getters: forwarding and clamps, through a probe proxy of the view's class
probe_xml = ['<ServerManagerConfiguration><ProxyGroup name="whitted_tests">',
             '<Proxy name="SettingsProbe" class="vtkPVWhittedView">']
for owner, typ, name, default, lo, hi, doc in rows:
    kind, helper = ("Double", "SimpleDoubleInformationHelper") if typ == "double" else ("Int", "SimpleIntInformationHelper")
    probe_xml.append('<%sVectorProperty name="%s" command="Set%s" number_of_elements="1" default_values="%r" />'
                     % (kind, name, name, view_default[name]))
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
    if not same(got, view_default[name]):
        problems.append("%s: the view's default is %s, the table's %s" % (name, got, view_default[name]))
    default = view_default[name]
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

if problems:
    wt.fail("%d disagreements with the settings table:\n  " % len(problems) + "\n  ".join(problems))
print("OK: %d settings agree in the table, the XML, the view and the pass" % len(rows))
