#!/usr/bin/env python3
"""The layering check: every include goes down the pipeline, never up.

core/ is in folders by pipeline stage, each a layer that uses only the layers below it (and itself):
    util <- geometry <- accel <- scene <- shading <- image <- scenes <- apps
Tests (*_test.cpp) sit beside the code they test and may include any core layer. core/ never includes plugin/
or VTK; the VTK module (plugin/*) never includes the ParaView classes (plugin/paraview/, vtkPV*, vtkSM*).
Files stay small enough to read: no core file above 450 lines, no plugin file above 600.

Usage: check_layers.py [ROOT]   (ROOT: the source tree, default: two folders up from this script)
Exit status 0 if every include respects the layers, 1 (with one line per violation) otherwise.
check_layers.py --self-test: the negative control: a copy of ROOT's core/ and plugin/ with one deliberate upward
include each (util including image, core including VTK, the VTK module including a ParaView class), one core file
and one plugin file grown past their limits must fail with exactly those violations, and the unmodified copy must
pass.
"""
import os
import re
import shutil
import sys
import tempfile

LAYERS = ["util", "geometry", "accel", "scene", "shading", "image", "scenes", "apps"]
SOURCE = (".h", ".hpp", ".cpp", ".cxx", ".cc")
MAX_LINES = {"core": 450, "plugin": 600}
INCLUDE = re.compile(r'^\s*#\s*include\s*([<"])([^>"]+)[>"]', re.M)


def sources(folder):
    for dirpath, _, names in os.walk(folder):
        for name in sorted(names):
            if name.endswith(SOURCE):
                yield os.path.join(dirpath, name)


def too_long(root):
    bad = []
    for folder, limit in MAX_LINES.items():
        for path in sources(os.path.join(root, folder)):
            with open(path, encoding="utf-8", errors="replace") as f:
                lines = sum(1 for _ in f)
            if lines > limit:
                rel = os.path.relpath(path, root).replace(os.sep, "/")
                bad.append("%s has %d lines: no %s file above %d" % (rel, lines, folder, limit))
    return bad


def check(root):
    bad = too_long(root)
    core = os.path.join(root, "core")
    plugin = os.path.join(root, "plugin")
    for path in sources(core):
        rel = os.path.relpath(path, core).replace(os.sep, "/")
        layer = rel.split("/")[0]
        if layer not in LAYERS:
            bad.append("%s: core file outside the layer folders %s" % (rel, "/".join(LAYERS)))
            continue
        test = rel.endswith("_test.cpp")
        for delim, inc in INCLUDE.findall(open(path, encoding="utf-8", errors="replace").read()):
            head = inc.split("/")[0]
            if inc.startswith("vtk") or head == "plugin":
                bad.append("core/%s includes %s: core never includes VTK or plugin/" % (rel, inc))
            elif head in LAYERS and "/" in inc:
                if not test and LAYERS.index(head) > LAYERS.index(layer):
                    bad.append("core/%s includes %s: layer %s is above %s" % (rel, inc, head, layer))
            elif delim == '"' and "/" not in inc:
                bad.append("core/%s includes \"%s\": name core headers by their folder (layer/file.h)" % (rel, inc))
    paraview = os.path.join(plugin, "paraview")
    pv_headers = set()
    for path in sources(paraview):
        pv_headers.add(os.path.basename(path))
    for path in sources(plugin):
        if os.path.commonpath([path, paraview]) == paraview:
            continue
        rel = os.path.relpath(path, root).replace(os.sep, "/")
        for _, inc in INCLUDE.findall(open(path, encoding="utf-8", errors="replace").read()):
            name = os.path.basename(inc)
            if name in pv_headers or name.startswith(("vtkPV", "vtkSM")):
                bad.append("%s includes %s: the VTK module never includes ParaView classes" % (rel, inc))
    return bad


def self_test(root):
    with tempfile.TemporaryDirectory() as tmp:
        for folder in ("core", "plugin"):
            shutil.copytree(os.path.join(root, folder), os.path.join(tmp, folder),
                            ignore=shutil.ignore_patterns("build*"))
        clean = check(tmp)
        planted = {
            os.path.join(tmp, "core", "util", "math.h"): '#include "image/renderer.h"\n',
            os.path.join(tmp, "core", "scene", "scene.cpp"): '#include "vtkObject.h"\n',
            os.path.join(tmp, "plugin", "vtkWhittedPass.cxx"): '#include "vtkPVRenderView.h"\n',
            os.path.join(tmp, "core", "image", "film.cpp"): "\n" * (MAX_LINES["core"] + 1),
            os.path.join(tmp, "plugin", "vtkWhittedLights.cxx"): "\n" * (MAX_LINES["plugin"] + 1),
        }
        for path, line in planted.items():
            with open(path, "a") as f:
                f.write(line)
        broken = check(tmp)
    print("self-test: unmodified copy %d violations; with 3 planted includes and two long files %d:" %
          (len(clean), len(broken)))
    for line in broken:
        print("  " + line)
    ok = not clean and len(broken) == 5 and "util/math.h includes image/renderer.h" in "".join(broken) and \
        "core/image/film.cpp has" in "".join(broken) and "plugin/vtkWhittedLights.cxx has" in "".join(broken)
    print("check_layers self-test: %s" % ("ok" if ok else "FAILED"))
    return 0 if ok else 1


def main():
    args = [a for a in sys.argv[1:] if a != "--self-test"]
    root = args[0] if args else os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..")
    root = os.path.abspath(root)
    if "--self-test" in sys.argv[1:]:
        return self_test(root)
    if not os.path.isdir(os.path.join(root, "core")):
        print("check_layers: no core/ under %s" % root)
        return 1
    bad = check(root)
    for line in bad:
        print("layering: " + line)
    print("check_layers: %d violations in %s" % (len(bad), root))
    return 1 if bad else 0


if __name__ == "__main__":
    sys.exit(main())
