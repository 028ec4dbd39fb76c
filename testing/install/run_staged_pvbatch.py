"""Runs a pvbatch script as if the whitted-paraview package were installed: pvbatch started from the staged
<stage>/usr/bin (a link to Debian's pvbatch), so ParaView reads the staged <stage>/usr/bin/paraview.conf and
finds the plugin through it and its plugins XML -- with PV_PLUGIN_PATH, PV_PLUGIN_CONFIG_FILE and PYTHONPATH
removed from the environment. ParaView's Python package (python3-paraview, unpacked privately here: it
conflicts with python3-vtk9) is linked where Debian installs it, <stage>/usr/lib/python3/dist-packages.

    python3 run_staged_pvbatch.py --stage S --pvbatch /usr/bin/pvbatch --pv-python <dist-packages> -- script args
"""
import argparse
import os
import subprocess
import sys

ap = argparse.ArgumentParser()
ap.add_argument("--stage", required=True)
ap.add_argument("--pvbatch", required=True)
ap.add_argument("--pv-python", required=True, help="dist-packages folder holding ParaView's Python package")
ap.add_argument("command", nargs=argparse.REMAINDER, help="-- script.py [args]")
args = ap.parse_args()
command = args.command[1:] if args.command[:1] == ["--"] else args.command


def link(target, path):
    os.makedirs(os.path.dirname(path), exist_ok=True)
    if os.path.lexists(path):
        os.remove(path)
    os.symlink(target, path)


pvbatch = os.path.join(args.stage, "usr", "bin", "pvbatch")
link(os.path.realpath(args.pvbatch), pvbatch)
link(os.path.realpath(args.pv_python), os.path.join(args.stage, "usr", "lib", "python3", "dist-packages"))
env = {k: v for k, v in os.environ.items() if k not in ("PV_PLUGIN_PATH", "PV_PLUGIN_CONFIG_FILE", "PYTHONPATH")}
sys.exit(subprocess.call([pvbatch] + command, env=env))
