"""Runs a Python script with the `whitted` package of a staged install, under the interpreter running this file
(Debian's /usr/bin/python3 or vtkpython), and checks that the package and its library come from the stage.

    PYTHONPATH=<stage>/usr/lib/python3/dist-packages <python> run_staged_python.py <stage> script.py [args]
"""
import os
import runpy
import sys

stage, script = os.path.realpath(sys.argv[1]), sys.argv[2]
import whitted  # noqa: E402

if not os.path.realpath(whitted.__file__).startswith(stage + os.sep):
    sys.exit("FAIL: whitted imported from %s, not from the stage %s" % (whitted.__file__, stage))
with open("/proc/self/maps") as maps:
    libraries = {line.split()[-1] for line in maps if "libvtkWhitted" in line}
print("whitted package: %s\nlibrary: %s" % (whitted.__file__, ", ".join(sorted(libraries))))
if not libraries or any(not os.path.realpath(lib).startswith(stage + os.sep) for lib in libraries):
    sys.exit("FAIL: libvtkWhitted is not loaded from the stage")
sys.argv = [script] + sys.argv[3:]
runpy.run_path(script, run_name="__main__")
