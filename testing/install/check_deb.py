"""Builds this tree's Debian package with CPack and checks it without installing it.

    python3 check_deb.py --build <build tree> --out <folder> --expect <path in the package>... --needs <package>...

Checks: one .deb is made; it holds every --expect path (under /usr only, no static archive), its Python package
(if any) where the given interpreters look once it is installed (sys.path, no PYTHONPATH), and nothing points into the build or
source tree (no such RUNPATH in a binary, no such path in a text file: CMake package, Python, XML, conf); its Depends names every --needs package and
only packages apt knows from Debian 12 (bookworm) sources; `apt-get install --simulate` of the .deb resolves.
"""
import argparse
import glob
import os
import re
import shutil
import subprocess
import sys
import tempfile

ap = argparse.ArgumentParser()
ap.add_argument("--build", required=True, help="the build tree (holds CPackConfig.cmake)")
ap.add_argument("--source", required=True, help="the source tree (must not be named inside the package)")
ap.add_argument("--out", required=True, help="folder for the package (emptied first)")
ap.add_argument("--expect", nargs="+", default=[], help="paths the package must hold, e.g. usr/bin/x")
ap.add_argument("--needs", nargs="+", default=[], help="packages Depends must name")
ap.add_argument("--python-package", help="folder of a Python package in the package, e.g. "
                "usr/lib/python3/dist-packages/whitted: its parent must be on the --python interpreters' sys.path")
ap.add_argument("--python", nargs="+", default=[], help="interpreters that must find --python-package installed")
args = ap.parse_args()
failures = []


def run(*cmd):
    result = subprocess.run(cmd, capture_output=True, text=True)
    if result.returncode != 0:
        sys.exit("FAIL: %s\n%s%s" % (" ".join(cmd), result.stdout, result.stderr))
    return result.stdout


# Package
shutil.rmtree(args.out, ignore_errors=True)
run("cpack", "-G", "DEB", "--config", os.path.join(args.build, "CPackConfig.cmake"), "-B", args.out)
debs = glob.glob(os.path.join(args.out, "*.deb"))
if len(debs) != 1:
    sys.exit("FAIL: expected one .deb in %s, found %s" % (args.out, debs))
deb = debs[0]
print(run("dpkg-deb", "-I", deb))
print("size: %.0f KiB" % (os.path.getsize(deb) / 1024))

# Contents
listing = run("dpkg-deb", "-c", deb)
print(listing)
paths = {re.sub(r" -> .*", "", line.split(None, 5)[5]).lstrip("./") for line in listing.splitlines()}
for path in args.expect:
    if path not in paths:
        failures.append("missing from the package: " + path)
for path in paths:
    if path and not path.startswith("usr/") and path != "usr":
        failures.append("installs outside /usr: " + path)
    if path.endswith(".a"):
        failures.append("ships a static archive (a build-time file): " + path)
with tempfile.TemporaryDirectory() as root:
    run("dpkg-deb", "-x", deb, root)
    trees = [os.path.realpath(args.build).encode(), os.path.realpath(args.source).encode()]
    for folder, _, files in os.walk(root):
        for name in files:
            path = os.path.join(folder, name)
            if os.path.islink(path):
                continue
            with open(path, "rb") as f:
                data = f.read()
            if data.startswith(b"\x7fELF"):  # binaries keep __FILE__ strings: check where they look for libraries
                data = run("readelf", "-d", path).encode()
                print("%s: %s" % (os.path.relpath(path, root),
                                  re.findall(r"\((?:RUNPATH|RPATH)\).*", data.decode()) or "no RUNPATH"))
            if any(tree in data for tree in trees):
                failures.append("points into the build or source tree: " + os.path.relpath(path, root))

# Python package: installed, it is found with no PYTHONPATH
if args.python_package:
    site = "/" + os.path.dirname(args.python_package.strip("/"))
    for python in args.python:
        env = {k: v for k, v in os.environ.items() if k != "PYTHONPATH"}
        path = subprocess.run([python, "-c", "import sys; print('\\n'.join(sys.path))"], capture_output=True,
                              text=True, env=env).stdout.split()
        print("%s looks in %s: %s" % (python, site, site in path))
        if site not in path:
            failures.append("%s does not look in %s" % (python, site))
    if not any(p.startswith(args.python_package.strip("/") + "/") for p in paths):
        failures.append("no Python package in " + args.python_package)

# Dependencies: each alternative is a package apt knows from Debian 12's archive
depends = run("dpkg-deb", "-f", deb, "Depends").strip()
names = {re.split(r"[ (:]", alt.strip())[0] for dep in depends.split(",") for alt in dep.split("|")}
print("Depends: %s" % depends)
for need in args.needs:
    if need not in names:
        failures.append("Depends does not name " + need)
for name in sorted(names):
    policy = run("apt-cache", "policy", name)
    if not re.search(r"^\s+\d+ \S+ bookworm(-updates|-security)?/main ", policy, re.M):
        failures.append("%s is not a package of Debian 12 (bookworm) for apt:\n%s" % (name, policy))
simulate = subprocess.run(["apt-get", "install", "--simulate", "--no-install-recommends", os.path.abspath(deb)],
                          capture_output=True, text=True)
package = run("dpkg-deb", "-f", deb, "Package").strip()
print(simulate.stdout[-2000:], simulate.stderr[-2000:])
if simulate.returncode != 0 or not re.search(r"^Inst %s " % re.escape(package), simulate.stdout, re.M):
    failures.append("apt-get install --simulate does not resolve the package")

for failure in failures:
    print("FAIL:", failure)
if failures:
    sys.exit(1)
print("OK: %s" % os.path.basename(deb))
