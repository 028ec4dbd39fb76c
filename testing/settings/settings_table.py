"""The settings table (plugin/vtkWhittedSettings.h) as Python, for the tests that check what states it by hand:
check_settings.py (both builds) and testing/paraview/test_settings.py (ParaView build)."""
import math
import os
import re

ROOT = os.path.normpath(os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", ".."))


class Row:
    """One row of VTK_WHITTED_SETTINGS: owner (Pass or View), type (bool, int, double), name, default, minimum,
    maximum (numbers; booleans 0 and 1) and documentation (one string)."""

    def __init__(self, owner, typ, name, default, lo, hi, doc):
        self.owner, self.type, self.name = owner, typ, name
        self.default, self.minimum, self.maximum, self.doc = default, lo, hi, doc
        self.view_default = default  # the ParaView view's default (VTK_WHITTED_VIEW_DEFAULTS), if it differs

    def __iter__(self):  # owner, type, name, default, minimum, maximum, documentation
        return iter((self.owner, self.type, self.name, self.default, self.minimum, self.maximum, self.doc))


def read_table(root=ROOT):
    """The rows of VTK_WHITTED_SETTINGS, in order; raises ValueError if a row cannot be read."""
    text = open(os.path.join(root, "plugin", "vtkWhittedSettings.h")).read()
    body = text[text.index("#define VTK_WHITTED_SETTINGS(X)"):text.index("// clang-format on")]
    value = {"true": 1.0, "false": 0.0}
    rows = []
    for m in re.finditer(r'X\((\w+), (\w+), (\w+), ([^,]+), ([^,]+), ([^,]+),((?:[\s\\]*"(?:[^"\\]|\\.)*")+)\)', body):
        numbers = []
        for expr in m.group(4, 5, 6):
            expr = expr.strip()
            numbers.append(value[expr] if expr in value else float(eval(expr, {"__builtins__": {}})))
        doc = "".join(re.findall(r'"((?:[^"\\]|\\.)*)"', m.group(7)))
        rows.append(Row(m.group(1), m.group(2), m.group(3), numbers[0], numbers[1], numbers[2], doc))
    if len(rows) != body.count("  X("):
        raise ValueError("read %d rows of the settings table, it has %d" % (len(rows), body.count("  X(")))
    overrides = text[text.index("#define VTK_WHITTED_VIEW_DEFAULTS(X)"):]
    overrides = overrides[:overrides.index("// clang-format on")]
    by_name = {row.name: row for row in rows}
    for m in re.finditer(r"X\((\w+), ([^)]+)\)", overrides):
        expr = m.group(2).strip()
        if m.group(1) not in by_name or by_name[m.group(1)].owner != "Pass":
            raise ValueError("VTK_WHITTED_VIEW_DEFAULTS: %s is no Pass row of the table" % m.group(1))
        by_name[m.group(1)].view_default = value[expr] if expr in value else float(eval(expr, {"__builtins__": {}}))
    return rows


def same(a, b):
    return math.isclose(float(a), float(b), rel_tol=1e-12, abs_tol=1e-15)


def words(text):
    return " ".join(text.split())


def label(name):
    """The GUI label of a setting: its name with a space before each capital (MaxDepth -> Max Depth)."""
    return re.sub(r"(?<=[a-z])(?=[A-Z])", " ", name)


def readme_problems(rows, root=ROOT):
    """Disagreements of the settings tables of plugin/README.md with the table: each setting's row, default and
    range."""
    readme = open(os.path.join(root, "plugin", "README.md")).read()

    def cell_value(cell):
        cell = cell.strip()
        if cell in ("on", "off"):
            return 1.0 if cell == "on" else 0.0
        if "/" in cell:
            a, b = cell.split("/")
            return float(a) / float(b)
        return float(cell)

    problems = []
    for row in rows:
        m = re.search(r"^\| `%s` \|([^|]*)\|([^|]*)\|" % row.name, readme, re.M)
        if not m:
            problems.append("%s: no row in the settings tables of plugin/README.md" % row.name)
            continue
        readme_default, readme_range = m.group(1).strip(), m.group(2).strip()
        view = re.match(r"(.*) \(view: (.*)\)$", readme_default)
        pass_cell, view_cell = (view.group(1), view.group(2)) if view else (readme_default, readme_default)
        if not same(cell_value(pass_cell), row.default) or not same(cell_value(view_cell), row.view_default):
            problems.append("%s: README default %s, table %s (view %s)" % (
                row.name, readme_default, row.default, row.view_default))
        if row.type == "bool":
            ok = readme_range == "on/off"
        else:
            parts = readme_range.split(" - ")
            ok = len(parts) == 2 and same(cell_value(parts[0]), row.minimum) and same(cell_value(parts[1]), row.maximum)
        if not ok:
            problems.append("%s: README range %s, table %s - %s" % (row.name, readme_range, row.minimum, row.maximum))
    return problems
