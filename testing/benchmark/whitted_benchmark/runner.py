"""Running commands and keeping their results: paths, the runner (logs, CPU time, provenance), CSV files, the
build of whitted_bench, the generated meshes, the ParaView build."""
import csv
import glob
import os
import re
import resource
import shlex
import shutil
import subprocess
import sys
import time

HERE = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))  # testing/benchmark
REPO = os.path.abspath(os.path.join(HERE, "..", ".."))
DATA = os.path.join(REPO, "data", "benchmark")
VTK_PYTHON = "/usr/bin/python3"  # Debian's VTK is only visible to the system interpreter
XVFB = ["xvfb-run", "-a", "-s", "-screen 0 1280x1024x24 -noreset"]
MESH_FILES = {"iso60k": "wavelet_60k.whtmesh", "iso1m": "wavelet_1m.whtmesh", "iso4m": "wavelet_4m.whtmesh"}


def usable_cores():
    """Cores this process may run on (its affinity), as whitted_bench's 'all threads' counts them."""
    try:
        return len(os.sched_getaffinity(0))
    except AttributeError:
        return os.cpu_count() or 1


class Runner:
    """Runs commands, keeps their output in logs/, records them per section (with this machine's folders
    replaced by placeholders) and measures the CPU time of each command's process tree."""

    def __init__(self, out):
        self.logdir = os.path.join(out, "logs")
        os.makedirs(self.logdir, exist_ok=True)
        self.section = ""
        self.by_section = {}
        self.count = 0
        self.last_cpu = 0.0
        self.placeholders = []  # (path, placeholder)

    def mask(self, text):
        for path, name in sorted(self.placeholders, key=lambda p: -len(p[0])):
            text = text.replace(path, name)
        return text

    def run(self, cmd, label, env=None, check=True, timeout=None):
        """Runs cmd; returns (returncode, output, wall seconds). self.last_cpu = user + system CPU seconds of the
        command and every process it waited for (getrusage of children: the process has ended and been reaped)."""
        self.count += 1
        shown = self.mask(" ".join(shlex.quote(c) for c in cmd))
        self.by_section.setdefault(self.section, []).append(shown)
        log = os.path.join(self.logdir, "%02d_%s.log" % (self.count, re.sub(r"[^A-Za-z0-9]+", "_", label)))
        print("  [%s] %s" % (label, shown if len(shown) < 160 else shown[:157] + "..."), flush=True)
        t0 = time.perf_counter()
        ru0 = resource.getrusage(resource.RUSAGE_CHILDREN)
        try:
            p = subprocess.run(cmd, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True, env=env,
                               timeout=timeout)
            rc, text = p.returncode, p.stdout
        except subprocess.TimeoutExpired as e:
            rc, text = -1, (e.stdout or "") if isinstance(e.stdout, str) else ""
            text += "\nTIMEOUT after %s s\n" % timeout
        wall = time.perf_counter() - t0
        ru1 = resource.getrusage(resource.RUSAGE_CHILDREN)
        self.last_cpu = (ru1.ru_utime + ru1.ru_stime) - (ru0.ru_utime + ru0.ru_stime)
        with open(log, "w") as f:
            f.write("$ %s\n%s" % (shown, text))
        if rc != 0 and check:
            raise RuntimeError("%s failed (exit %d); see %s\n%s" % (label, rc, log, text[-2000:]))
        return rc, text, wall


class Context:
    """Everything a section needs: args, cfg (config.py), out folder, runner, whitted_bench path, data search
    path, notes for the report, usable cores, environment versions, provenance of earlier runs."""

    def __init__(self, args, cfg, out, runner):
        self.args, self.cfg, self.out, self.runner = args, cfg, out, runner
        self.bench = ""
        self.data = ""
        self.notes = []
        self.skipped = set()  # sections that could not run here (their outputs are not expected)
        self.threads = usable_cores()
        self.env = {}
        self.prov = {}
        self.headline_scene = "iso60k" if cfg["quick"] else "iso1m"

    def path(self, name):
        return os.path.join(self.out, name)

    def skip(self, section, note):
        """Marks a section as not runnable on this machine, with the reason for the report."""
        self.notes.append(note)
        self.skipped.add(section)


# CSV files --------------------------------------------------------------------------------------------------------

def read_csv(path):
    if not os.path.exists(path):
        return []
    with open(path) as f:
        return [{k: _num(v) for k, v in r.items()} for r in csv.DictReader(f)]


def _num(v):
    try:
        return int(v)
    except (TypeError, ValueError):
        try:
            return float(v)
        except (TypeError, ValueError):
            return v


def write_csv(path, rows):
    if not rows:
        return
    with open(path, "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=list(rows[0].keys()))
        w.writeheader()
        w.writerows(rows)


def drop_tags(path, tags):
    """Removes a section's earlier rows from the shared frames.csv (re-running one section keeps the others)."""
    if not os.path.exists(path):
        return
    with open(path) as f:
        rows = list(csv.reader(f))
    if not rows:
        return
    i = rows[0].index("tag")
    keep = [rows[0]] + [r for r in rows[1:] if not any(r[i] == t or r[i].startswith(t + "-") for t in tags)]
    with open(path, "w", newline="") as f:
        csv.writer(f).writerows(keep)


def fresh(path):
    if os.path.exists(path):
        os.remove(path)
    return path


def is_num(v):
    return isinstance(v, (int, float)) and v == v


# Build and data ---------------------------------------------------------------------------------------------------

def find_bench(args, runner):
    if args.bench:
        return os.path.abspath(args.bench)
    bdir = os.path.abspath(args.build_dir)
    if os.path.exists(os.path.join(bdir, "CMakeCache.txt")):
        with open(os.path.join(bdir, "CMakeCache.txt")) as f:
            standalone = "CMAKE_HOME_DIRECTORY:INTERNAL=%s" % HERE in f.read()
    else:
        os.makedirs(bdir, exist_ok=True)
        runner.run(["cmake", "-S", HERE, "-B", bdir, "-DCMAKE_BUILD_TYPE=Release"], "configure")
        standalone = True
    runner.run(["cmake", "--build", bdir, "--target", "whitted_bench", "--parallel"], "build whitted_bench")
    path = os.path.join(bdir, "whitted_bench") if standalone else os.path.join(bdir, "testing", "benchmark",
                                                                                 "whitted_bench")
    if not os.path.exists(path):
        sys.exit("whitted_bench not found at %s (configure with -DWHITTED_BENCHMARK=ON)" % path)
    return path


def have_vtk():
    try:
        return subprocess.run([VTK_PYTHON, "-c", "import vtkmodules.vtkFiltersCore"], capture_output=True,
                              timeout=60).returncode == 0
    except (OSError, subprocess.TimeoutExpired):
        return False


def ensure_meshes(sizes, cache, runner, notes):
    """Generates the big wavelet meshes into the cache (once); returns the data search path."""
    missing = [s for s in sizes if not os.path.exists(os.path.join(cache, "wavelet_%s.whtmesh" % s))]
    if missing:
        if have_vtk():
            runner.run([VTK_PYTHON, os.path.join(HERE, "gen_wavelet.py"), "--out", cache, "--sizes",
                        ",".join(missing)], "generate wavelet meshes")
        else:
            notes.append("VTK Python not available: could not generate wavelet meshes %s" % ",".join(missing))
    return ",".join([DATA, cache])


def mesh_path(scene, data_dirs):
    """The .whtmesh file of an isosurface scene in the data search path, or None."""
    for d in data_dirs.split(","):
        p = os.path.join(d, MESH_FILES[scene])
        if os.path.exists(p):
            return p
    return None


def available_scenes(scenes, data_dirs):
    return [s for s in scenes if s not in MESH_FILES or mesh_path(s, data_dirs)]


def find_whitted_pythonpath(args):
    """Folder to put on PYTHONPATH so that `from whitted import vtkWhittedPass` works, if the module is built."""
    if args.whitted_pythonpath:
        return args.whitted_pythonpath
    for root in ([os.path.abspath(args.build_dir)] if args.build_dir else []):
        # The build's own module first: the tree also holds staged installs and package trees of earlier test
        # runs (Testing/install), whose module may be stale
        own = os.path.join(root, "lib", "python3", "dist-packages")
        if os.path.isfile(os.path.join(own, "whitted", "__init__.py")):
            return own
        for dirpath, dirnames, filenames in os.walk(root):
            if os.path.basename(dirpath) == "whitted" and "__init__.py" in filenames:
                return os.path.dirname(dirpath)
            dirnames[:] = [d for d in dirnames if not d.startswith(".") and d not in ("CMakeFiles", "Testing")]
    return ""


def vtk_tools_ok():
    """Whether the VTK sections can run: xvfb-run and Debian's VTK Python."""
    return bool(shutil.which("xvfb-run")) and have_vtk()


def whitted_env(args):
    """The environment for a VTK script that imports the whitted module: PYTHONPATH led by its folder (when built)."""
    env = dict(os.environ)
    wpath = find_whitted_pythonpath(args)
    if wpath:
        env["PYTHONPATH"] = wpath + os.pathsep + env.get("PYTHONPATH", "")
    return env


def find_paraview(args):
    """(WhittedView plugin, PYTHONPATH holding ParaView's Python package) next to the build tree, or ""."""
    plugin, pvpath = args.paraview_plugin, args.pv_pythonpath
    build = os.path.abspath(args.build_dir) if args.build_dir else ""
    for root in ([os.path.dirname(build), build] if build else []):  # --build-dir build/vtk or --build-dir build
        if not plugin:
            found = sorted(glob.glob(os.path.join(root, "paraview", "lib", "*", "paraview-*", "plugins",
                                                  "WhittedView", "WhittedView.so")))
            plugin = found[0] if found else ""
        if not pvpath:
            p = os.path.join(root, "pvprefix", "usr", "lib", "python3", "dist-packages")
            pvpath = p if os.path.isdir(os.path.join(p, "paraview")) else ""
    return plugin, pvpath


def paraview_tools(ctx, section, mpi=False):
    """(plugin, PYTHONPATH of ParaView's Python package, pvbatch, mpirun or None) when the ParaView build and the
    programs a ParaView section needs are there; else None, with a note for the report."""
    plugin, pvpath = find_paraview(ctx.args)
    needed = ["pvbatch", "xvfb-run"] + (["mpirun"] if mpi else [])
    found = {t: shutil.which(t) for t in needed}
    if plugin and pvpath and all(found.values()):
        return plugin, pvpath, found["pvbatch"], found.get("mpirun")
    ctx.skip(section, "ParaView plugin build, python3-paraview prefix or %s not found: %s section skipped (pass "
                      "--paraview-plugin and --pv-pythonpath)" % (", ".join(needed), section))
    return None


def paraview_env(pvpath):
    env = dict(os.environ)
    env["PYTHONPATH"] = pvpath + (os.pathsep + env["PYTHONPATH"] if env.get("PYTHONPATH") else "")
    return env


def run_view_bench(ctx, section, script, csv_name, script_args, reps, timeout):
    """Runs a pvbatch script comparing the Whitted view with the Render View (pv_view_bench.py, pv_time_bench.py)
    reps times into a fresh csv_name in the results folder, alternating which view renders first (--first,
    --rep). Skipped with a note when the ParaView build is missing."""
    path = fresh(ctx.path(csv_name))
    tools = paraview_tools(ctx, section)
    if not tools:
        return
    plugin, pvpath, pvbatch, _ = tools
    for rep in range(reps):
        first = "whitted" if rep % 2 == 0 else "render"
        cmd = XVFB + [pvbatch, os.path.join(HERE, script), "--plugin", plugin, "--csv", path] + script_args + \
            ["--first", first, "--rep", str(rep)]
        ctx.runner.run(cmd, "%s rep %d (%s first)" % (section, rep, first), env=paraview_env(pvpath),
                       timeout=timeout)
