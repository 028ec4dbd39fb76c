#!/usr/bin/env python3
"""Whitted benchmark: ray throughput and BVH build against Embree 3, whole frames against POV-Ray 3.7 and VTK's
own OpenGL renderer, scaling, update cost, error against run time, and the ParaView view under MPI. Writes a Markdown report, CSV files and
PNG plots into one folder and prints the headline table.

    /usr/bin/python3 testing/benchmark/run_benchmark.py --build-dir build --out results          # full (~30 min)
    /usr/bin/python3 testing/benchmark/run_benchmark.py --build-dir build --out results --quick  # CI (< 60 s)

--build-dir: a configured build tree of the project (whitted_bench is built there first) or an empty folder (the
benchmark is then configured standalone from testing/benchmark/). --bench PATH uses an existing whitted_bench.
Meshes too large to keep in the repository (1M and 4M triangles) are generated with VTK into --cache
(default <out>/cache) and reused by later runs.

The mpi section runs testing/paraview/bench_still.py in pvbatch under mpirun; it needs the ParaView plugin build
(found next to --build-dir as ../paraview and ../pvprefix, as ./whitted.sh test lays them out, or given with
--paraview-plugin and --pv-pythonpath) and is skipped with a note otherwise.

Every timing is a median of repeated runs after a warm-up; every ratio compares measurements of the same run
(ours and Embree even alternate run by run). Speed ratios are written ours/anchor: > 1 means Whitted is faster.
"""
import argparse
import csv
import glob
import json
import math
import os
import platform
import re
import resource
import shlex
import shutil
import statistics
import subprocess
import sys
import time

HERE = os.path.dirname(os.path.abspath(__file__))
REPO = os.path.abspath(os.path.join(HERE, "..", ".."))
DATA = os.path.join(REPO, "data", "benchmark")
VTK_PYTHON = "/usr/bin/python3"  # Debian's VTK is only visible to the system interpreter
XVFB = ["xvfb-run", "-a", "-s", "-screen 0 1280x1024x24 -noreset"]
SECTIONS = ["rays", "build", "pov", "vtk", "scaling", "update", "error", "mpi"]
DEFAULT_LABEL = "spp 1, depth 5, threshold 1/255, non-adaptive"


# Configuration ---------------------------------------------------------------------------------------------------

def config(quick):
    """What each section measures. The quick mode exercises every code path on tiny inputs (CI)."""
    if quick:
        return dict(
            ray_scenes=["classic", "iso60k"], ray_size="96x72", ray_reps=2,
            build_scenes=["iso60k"], build_reps=1,
            pov_sizes=["160x120"], pov_reps=1, frame_reps=2,
            vtk_scene="iso60k", vtk_size="256x256", vtk_reps=2, vtk_msaa=[0],
            scaling_tri=["iso60k"], scaling_size_scene="classic", scaling_sizes=["64x48", "128x96"],
            scaling_thread_scenes=["classic"], scaling_thread_size="128x96",
            update_scene="iso60k", update_size="96x72", update_reps=1,
            error_scenes=["classic"], error_size="64x48", error_ref_spp=4, error_ref_depth=8, error_reps=1,
            error_budget=1.0, error_quick=True, meshes=[],
            mpi_extent=10, mpi_size="160x120", mpi_frames=1, mpi_reps=1)
    return dict(
        ray_scenes=["classic", "iso60k", "iso1m", "iso4m", "points100k", "tubes", "glassmirror"],
        ray_size="1024x768", ray_reps=5,
        build_scenes=["iso60k", "iso1m", "iso4m", "points100k", "tubes"], build_reps=3,
        pov_sizes=["1024x768", "2048x1536"], pov_reps=5, frame_reps=5,
        vtk_scene="iso1m", vtk_size="1024x1024", vtk_reps=10, vtk_msaa=[0, 8],
        scaling_tri=["iso60k", "iso1m", "iso4m"], scaling_size_scene="iso1m",
        scaling_sizes=["256x192", "512x384", "1024x768", "2048x1536"],
        scaling_thread_scenes=["classic", "iso1m", "tubes"], scaling_thread_size="1024x768",
        update_scene="iso1m", update_size="1024x768", update_reps=5,
        error_scenes=["classic", "iso1m", "points100k", "tubes", "glassmirror"], error_size="192x144",
        error_ref_spp=64, error_ref_depth=16, error_reps=3, error_budget=1.5, error_quick=False, meshes=["1m", "4m"],
        mpi_extent=122, mpi_size="1024x768", mpi_frames=3, mpi_reps=3)


# Running commands ------------------------------------------------------------------------------------------------

class Runner:
    def __init__(self, out):
        self.out = out
        self.logdir = os.path.join(out, "logs")
        os.makedirs(self.logdir, exist_ok=True)
        self.commands = []
        self.section = ""
        self.by_section = {}
        self.count = 0
        self.placeholders = []  # (path, placeholder): recorded commands name no folder of this machine

    def mask(self, text):
        for path, name in sorted(self.placeholders, key=lambda p: -len(p[0])):
            text = text.replace(path, name)
        return text

    def run(self, cmd, label, env=None, check=True, timeout=None):
        """Runs cmd, keeps its output in logs/, returns (returncode, stdout, wall seconds)."""
        self.count += 1
        shown = self.mask(" ".join(shlex.quote(c) for c in cmd))
        self.commands.append(shown)
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
        self.last_cpu = (ru1.ru_utime + ru1.ru_stime) - (ru0.ru_utime + ru0.ru_stime)  # CPU s of that process tree
        with open(log, "w") as f:
            f.write("$ %s\n%s" % (shown, text))
        if rc != 0 and check:
            raise RuntimeError("%s failed (exit %d); see %s\n%s" % (label, rc, log, text[-2000:]))
        return rc, text, wall


def read_csv(path):
    if not os.path.exists(path):
        return []
    rows = []
    with open(path) as f:
        for r in csv.DictReader(f):
            rows.append({k: _num(v) for k, v in r.items()})
    return rows


def _num(v):
    try:
        return int(v)
    except (TypeError, ValueError):
        try:
            return float(v)
        except (TypeError, ValueError):
            return v


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


# Build and data --------------------------------------------------------------------------------------------------

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


def available_scenes(scenes, data_dirs):
    names = {"iso60k": "60k", "iso1m": "1m", "iso4m": "4m"}
    ok = []
    for s in scenes:
        if s in names:
            f = "wavelet_%s.whtmesh" % names[s]
            if not any(os.path.exists(os.path.join(d, f)) for d in data_dirs.split(",")):
                continue
        ok.append(s)
    return ok


# Sections --------------------------------------------------------------------------------------------------------

def section_rays(ctx):
    c = ctx.cfg
    path = fresh(os.path.join(ctx.out, "rays.csv"))
    agree = fresh(os.path.join(ctx.out, "rays_agreement.csv"))
    for s in available_scenes(c["ray_scenes"], ctx.data):
        ctx.runner.run([ctx.bench, "rays", "--scene", s, "--data", ctx.data, "--size", c["ray_size"], "--reps",
                        str(c["ray_reps"]), "--warmup", "1", "--threads-list", "1,0", "--csv", path,
                        "--agreement-csv", agree], "rays " + s)


def section_build(ctx):
    c = ctx.cfg
    path = fresh(os.path.join(ctx.out, "build.csv"))
    for s in available_scenes(c["build_scenes"], ctx.data):
        ctx.runner.run([ctx.bench, "build", "--scene", s, "--data", ctx.data, "--reps", str(c["build_reps"]),
                        "--warmup", "1", "--threads-list", "1,0", "--csv", path], "build " + s)


def parse_pov_time(text, what):
    m = re.search(r"%s Time:.*\(([\d.]+) seconds\)" % what, text)
    return float(m.group(1)) if m else float("nan")


def section_pov(ctx):
    """POV-Ray 3.7 on data/benchmark/classic.pov vs whitted_bench on the classic scene, same size, depth, threads."""
    c = ctx.cfg
    frames = os.path.join(ctx.out, "frames.csv")
    drop_tags(frames, ["pov"])
    pov_csv = fresh(os.path.join(ctx.out, "pov.csv"))
    if not shutil.which("povray"):
        ctx.notes.append("povray not found: POV-Ray comparison skipped")
        return
    depth, threshold, threads = 5, 1.0 / 255.0, ctx.threads
    rows = []
    for size in c["pov_sizes"]:
        w, h = (int(v) for v in size.split("x"))
        ours_png = os.path.join(ctx.out, "pov_ours_%s.png" % size)
        pov_png = os.path.join(ctx.out, "pov_povray_%s.png" % size)
        # Ours in-process: trace time median after a warm-up (the renderer's own timer)
        ctx.runner.run([ctx.bench, "frame", "--scene", "classic", "--sizes", size, "--depth", str(depth),
                        "--threshold", repr(threshold), "--threads-list", "0", "--reps", str(c["frame_reps"]),
                        "--warmup", "1", "--tag", "pov", "--csv", frames, "--png", ours_png], "ours classic " + size)
        # Whole processes, alternating ours and POV-Ray, each rendering once (cold, like POV-Ray's single frame):
        # process wall/CPU time includes start-up, parsing or scene build and PNG output; trace wall/CPU time is
        # each program's own timer
        pov_cmd = ["povray", "+I" + os.path.join(DATA, "classic.pov"), "+O" + pov_png, "+W%d" % w, "+H%d" % h,
                   "-A", "+WT%d" % threads, "-D", "+FN", "-V", "File_Gamma=1.0",
                   "Declare=TraceLevel=%d" % (depth + 1), "Declare=Bailout=%.17g" % threshold,
                   "Declare=Aspect=%.17g" % (w / h)]
        ours_cmd = [ctx.bench, "frame", "--scene", "classic", "--sizes", size, "--depth", str(depth), "--threshold",
                    repr(threshold), "--threads-list", "0", "--reps", "1", "--warmup", "0", "--png", ours_png]
        m = {k: [] for k in ["pov_wall", "pov_cpu", "pov_trace", "pov_trace_cpu", "ours_wall", "ours_cpu",
                             "ours_trace", "ours_trace_cpu"]}
        for i in range(1 + c["pov_reps"]):  # first round is the warm-up (file cache, binaries)
            _, text, wall = ctx.runner.run(pov_cmd, "povray %s run %d" % (size, i))
            pcpu = ctx.runner.last_cpu
            _, otext, owall = ctx.runner.run(ours_cmd, "ours process %s run %d" % (size, i))
            ocpu = ctx.runner.last_cpu
            if i > 0 or c["pov_reps"] == 0:
                tcpu = re.search(r"Trace Time:.*\n\s*using \d+ thread\(s\) with ([\d.]+) CPU-seconds", text)
                mo = re.search(r"trace\s+([\d.]+) ms .*cpu ([\d.]+) ms", otext)
                for k, v in [("pov_wall", wall), ("pov_cpu", pcpu), ("pov_trace", parse_pov_time(text, "Trace")),
                             ("pov_trace_cpu", float(tcpu.group(1)) if tcpu else float("nan")),
                             ("ours_wall", owall), ("ours_cpu", ocpu),
                             ("ours_trace", float(mo.group(1)) * 1e-3 if mo else float("nan")),
                             ("ours_trace_cpu", float(mo.group(2)) * 1e-3 if mo else float("nan"))]:
                    m[k].append(v)
        fr = [r for r in read_csv(frames) if r["tag"] == "pov" and r["width"] == w and r["height"] == h][-1]
        diff, diff_max = image_rmse(ours_png, pov_png)
        row = dict(size=size, threads=threads, depth=depth, pov_max_trace_level=depth + 1, runs=len(m["pov_wall"]))
        row.update({k + "_median": statistics.median(v) for k, v in m.items()})
        row.update(ours_trace_warm_median=fr["seconds_median"], image_rmse_8bit=diff, image_max_levels=diff_max)
        rows.append(row)
        if size == c["pov_sizes"][0]:
            plot_pov(ctx, ours_png, pov_png, row)
    write_csv(pov_csv, rows)


def image_rmse(a, b):
    """RMSE of two 8-bit images (values in [0,1]) and their largest difference in 8-bit levels."""
    try:
        import matplotlib.image as mpimg
        import numpy as np
        x, y = mpimg.imread(a)[..., :3].astype(float), mpimg.imread(b)[..., :3].astype(float)
        if x.shape != y.shape:
            return float("nan"), -1
        return float(np.sqrt(np.mean((x - y) ** 2))), int(round(np.abs(x - y).max() * 255))
    except Exception:  # noqa: BLE001 - image comparison is informational
        return float("nan"), -1


def write_csv(path, rows):
    if not rows:
        return
    keys = list(rows[0].keys())
    with open(path, "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=keys)
        w.writeheader()
        for r in rows:
            w.writerow(r)


def find_whitted_pythonpath(args):
    """Folder to put on PYTHONPATH so that `from whitted import vtkWhittedPass` works, if the module is built."""
    if args.whitted_pythonpath:
        return args.whitted_pythonpath
    roots = [os.path.abspath(args.build_dir)] if args.build_dir else []
    for root in roots:
        for dirpath, dirnames, filenames in os.walk(root):
            if os.path.basename(dirpath) == "whitted" and "__init__.py" in filenames:
                return os.path.dirname(dirpath)
            dirnames[:] = [d for d in dirnames if not d.startswith(".") and d != "CMakeFiles"]
    return ""


def section_vtk(ctx):
    """VTK's OpenGL (llvmpipe under Xvfb) on the isosurface vs our frame with shadows, same camera and size."""
    c = ctx.cfg
    vtk_csv = fresh(os.path.join(ctx.out, "vtk_opengl.csv"))
    frames = os.path.join(ctx.out, "frames.csv")
    drop_tags(frames, ["vtk"])
    scene = c["vtk_scene"]
    if not available_scenes([scene], ctx.data):
        ctx.notes.append("mesh for %s missing: VTK comparison skipped" % scene)
        return
    size = c["vtk_size"]
    ours_png = os.path.join(ctx.out, "vtk_ours_%s.png" % scene)
    ours_cmd = [ctx.bench, "frame", "--scene", scene, "--data", ctx.data, "--sizes", size, "--threads-list", "0",
                "--reps", str(c["frame_reps"]), "--warmup", "1", "--tag", "vtk", "--csv", frames, "--png", ours_png]
    ctx.runner.run(ours_cmd, "ours " + scene + " " + size)  # again after the VTK runs: the report uses both
    if not shutil.which("xvfb-run") or not have_vtk():
        ctx.notes.append("xvfb-run or VTK Python missing: VTK OpenGL comparison skipped")
        return
    info = os.path.join(ctx.out, "cache", scene + ".json")
    os.makedirs(os.path.dirname(info), exist_ok=True)
    _, text, _ = ctx.runner.run([ctx.bench, "info", "--scene", scene, "--data", ctx.data], "info " + scene)
    with open(info, "w") as f:
        f.write(text)
    mesh = None
    for d in ctx.data.split(","):
        p = os.path.join(d, {"iso60k": "wavelet_60k", "iso1m": "wavelet_1m", "iso4m": "wavelet_4m"}[scene] + ".whtmesh")
        if os.path.exists(p):
            mesh = p
            break
    script = os.path.join(HERE, "vtk_gl_bench.py")
    modes = [("opengl", m) for m in c["vtk_msaa"]] + [("shadowmap", 0), ("whitted", 0)]
    env = dict(os.environ)
    wpath = find_whitted_pythonpath(ctx.args)
    if wpath:
        env["PYTHONPATH"] = wpath + os.pathsep + env.get("PYTHONPATH", "")
    for mode, msaa in modes:
        png = os.path.join(ctx.out, "vtk_%s_msaa%d.png" % (mode, msaa))
        cmd = XVFB + [VTK_PYTHON, script, "--mesh", mesh, "--info", info, "--size", size, "--mode", mode, "--msaa",
                      str(msaa), "--reps", str(c["vtk_reps"]), "--warmup", "2", "--csv", vtk_csv, "--png", png]
        rc, text, _ = ctx.runner.run(cmd, "vtk %s msaa %d" % (mode, msaa), env=env, check=False, timeout=900)
        if rc != 0:
            ctx.notes.append("VTK %s (MultiSamples %d) failed (exit %d), see logs/" % (mode, msaa, rc))
    ctx.runner.run(ours_cmd, "ours " + scene + " " + size + " again")


def section_scaling(ctx):
    c = ctx.cfg
    frames = os.path.join(ctx.out, "frames.csv")
    drop_tags(frames, ["scale"])
    for s in available_scenes(c["scaling_tri"], ctx.data):
        ctx.runner.run([ctx.bench, "frame", "--scene", s, "--data", ctx.data, "--sizes", c["scaling_thread_size"],
                        "--threads-list", "0", "--reps", str(c["frame_reps"]), "--warmup", "1", "--tag",
                        "scale-triangles", "--csv", frames], "scaling triangles " + s)
    s = c["scaling_size_scene"]
    if available_scenes([s], ctx.data):
        ctx.runner.run([ctx.bench, "frame", "--scene", s, "--data", ctx.data, "--sizes", ",".join(c["scaling_sizes"]),
                        "--threads-list", "0", "--reps", str(c["frame_reps"]), "--warmup", "1", "--tag",
                        "scale-size", "--csv", frames], "scaling image size " + s)
    threads = sorted({1, 2, ctx.threads} | ({ctx.threads * 2} if not ctx.cfg["error_quick"] else set()))
    for s in available_scenes(c["scaling_thread_scenes"], ctx.data):
        ctx.runner.run([ctx.bench, "frame", "--scene", s, "--data", ctx.data, "--sizes", c["scaling_thread_size"],
                        "--threads-list", ",".join(map(str, threads)), "--reps", str(c["frame_reps"]), "--warmup",
                        "1", "--tag", "scale-threads", "--csv", frames], "scaling threads " + s)


def section_update(ctx):
    c = ctx.cfg
    path = fresh(os.path.join(ctx.out, "update.csv"))
    s = c["update_scene"]
    if not available_scenes([s], ctx.data):
        ctx.notes.append("mesh for %s missing: update section skipped" % s)
        return
    ctx.runner.run([ctx.bench, "update", "--scene", s, "--data", ctx.data, "--size", c["update_size"], "--reps",
                    str(c["update_reps"]), "--warmup", "1", "--csv", path], "update " + s)


MPI_CONFIGS = [(1, 1), (2, 1), (1, 0)]  # (ranks, tracing threads per rank; 0 = all cores)


def find_paraview(ctx):
    """(WhittedView plugin, PYTHONPATH holding ParaView's Python package) next to the build tree, or ""."""
    plugin, pvpath = ctx.args.paraview_plugin, ctx.args.pv_pythonpath
    build = os.path.abspath(ctx.args.build_dir) if ctx.args.build_dir else ""
    roots = [os.path.dirname(build), build] if build else []  # --build-dir build/vtk or --build-dir build
    for root in roots:
        if not plugin:
            found = sorted(glob.glob(os.path.join(root, "paraview", "lib", "paraview-*", "plugins", "WhittedView",
                                                  "WhittedView.so")))
            plugin = found[0] if found else ""
        if not pvpath:
            p = os.path.join(root, "pvprefix", "usr", "lib", "python3", "dist-packages")
            pvpath = p if os.path.isdir(os.path.join(p, "paraview")) else ""
    return plugin, pvpath


def mpi_tools(ctx):
    plugin, pvpath = find_paraview(ctx)
    tools = [shutil.which(t) for t in ("pvbatch", "mpirun", "xvfb-run")]
    return (plugin, pvpath, tools[0], tools[1]) if plugin and pvpath and all(tools) else None


def section_mpi(ctx):
    """The Whitted Ray Trace view in pvbatch: 1 rank x 1 thread, 2 ranks x 1 thread (image split between ranks,
    geometry replicated) and 1 rank x all threads, alternating, on the wavelet isosurface."""
    c = ctx.cfg
    path = fresh(os.path.join(ctx.out, "mpi.csv"))
    tools = mpi_tools(ctx)
    if not tools:
        ctx.notes.append("ParaView plugin build, python3-paraview prefix, pvbatch, mpirun or xvfb-run not found: "
                         "MPI section skipped (pass --paraview-plugin and --pv-pythonpath)")
        return
    plugin, pvpath, pvbatch, mpirun = tools
    env = dict(os.environ)
    env["PYTHONPATH"] = pvpath + (os.pathsep + env["PYTHONPATH"] if env.get("PYTHONPATH") else "")
    script = os.path.join(REPO, "testing", "paraview", "bench_still.py")
    rows = []
    for rep in range(c["mpi_reps"]):
        for ranks, threads in MPI_CONFIGS:
            # --bind-to none: Open MPI binds each rank to one core by default (np <= 2), which would leave the
            # 1 rank x all threads case one core (the tracer follows the affinity mask)
            cmd = XVFB + [mpirun, "--allow-run-as-root", "--oversubscribe", "--bind-to", "none", "--mca", "btl", "self,vader", "-x",
                          "DISPLAY", "-x", "PYTHONPATH", "-np", str(ranks), pvbatch, script, "--plugin", plugin,
                          "--extent", str(c["mpi_extent"]), "--size", c["mpi_size"], "--threads", str(threads),
                          "--frames", str(c["mpi_frames"])]
            _, text, _ = ctx.runner.run(cmd, "mpi %d rank %s threads rep %d" % (ranks, threads or "all", rep),
                                        env=env, timeout=900)
            still = re.search(r"first frame ([0-9.]+) s, still frame median ([0-9.]+) s", text)
            cpu = re.search(r"CPU seconds per frame and rank: ([0-9. ]+) \(load average ([0-9.]+)\)", text)
            tris = re.search(r"([0-9]+) triangles", text)
            if not (still and cpu and tris):
                raise RuntimeError("unexpected output of bench_still.py:\n" + text[-2000:])
            cpus = [float(v) for v in cpu.group(1).split()]
            w, h = c["mpi_size"].split("x")
            rows.append(dict(ranks=ranks, threads_per_rank=threads or ctx.threads, rep=rep,
                             triangles=int(tris.group(1)), width=int(w), height=int(h),
                             first_seconds=float(still.group(1)), still_seconds=float(still.group(2)),
                             cpu_seconds_per_rank=" ".join("%.3f" % v for v in cpus),
                             cpu_seconds_total=sum(cpus), load=float(cpu.group(2))))
    write_csv(path, rows)


def section_error(ctx):
    c = ctx.cfg
    path = fresh(os.path.join(ctx.out, "error.csv"))
    for s in available_scenes(c["error_scenes"], ctx.data):
        cmd = [ctx.bench, "error", "--scene", s, "--data", ctx.data, "--size", c["error_size"], "--ref-spp",
               str(c["error_ref_spp"]), "--ref-depth", str(c["error_ref_depth"]), "--reps", str(c["error_reps"]),
               "--warmup", "1", "--budget", str(c["error_budget"]), "--csv", path, "--png-dir", ctx.out]
        if c["error_quick"]:
            cmd.append("--quick")
        ctx.runner.run(cmd, "error " + s)


# Plots -----------------------------------------------------------------------------------------------------------

def plt_module():
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    plt.rcParams.update({"font.size": 10, "axes.grid": True, "grid.alpha": 0.3, "savefig.dpi": 110})
    return plt


def plain_log_ticks(ax, axis="both"):
    """Log axes labelled 2, 5, 10, 20 ... instead of 2x10^0."""
    from matplotlib.ticker import FuncFormatter, LogLocator
    fmt = FuncFormatter(lambda v, _: ("%g" % v) if v >= 1e-3 else ("%.0e" % v))
    for a in ([ax.xaxis] if axis == "x" else [ax.yaxis] if axis == "y" else [ax.xaxis, ax.yaxis]):
        if a.get_scale() != "log":
            continue
        a.set_major_locator(LogLocator(base=10, subs=(1.0, 2.0, 5.0)))
        a.set_major_formatter(fmt)
        a.set_minor_formatter(FuncFormatter(lambda v, _: ""))


def plot_pov(ctx, ours_png, pov_png, row):
    plt = plt_module()
    import matplotlib.image as mpimg
    import numpy as np
    a, b = mpimg.imread(ours_png)[..., :3], mpimg.imread(pov_png)[..., :3]
    fig, ax = plt.subplots(1, 3, figsize=(15, 4.4))
    ax[0].imshow(a)
    ax[0].set_title("Whitted: trace %.0f ms (process %.0f ms)" % (row["ours_trace_median"] * 1e3,
                                                                  row["ours_wall_median"] * 1e3))
    ax[1].imshow(b)
    ax[1].set_title("POV-Ray 3.7: trace %.0f ms (process %.0f ms)" % (row["pov_trace_median"] * 1e3,
                                                                     row["pov_wall_median"] * 1e3))
    if a.shape == b.shape:
        ax[2].imshow(np.clip(np.abs(a - b).max(axis=2) * 4, 0, 1), cmap="magma", vmin=0, vmax=1)
    ax[2].set_title("|difference| x 4 (RMSE %.2g, max %d/255)" % (row["image_rmse_8bit"], row["image_max_levels"]))
    for x in ax:
        x.axis("off")
    fig.suptitle("Classic scene %s, depth %d (POV max_trace_level %d), %d threads, no antialiasing" % (
        row["size"], row["depth"], row["pov_max_trace_level"], row["threads"]))
    fig.tight_layout(rect=[0, 0, 1, 0.94])
    fig.savefig(os.path.join(ctx.out, "pov_compare.png"))
    plt.close(fig)


def plot_vtk(ctx):
    plt = plt_module()
    import matplotlib.image as mpimg
    rows = read_csv(os.path.join(ctx.out, "vtk_opengl.csv"))
    frames = [r for r in read_csv(os.path.join(ctx.out, "frames.csv")) if r["tag"] == "vtk"]
    if not frames:
        return
    ours_png = os.path.join(ctx.out, "vtk_ours_%s.png" % frames[-1]["scene"])
    panels = []
    if frames:
        panels.append((ours_png, "Whitted core, shadows: %.0f ms" % (
            statistics.mean(r["seconds_median"] for r in frames) * 1e3)))
    for r in rows:
        if r.get("status") == "ok" and r.get("screenshot"):
            label = {"opengl": "VTK OpenGL", "shadowmap": "VTK OpenGL + shadow maps",
                     "whitted": "vtkWhittedPass"}[r["mode"]]
            panels.append((os.path.join(ctx.out, r["screenshot"]), "%s, MSAA %d: %.0f ms" % (
                label, r["msaa"], r["seconds_median"] * 1e3)))
    panels = [p for p in panels if os.path.exists(p[0])]
    if not panels:
        return
    cols = min(3, len(panels))
    rows = (len(panels) + cols - 1) // cols
    fig, ax = plt.subplots(rows, cols, figsize=(5.2 * cols, 5.4 * rows), squeeze=False)
    ax = list(ax.flat)
    for x in ax:
        x.axis("off")
    for x, (p, title) in zip(ax, panels):
        x.imshow(mpimg.imread(p))
        x.set_title(title, fontsize=11)
    fig.suptitle("%s at %dx%d (median frame time after a camera move)" % (
        frames[-1]["scene"], frames[-1]["width"], frames[-1]["height"]))
    fig.tight_layout(rect=[0, 0, 1, 0.94])
    fig.savefig(os.path.join(ctx.out, "vtk_compare.png"))
    plt.close(fig)


def plot_rays(ctx, rays):
    if not rays:
        return
    plt = plt_module()
    import numpy as np
    scenes = list(dict.fromkeys(r["scene"] for r in rays))
    kinds = ["primary", "shadow", "incoherent"]
    threads = sorted({r["threads"] for r in rays})
    fig, axes = plt.subplots(1, len(threads), figsize=(7 * len(threads), 4.8), squeeze=False)
    for ax, t in zip(axes[0], threads):
        width = 0.13
        x = np.arange(len(scenes))
        for k, kind in enumerate(kinds):
            for e, eng in enumerate(["whitted", "embree"]):
                vals = []
                for s in scenes:
                    m = [r["mrays_median"] for r in rays if r["scene"] == s and r["kind"] == kind and
                         r["threads"] == t and r["engine"] == eng]
                    vals.append(m[0] if m else 0)
                off = (2 * k + e - 2.5) * width
                ax.bar(x + off, vals, width, color="C%d" % k, alpha=1.0 if eng == "whitted" else 0.45,
                       hatch=None if eng == "whitted" else "//", edgecolor="k", linewidth=0.3,
                       label="%s %s" % ("Whitted" if eng == "whitted" else "Embree", kind))
        ax.set_xticks(x)
        ax.set_xticklabels(scenes, rotation=20)
        ax.set_yscale("log")
        plain_log_ticks(ax, "y")
        ax.set_ylabel("Mrays/s (log)")
        ax.set_title("%d thread%s" % (t, "s" if t > 1 else ""))
    handles, labels = axes[0][0].get_legend_handles_labels()
    fig.legend(handles, labels, fontsize=9, ncol=6, loc="lower center")
    fig.suptitle("Ray throughput: Whitted (solid) vs Embree 3 (hatched), same rays")
    fig.tight_layout(rect=[0, 0.07, 1, 1])
    fig.savefig(os.path.join(ctx.out, "rays.png"))
    plt.close(fig)


def plot_build(ctx, build):
    if not build:
        return
    plt = plt_module()
    scenes = list(dict.fromkeys(r["scene"] for r in build))
    variants = [("whitted", "Scene::commit", ctx.threads), ("embree", "low", 1), ("embree", "medium", 1),
                ("embree", "high", 1), ("embree", "low", ctx.threads), ("embree", "medium", ctx.threads),
                ("embree", "high", ctx.threads)]
    fig, ax = plt.subplots(1, 2, figsize=(13, 4.6))
    import numpy as np
    x = np.arange(len(scenes))
    width = 0.8 / len(variants)
    for i, (eng, var, th) in enumerate(variants):
        sp, mem = [], []
        for s in scenes:
            m = [r for r in build if r["scene"] == s and r["engine"] == eng and r["variant"] == var and r["threads"] == th]
            sp.append(m[0]["mprims_per_s"] if m else 0)
            mem.append(m[0]["bytes_per_prim"] if m else 0)
        label = "Whitted (core's own threading)" if eng == "whitted" else "Embree %s, %d thr" % (var, th)
        color = "k" if eng == "whitted" else "C%d" % (["low", "medium", "high"].index(var))
        alpha = 1.0 if eng == "whitted" or th == 1 else 0.5
        ax[0].bar(x + (i - len(variants) / 2 + 0.5) * width, sp, width, color=color, alpha=alpha, label=label)
        if th == 1 or eng == "whitted":
            ax[1].bar(x + (i - 2) * 0.2, mem, 0.2, color=color, label=label)
    ax[0].set_yscale("log")
    plain_log_ticks(ax[0], "y")
    ax[0].set_ylabel("build speed, Mprims/s (log)")
    ax[1].set_ylabel("acceleration structure, bytes per primitive")
    for a in ax:
        a.set_xticks(x)
        a.set_xticklabels(scenes)
    ax[0].legend(fontsize=8, ncol=2)
    ax[1].legend(fontsize=8)
    ax[0].set_title("BVH build speed")
    ax[1].set_title("BVH memory")
    fig.tight_layout()
    fig.savefig(os.path.join(ctx.out, "build.png"))
    plt.close(fig)


def plot_scaling(ctx, frames, build):
    plt = plt_module()
    fig, ax = plt.subplots(1, 3, figsize=(16, 4.6))
    tri = sorted([r for r in frames if r["tag"] == "scale-triangles"], key=lambda r: r["primitives"])
    if tri:
        n = [r["primitives"] for r in tri]
        ax[0].loglog(n, [r["seconds_median"] * 1e3 for r in tri], "o-", label="Whitted trace (%dx%d, %d thr)" % (
            tri[0]["width"], tri[0]["height"], tri[0]["threads"]))
        if all(isinstance(r.get("cpu_seconds_median"), float) for r in tri):
            ax[0].loglog(n, [r["cpu_seconds_median"] * 1e3 for r in tri], "o:", color="C0", alpha=0.6,
                         label="Whitted trace, CPU time (all threads)")
        wb = {r["primitives"]: r["seconds_median"] for r in build if r["variant"] == "Scene::commit"}
        ax[0].loglog(n, [wb.get(r["primitives"], r["commit_seconds"]) * 1e3 for r in tri], "s-",
                     label="Whitted BVH build (commit)")
        em = {r["primitives"]: r["seconds_median"] * 1e3 for r in build if r["engine"] == "embree" and
              r["variant"] == "medium" and r["threads"] == ctx.threads}
        pts = [(k, em[k]) for k in n if k in em]
        if pts:
            ax[0].loglog(*zip(*pts), "^--", label="Embree build, medium, %d thr" % ctx.threads)
        ax[0].set_xlabel("triangles")
        ax[0].set_ylabel("ms")
        ax[0].set_title("Time vs triangle count (isosurfaces)")
        ax[0].legend(fontsize=8)
        plain_log_ticks(ax[0], "y")
    sz = sorted([r for r in frames if r["tag"] == "scale-size"], key=lambda r: r["width"] * r["height"])
    if sz:
        px = [r["width"] * r["height"] for r in sz]
        ms = [r["seconds_median"] * 1e3 for r in sz]
        ax[1].loglog(px, ms, "o-", label="%s trace" % sz[0]["scene"])
        if all(isinstance(r.get("cpu_seconds_median"), float) for r in sz):
            ax[1].loglog(px, [r["cpu_seconds_median"] * 1e3 for r in sz], "o:", color="C0", alpha=0.6,
                         label="%s trace, CPU time" % sz[0]["scene"])
        ax[1].loglog(px, [ms[0] * p / px[0] for p in px], ":", color="gray", label="linear in pixels")
        ax[1].set_xlabel("pixels")
        ax[1].set_ylabel("ms")
        ax[1].set_title("Time vs image size (%d threads)" % sz[0]["threads"])
        ax[1].legend(fontsize=8)
        plain_log_ticks(ax[1], "y")
    th = [r for r in frames if r["tag"] == "scale-threads"]
    for i, s in enumerate(dict.fromkeys(r["scene"] for r in th)):
        rs = sorted([r for r in th if r["scene"] == s], key=lambda r: r["threads"])
        t1 = [r["seconds_median"] for r in rs if r["threads"] == 1]
        if not t1:
            continue
        ax[2].plot([r["threads"] for r in rs], [t1[0] / (r["seconds_median"] * min(r["threads"], ctx.threads))
                                                for r in rs], "o-", color="C%d" % i, label="%s (wall)" % s)
        c1 = [r.get("cpu_seconds_median") for r in rs if r["threads"] == 1]
        if c1 and isinstance(c1[0], float):
            ax[2].plot([r["threads"] for r in rs], [c1[0] / r["cpu_seconds_median"] for r in rs], "s--", color="C%d" % i,
                       alpha=0.7, label="%s (CPU: threading overhead only)" % s)
    ax[2].axhline(1.0, color="gray", ls=":")
    ax[2].axvline(ctx.threads, color="gray", ls="--", lw=0.8)
    ax[2].set_ylim(0, 1.2)
    if th:
        ax[2].set_xticks(sorted({r["threads"] for r in th}))
    ax[2].set_xlabel("threads (dashed: hardware threads)")
    ax[2].set_ylabel("efficiency: T1 / (min(n, cores) Tn); CPU1 / CPUn")
    ax[2].set_title("Thread scaling")
    if th:
        ax[2].legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(os.path.join(ctx.out, "scaling.png"))
    plt.close(fig)


def plot_update(ctx, upd):
    if not upd:
        return
    plt = plt_module()
    fig, ax = plt.subplots(figsize=(10, 4.2))
    names = [r["case"] for r in upd]
    c = [r["commit_seconds"] * 1e3 for r in upd]
    t = [r["trace_seconds"] * 1e3 for r in upd]
    y = range(len(names))
    ax.barh(y, c, color="C3", label="commit (BVH rebuilds)")
    ax.barh(y, t, left=c, color="C0", label="trace")
    for i in y:
        ax.text(c[i] + t[i], i, " %.0f ms" % (c[i] + t[i]), va="center", fontsize=9)
    ax.set_yticks(list(y))
    ax.set_yticklabels(names)
    ax.invert_yaxis()
    ax.set_xlabel("ms (median)")
    ax.set_title("Re-render cost after an edit: %s, %d instances, %dx%d" % (
        upd[0]["scene"], upd[0]["instances"], upd[0]["width"], upd[0]["height"]))
    ax.legend(loc="upper right")
    ax.set_xlim(0, max(a + b for a, b in zip(c, t)) * 1.15)
    fig.tight_layout()
    fig.savefig(os.path.join(ctx.out, "update.png"))
    plt.close(fig)


SAMPLING_LABELS = {(1, 0): "1 spp", (4, 0): "4 spp", (4, 1): "4 spp adaptive", (16, 0): "16 spp",
                   (16, 1): "16 spp adaptive"}


def pareto(points):
    """Indices of the points not dominated in (time, error), sorted by time."""
    idx = sorted(range(len(points)), key=lambda i: (points[i][0], points[i][1]))
    front, best = [], float("inf")
    for i in idx:
        if points[i][1] < best:
            front.append(i)
            best = points[i][1]
    return front


def error_time_key(err):
    """Cost axis of the error study: CPU time of the render when recorded (stable on a shared machine; on an
    idle machine it is threads x wall time), else wall time."""
    if err and all(isinstance(r.get("cpu_seconds_median"), float) and r["cpu_seconds_median"] > 0 for r in err):
        return "cpu_seconds_median", "render CPU time, ms (median, all %d threads summed, log)"
    return "seconds_median", "render time, ms (median, wall, log)"


def dominated_by(rows, d, key, tol=0.1):
    """Settings clearly better than d: >= tol faster at no more error, or >= tol less error at no more time."""
    # A cheaper setting must also trace fewer rays: settings that give the same image with the same rays (e.g.
    # any depth in a scene without mirrors) differ only by timing noise
    return [r for r in rows if r is not d and (
        (r[key] <= (1 - tol) * d[key] and r["rays"] < d["rays"] and r["rmse"] <= d["rmse"]) or
        (r[key] <= d[key] and r["rmse"] <= (1 - tol) * d["rmse"]))]


def plot_error(ctx, err):
    plt = plt_module()
    out = []
    tkey, tlabel = error_time_key(err)
    for scene in dict.fromkeys(r["scene"] for r in err):
        rows = [r for r in err if r["scene"] == scene and not r["is_reference"]]
        if not rows:
            continue
        ref = [r for r in err if r["scene"] == scene and r["is_reference"]][0]
        fig, ax = plt.subplots(1, 2, figsize=(14, 5.2))
        for k, (metric, ylabel) in enumerate([("rmse", "RMSE vs reference (linear RGB in [0,1])"),
                                              ("one_minus_ssim", "1 - SSIM vs reference")]):
            a = ax[k]
            val = (lambda r: max(1e-6, 1 - r["ssim"])) if metric == "one_minus_ssim" else (lambda r: max(1e-6, r["rmse"]))
            for i, key in enumerate(SAMPLING_LABELS):
                sel = [r for r in rows if (r["spp"], r["adaptive"]) == key]
                if sel:
                    a.scatter([r[tkey] * 1e3 for r in sel], [val(r) for r in sel], s=14,
                              color="C%d" % i, alpha=0.7, label=SAMPLING_LABELS[key])
            pts = [(r[tkey], val(r)) for r in rows]
            front = pareto(pts)
            a.plot([pts[i][0] * 1e3 for i in front], [pts[i][1] for i in front], "k-", lw=1.2, drawstyle="steps-post",
                   label="Pareto front")
            placed = []
            for i in front:
                r = rows[i]
                lx, ly = math.log10(pts[i][0] * 1e3), math.log10(pts[i][1])
                if any(abs(lx - px) < 0.15 and abs(ly - py) < 0.06 for px, py in placed):
                    continue  # too close to a label already drawn
                placed.append((lx, ly))
                a.annotate("d%d t%.0f%s" % (r["depth"], r["threshold"] * 255,
                                            "" if r["spp"] == 1 else " %d%s" % (r["spp"], "a" if r["adaptive"] else "")),
                           (pts[i][0] * 1e3, pts[i][1]), fontsize=7, xytext=(4, 3), textcoords="offset points")
            d = [r for r in rows if r["is_default"]]
            if d:
                a.scatter([d[0][tkey] * 1e3], [val(d[0])], marker="*", s=260, color="gold",
                          edgecolor="k", zorder=5, label="default (%s)" % DEFAULT_LABEL)
            a.set_xscale("log")
            a.set_yscale("log")
            a.set_xlabel(tlabel % ctx.threads if "%d" in tlabel else tlabel)
            a.set_ylabel(ylabel)
            plain_log_ticks(a)
        ax[0].legend(fontsize=7.5, loc="lower left")  # nothing lies below-left of the Pareto front
        size = "%s" % ctx.cfg["error_size"]
        fig.suptitle("%s %s: error vs cost (labels on the front: d = depth, t = threshold x 255, then spp, a = "
                     "adaptive); reference %d spp, depth %d, threshold 0: %.1f s" % (
                         scene, size, ref["spp"], ref["depth"], ref[tkey]), fontsize=10)
        fig.tight_layout(rect=[0, 0, 1, 0.95])
        name = "error_%s.png" % scene
        fig.savefig(os.path.join(ctx.out, name))
        plt.close(fig)
        out.append(name)
    return out


def plot_estimate(ctx, err):
    rows = [r for r in err if not r["is_reference"]]
    if not rows:
        return
    plt = plt_module()
    fig, ax = plt.subplots(1, 2, figsize=(13, 5.2))
    lo = 1e-5
    for i, scene in enumerate(dict.fromkeys(r["scene"] for r in rows)):
        sel = [r for r in rows if r["scene"] == scene]
        for a, key in zip(ax, ["trunc_rms", "rmse"]):
            fixed = [r for r in sel if not r["adaptive"]]
            adap = [r for r in sel if r["adaptive"]]
            a.scatter([max(lo, r[key]) for r in fixed], [max(lo, r["est_rms"]) for r in fixed], s=14, color="C%d" % i,
                      alpha=0.7, label=scene)
            a.scatter([max(lo, r[key]) for r in adap], [max(lo, r["est_rms"]) for r in adap], s=14, color="C%d" % i,
                      alpha=0.7, marker="x")
    for a in ax:
        a.plot([lo, 1], [lo, 1], "k--", lw=1, label="estimate = measured")
        a.set_xscale("log")
        a.set_yscale("log")
        a.set_xlim(lo / 2, 1.5)
        a.set_ylim(lo / 2, 1.5)
        a.set_ylabel("FrameStats::errorEstimateRms")
    ax[0].set_xlabel("measured: RMS over pixels of max-channel error vs same samples at depth %d, threshold 0" %
                     ctx.cfg["error_ref_depth"])
    ax[1].set_xlabel("measured: RMSE vs the high-quality reference (includes sampling error)")
    ax[0].set_title("What the estimate bounds (points above the line: bound holds)")
    ax[1].set_title("Total error (the estimate does not cover sampling)")
    ax[0].legend(fontsize=8, loc="upper left")
    fig.suptitle("Renderer's error estimate vs measured error (o: fixed sampling, x: adaptive; zeros drawn at 1e-5)")
    fig.tight_layout(rect=[0, 0, 1, 0.95])
    fig.savefig(os.path.join(ctx.out, "error_estimate.png"))
    plt.close(fig)


# Report ----------------------------------------------------------------------------------------------------------

def fmt_ratio(x):
    if x is None or (isinstance(x, float) and math.isnan(x)):
        return "n/a"
    return "%.2f" % x


def commands_block(ctx, *sections):
    """The commands that produced a section's numbers, folded (GitHub renders <details>)."""
    cmds = [c for s in sections for c in (ctx.prov.get(s, {}).get("commands") or ctx.runner.by_section.get(s, []))]
    if not cmds:
        return ""
    return ("\n<details><summary>Commands (%d)</summary>\n\n```sh\n%s\n```\n</details>\n" %
            (len(cmds), "\n".join(cmds)))


def md_table(header, rows):
    out = ["| " + " | ".join(header) + " |", "|" + "|".join("---" for _ in header) + "|"]
    out += ["| " + " | ".join(str(c) for c in r) + " |" for r in rows]
    return "\n".join(out)


def geomean(v):
    v = [x for x in v if x and x > 0]
    return math.exp(sum(math.log(x) for x in v) / len(v)) if v else float("nan")


def report(ctx, started, elapsed):
    out = ctx.out
    rays = read_csv(os.path.join(out, "rays.csv"))
    agree = read_csv(os.path.join(out, "rays_agreement.csv"))
    build = read_csv(os.path.join(out, "build.csv"))
    frames = read_csv(os.path.join(out, "frames.csv"))
    pov = read_csv(os.path.join(out, "pov.csv"))
    vtk = read_csv(os.path.join(out, "vtk_opengl.csv"))
    upd = read_csv(os.path.join(out, "update.csv"))
    err = read_csv(os.path.join(out, "error.csv"))
    mpi = read_csv(os.path.join(out, "mpi.csv"))

    plot_rays(ctx, rays)
    plot_build(ctx, build)
    plot_scaling(ctx, frames, build)
    plot_update(ctx, upd)
    plot_vtk(ctx)
    error_plots = plot_error(ctx, err) if err else []
    plot_estimate(ctx, err)

    L = []
    head = []  # headline rows: (comparison, ours, anchor, speed ratio)
    L.append("# Whitted benchmark%s\n" % (" (quick mode: tiny inputs, not for quoting)" if ctx.cfg["error_quick"] else ""))
    prov_path = os.path.join(out, "sections.json")
    ctx.prov = json.load(open(prov_path)) if os.path.exists(prov_path) else {}
    head_at = len(L)
    if ctx.prov:
        cmds = list(dict.fromkeys(p["command"] for p in ctx.prov.values()))
        srcs = list(dict.fromkeys(p["sources"] for p in ctx.prov.values()))
        L.append("Produced by %s; sources: %s.\n" % (
            " and ".join("`%s`" % c for c in cmds) + (" (see the table for which section came from which)"
                                                       if len(cmds) > 1 else ""), "; ".join(srcs)))
        L.append("| section | started | took | load average (1 min) at start%s |\n|---|---|---|---|%s" % (
            " | command" if len(cmds) > 1 else "", "---|" if len(cmds) > 1 else ""))
        for name in SECTIONS:
            p = ctx.prov.get(name)
            if p:
                L.append("| %s | %s | %.0f s | %s |%s" % (name, p["started"], p["seconds"], p["load"],
                                                          " %d |" % (cmds.index(p["command"]) + 1) if len(cmds) > 1 else ""))
        L.append("")
    else:
        L.append("Produced by `%s` on %s in %.0f s; sources: %s.\n" % (
            ctx.runner.mask(" ".join(shlex.quote(a) for a in ctx.argv)), started, elapsed, ctx.git))
    if ctx.env:
        L.append("Versions: whitted_bench built with %s; Embree %s; %s; VTK %s; Linux %s.\n" % (
            ctx.env.get("compiler", "?"), ctx.env.get("embree", "?"), ctx.env.get("povray", "POV-Ray ?"),
            ctx.env.get("vtk", "?"), ctx.env.get("kernel", "?")))
    L.append("Machine: %s, %d hardware threads. Other jobs running on the machine are not excluded (load average "
             "above, 1-minute): ours and the anchors are measured alternately in the same run so wall-time ratios "
             "stay comparable, and every comparison is also given in CPU time, which waiting for a core does not "
             "inflate.\n" % (ctx.cpu, ctx.threads))
    L.append("Speed ratio = ours/anchor speed (anchor time / our time): **> 1 means Whitted is faster**. Times are "
             "medians over repeated runs after a warm-up; every command is listed in `commands.txt`, raw output in "
             "`logs/`.\n")
    if ctx.notes:
        L.append("Notes:\n" + "\n".join("- " + n for n in ctx.notes) + "\n")

    # Rays
    sec = []
    if rays:
        sec.append("## Ray throughput against Embree %s\n" % ctx.embree_version)
        sec.append("Same rays for both (%s image: primary rays through pixel centres; shadow rays from every "
                   "primary hit to the first light; incoherent rays in uniform random directions over the hemisphere "
                   "facing the viewer). Secondary rays start at our robust offset origin with tMin = 1e-5 x scene "
                   "diagonal for both engines; materials are made opaque so the shadow query is a pure any-hit "
                   "(Scene::transmittance vs rtcOccluded1); closest hits use Scene::intersect vs rtcIntersect1. "
                   "Geometry is rounded to float so both see identical primitives. One Embree geometry per "
                   "instance (triangles, SPHERE_POINT, ROUND_LINEAR_CURVE); Embree build quality medium.\n" %
                   ctx.cfg["ray_size"])
        def pick(s, kind, t, eng):
            m = [r for r in rays if r["scene"] == s and r["kind"] == kind and r["threads"] == t and r["engine"] == eng]
            return m[0] if m else None

        def cpu_rate(r):
            v = r.get("mrays_per_cpu_second", "")
            return v if isinstance(v, (int, float)) and v > 0 else float("nan")

        tab = []
        for s in dict.fromkeys(r["scene"] for r in rays):
            for kind in ["primary", "shadow", "incoherent"]:
                for t in sorted({r["threads"] for r in rays}):
                    o, e = pick(s, kind, t, "whitted"), pick(s, kind, t, "embree")
                    if not o:
                        continue
                    tab.append([s, kind, t, o["rays"], "%.2f" % o["mrays_median"],
                                "%.2f" % e["mrays_median"] if e else "n/a",
                                fmt_ratio(o["mrays_median"] / e["mrays_median"]) if e else "n/a",
                                fmt_ratio(cpu_rate(o) / cpu_rate(e)) if e else "n/a",
                                "%.0f" % o["nodes_per_ray"] if o["nodes_per_ray"] != "" else ""])
        sec.append(md_table(["scene", "rays", "threads", "count", "Whitted Mrays/s", "Embree Mrays/s",
                             "speed ratio (wall)", "speed ratio (CPU time)", "Whitted nodes/ray"], tab))
        sec.append("\nSpeed ratio (CPU time) compares rays per CPU-second of the tracing threads: it is immune to "
                   "other jobs taking cores away, which the wall-time ratio is only partly (the engines alternate run "
                   "by run).\n")
        sec.append(commands_block(ctx, "rays"))
        sec.append("\n![rays](rays.png)\n")
        scenes = list(dict.fromkeys(r["scene"] for r in rays))
        main = ctx.headline_scene if ctx.headline_scene in scenes else scenes[0]
        for kind in ["primary", "shadow", "incoherent"]:
            for t in sorted({r["threads"] for r in rays}):
                ratios = [pick(s, kind, t, "whitted")["mrays_median"] / pick(s, kind, t, "embree")["mrays_median"]
                          for s in scenes if pick(s, kind, t, "whitted") and pick(s, kind, t, "embree")]
                o, e = pick(main, kind, t, "whitted"), pick(main, kind, t, "embree")
                if o and e:
                    head.append(["%s rays, %d thr, %s (geomean over %d scenes: %s)" % (
                        kind, t, main, len(ratios), fmt_ratio(geomean(ratios))), "%.2f Mrays/s" % o["mrays_median"],
                        "Embree %.2f Mrays/s" % e["mrays_median"], fmt_ratio(o["mrays_median"] / e["mrays_median"]),
                        fmt_ratio(cpu_rate(o) / cpu_rate(e))])
        if agree:
            sec.append("\nHit agreement (differences at shared edges and grazing hits are expected; a 'tie' is a "
                       "different primitive at the same distance within 1e-4):\n")
            sec.append(md_table(["scene", "rays", "count", "hits Whitted", "hits Embree", "hit/miss differ",
                                 "other primitive", "of which ties", "max rel. t diff", "99.9% rel. t diff"],
                                [[a["scene"], a["kind"], a["rays"], a["hits_ours"], a["hits_embree"], a["hit_mismatch"],
                                  a["prim_mismatch"], a["prim_mismatch_same_t"], "%.2g" % a["t_rel_err_max"],
                                  "%.2g" % a["t_rel_err_p999"]] for a in agree]))
        L += sec
        sec = []

    # Build
    if build:
        L.append("\n## BVH build against Embree\n")
        L.append("Whitted: `Scene::commit` of freshly set geometry (validity checks, boxes, binned SAH, leaf-order "
                 "copies; the core picks its own build threads, there is no setting, so its rows carry the hardware "
                 "thread count) and `Bvh::build` alone on precomputed boxes. Memory: Whitted = BVH nodes + "
                 "index arrays + leaf-ordered triangle indices; Embree = bytes its memory monitor reports for the "
                 "build (its leaves embed the triangles), peak during the build in brackets. Primary Mrays/s "
                 "(512x512, all threads) shows what each build quality buys.\n")
        tab = []
        for r in build:
            cpu = r.get("cpu_seconds_median")
            tab.append([r["scene"], r["primitives"], r["engine"], r["variant"], r["threads"],
                        "%.1f / %.1f" % (r["seconds_median"] * 1e3, cpu * 1e3 if isinstance(cpu, float) else float("nan")),
                        "%.2f" % r["mprims_per_s"],
                        "%.1f (%.1f)" % (r["bytes_per_prim"], r["peak_bytes_per_prim"]),
                        "%.2f" % r["primary_mrays"] if r["primary_mrays"] != "" else ""])
        L.append(md_table(["scene", "prims", "engine", "variant", "threads", "ms (wall / CPU)", "Mprims/s",
                           "bytes/prim (peak)", "primary Mrays/s"], tab))
        L.append(commands_block(ctx, "build"))
        L.append("\n![build](build.png)\n")
        main = ctx.headline_scene if ctx.headline_scene in {r["scene"] for r in build} else build[0]["scene"]
        o = [r for r in build if r["scene"] == main and r["variant"] == "Scene::commit"]
        for q, t in [("low", ctx.threads), ("medium", ctx.threads), ("high", ctx.threads), ("medium", 1)]:
            e = [r for r in build if r["scene"] == main and r["engine"] == "embree" and r["variant"] == q and r["threads"] == t]
            if o and e:
                head.append(["BVH build %s vs Embree %s, %d thr (memory %.0f vs %.0f B/prim)" % (
                        main, q, t, o[0]["bytes_per_prim"], e[0]["bytes_per_prim"]), "%.2f Mprims/s" % o[0]["mprims_per_s"],
                        "%.2f Mprims/s" % e[0]["mprims_per_s"], fmt_ratio(o[0]["mprims_per_s"] / e[0]["mprims_per_s"]),
                    fmt_ratio(e[0]["cpu_seconds_median"] / o[0]["cpu_seconds_median"])
                    if isinstance(e[0].get("cpu_seconds_median"), float) and isinstance(o[0].get("cpu_seconds_median"), float) else ""])

    # POV-Ray
    if pov:
        L.append("\n## Whole frame against POV-Ray 3.7\n")
        L.append("`data/benchmark/classic.pov` is the classic scene term by term (same geometry, camera, light, "
                 "VTK-style ambient/diffuse/Phong, kr, kt, IOR), no antialiasing, `adc_bailout` = our threshold "
                 "1/255, `+WT%d`. POV-Ray counts the camera ray as trace level 1, so `max_trace_level` = our depth + 1 "
                 "(checked: level 2 reproduces our depth-1 image). Process wall time includes start-up (POV-Ray "
                 "needs ~0.7 s before tracing anything), parsing and PNG output; trace time is each program's own "
                 "timer.\n" % ctx.threads)
        tab = []
        for r in pov:
            tab.append([r["size"], "%.0f / %.0f" % (r["ours_trace_median"] * 1e3, r["ours_trace_cpu_median"] * 1e3),
                        "%.0f / %.0f" % (r["pov_trace_median"] * 1e3, r["pov_trace_cpu_median"] * 1e3),
                        "%s / %s" % (fmt_ratio(r["pov_trace_median"] / r["ours_trace_median"]),
                                     fmt_ratio(r["pov_trace_cpu_median"] / r["ours_trace_cpu_median"])),
                        "%.0f / %.0f" % (r["ours_wall_median"] * 1e3, r["ours_cpu_median"] * 1e3),
                        "%.0f / %.0f" % (r["pov_wall_median"] * 1e3, r["pov_cpu_median"] * 1e3),
                        "%s / %s" % (fmt_ratio(r["pov_wall_median"] / r["ours_wall_median"]),
                                     fmt_ratio(r["pov_cpu_median"] / r["ours_cpu_median"])),
                        "%.0f" % (r["ours_trace_warm_median"] * 1e3),
                        "%.2g (max %s/255)" % (r["image_rmse_8bit"], r.get("image_max_levels", "?"))])
            head.append(["classic %s vs POV-Ray 3.7, trace (whole process: %s)" % (
                r["size"], fmt_ratio(r["pov_wall_median"] / r["ours_wall_median"])),
                "%.0f ms" % (r["ours_trace_median"] * 1e3), "%.0f ms" % (r["pov_trace_median"] * 1e3),
                fmt_ratio(r["pov_trace_median"] / r["ours_trace_median"]),
                fmt_ratio(r["pov_trace_cpu_median"] / r["ours_trace_cpu_median"])])
        L.append(md_table(["size", "Whitted trace ms (wall / CPU)", "POV-Ray trace ms (wall / CPU)",
                           "speed ratio trace (wall / CPU)", "Whitted process ms (wall / CPU)",
                           "POV-Ray process ms (wall / CPU)", "speed ratio process (wall / CPU)",
                           "Whitted warm trace ms", "image difference (RMSE)"], tab))
        L.append(commands_block(ctx, "pov"))
        L.append("\n![pov](pov_compare.png)\n")

    # VTK
    vtk_frames = [r for r in frames if r["tag"] == "vtk"]
    if vtk_frames:
        ours = dict(vtk_frames[-1])
        # Ours was measured before and after the VTK runs: use the mean of both medians
        ours["seconds_median"] = statistics.mean(r["seconds_median"] for r in vtk_frames)
        cpus = [r["cpu_seconds_median"] for r in vtk_frames if isinstance(r.get("cpu_seconds_median"), float)]
        ours["cpu_seconds_median"] = statistics.mean(cpus) if cpus else float("nan")
        ours["commit_seconds"] = statistics.mean(r["commit_seconds"] for r in vtk_frames)
        L.append("\n## Whole frame against VTK's OpenGL renderer\n")
        L.append("%s (%d triangles) at %dx%d, same camera, lights and material (from `whitted_bench info`). VTK: "
                 "Mesa llvmpipe under `%s`, one window per configuration, frame = Render() + WaitForCompletion() "
                 "after a 0.5 degree azimuth; first frame (shader compile, upload) separately; CPU time = the VTK "
                 "process's (llvmpipe renders on its threads). Whitted: one key light with shadows + a fill light, "
                 "spp 1, depth 5, %d threads; steady frame = trace time after a camera move (no rebuild; mean of the "
                 "medians measured before and after the VTK runs), first frame = BVH build + trace.\n" % (
                     ours["scene"], ours["primitives"], ours["width"], ours["height"], " ".join(XVFB),
                     ours["threads"]))
        tab = [["Whitted core (shadows)", "", "%.0f" % ((ours["commit_seconds"] + ours["seconds_median"]) * 1e3),
                "%.0f / %.0f" % (ours["seconds_median"] * 1e3, ours["cpu_seconds_median"] * 1e3), "1.00 / 1.00",
                " / ".join("%.0f" % (r["seconds_median"] * 1e3) for r in vtk_frames) + " ms (before / after)"]]
        for r in vtk:
            label = {"opengl": "VTK OpenGL", "shadowmap": "VTK OpenGL + vtkShadowMapPass",
                     "whitted": "vtkWhittedPass"}.get(r["mode"], r["mode"])
            if r["status"] != "ok":
                tab.append([label, r["msaa"], "", "", "", r["status"]])
                continue
            ratio = r["seconds_median"] / ours["seconds_median"]
            rc = r.get("cpu_seconds_median")
            cratio = rc / ours["cpu_seconds_median"] if isinstance(rc, float) else float("nan")
            tab.append([label, r["msaa"], "%.0f" % (r["first_frame_seconds"] * 1e3),
                        "%.0f / %.0f" % (r["seconds_median"] * 1e3, rc * 1e3 if isinstance(rc, float) else float("nan")),
                        "%s / %s" % (fmt_ratio(ratio), fmt_ratio(cratio)), r.get("breakdown") or r.get("gl_renderer", "")])
            if r["mode"] != "whitted":
                head.append(["%s %dx%d vs %s, MSAA %d (steady frame; first frame: %s)" % (
                    ours["scene"], ours["width"], ours["height"], label, r["msaa"],
                    fmt_ratio(r["first_frame_seconds"] / (ours["commit_seconds"] + ours["seconds_median"]))),
                    "%.0f ms" % (ours["seconds_median"] * 1e3), "%.0f ms" % (r["seconds_median"] * 1e3), fmt_ratio(ratio),
                    fmt_ratio(cratio)])
        gl0 = [r for r in vtk if r["mode"] == "opengl" and r["msaa"] == 0 and r["status"] == "ok"]
        wp = [r for r in vtk if r["mode"] == "whitted" and r["status"] == "ok"]
        if gl0 and wp:
            head.append(["vtkWhittedPass (whole VTK frame) vs VTK OpenGL MSAA 0, %s %dx%d" % (
                ours["scene"], ours["width"], ours["height"]), "%.0f ms" % (wp[0]["seconds_median"] * 1e3),
                "%.0f ms" % (gl0[0]["seconds_median"] * 1e3), fmt_ratio(gl0[0]["seconds_median"] / wp[0]["seconds_median"]),
                fmt_ratio(gl0[0]["cpu_seconds_median"] / wp[0]["cpu_seconds_median"])
                if isinstance(wp[0].get("cpu_seconds_median"), float) else ""])
        L.append(md_table(["renderer", "MultiSamples", "first frame ms", "frame ms (wall / CPU)",
                           "speed ratio Whitted/this (wall / CPU)", "GL renderer / status / pass phases"], tab))
        if not wp:
            L.append("\nThe vtkWhittedPass row is filled in once `from whitted import vtkWhittedPass` works (pass "
                     "`--whitted-pythonpath DIR` or build the VTK module in --build-dir).\n")
        else:
            L.append("\nvtkWhittedPass = the whole VTK frame through the pass (scene conversion, tracing, compositing "
                     "into the GL framebuffer), same window setup as the OpenGL rows; its phases are the pass's own "
                     "timers.\n")
        L.append(commands_block(ctx, "vtk"))
        if os.path.exists(os.path.join(out, "vtk_compare.png")):
            L.append("![vtk](vtk_compare.png)\n")

    # Scaling
    if any(r["tag"].startswith("scale") for r in frames):
        L.append("\n## Scaling\n")
        tab = []
        for r in frames:
            if r["tag"].startswith("scale"):
                tab.append([r["tag"][6:], r["scene"], r["primitives"], "%dx%d" % (r["width"], r["height"]), r["threads"],
                            "%.1f" % (r["commit_seconds"] * 1e3), "%.1f" % (r["seconds_median"] * 1e3),
                            "%.2f" % r["mrays"]])
        L.append(md_table(["sweep", "scene", "prims", "size", "threads", "build ms", "trace ms", "Mrays/s"], tab))
        L.append(commands_block(ctx, "scaling"))
        L.append("\nParallel efficiency is T1 / (min(n, cores) x Tn); thread counts above the core count show the "
                 "cost of oversubscription.\n\n![scaling](scaling.png)\n")

    # Update
    if upd:
        L.append("\n## Update cost (what caching leaves out)\n")
        L.append("%s plus %d small glyph actors (UV spheres, ~16k triangles each) at %dx%d. Each case edits the "
                 "scene, calls commit() and renders; 'full rebuild' re-sets every object, as an adapter without "
                 "caching would.\n" % (upd[0]["scene"], upd[0]["instances"] - 1, upd[0]["width"], upd[0]["height"]))
        def cpu_ms(r, k):
            v = r.get(k)
            return "%.1f" % (v * 1e3) if isinstance(v, float) else ""
        L.append(md_table(["case", "commit ms (wall / CPU)", "trace ms (wall / CPU)", "total ms", "objects rebuilt",
                           "top level rebuilt"],
                          [[r["case"], "%.2f / %s" % (r["commit_seconds"] * 1e3, cpu_ms(r, "commit_cpu_seconds")),
                            "%.1f / %s" % (r["trace_seconds"] * 1e3, cpu_ms(r, "trace_cpu_seconds")),
                            "%.1f" % (r["total_seconds"] * 1e3), r["objects_rebuilt"], r["top_level_rebuilt"]]
                           for r in upd]))
        L.append(commands_block(ctx, "update"))
        L.append("\n![update](update.png)\n")

    # MPI
    if mpi:
        r0 = min(mpi, key=lambda r: r["ranks"])  # one rank: the triangle count without ghost cells
        L.append("\n## ParaView view under MPI (pvbatch)\n")
        L.append("The Whitted Ray Trace view in `pvbatch` (`testing/paraview/bench_still.py`): the wavelet contoured to "
                 "%d triangles as Whitted Surface (reflectance 0.2) with ParaView's light kit and shadows, %dx%d. "
                 "Under MPI the geometry is replicated to every rank and the image split between ranks (IceT "
                 "composites by depth). Still frame = Render() wall time on rank 0 after a 2-degree camera turn, "
                 "median of %d frames, then median over %d repetitions run alternately with the other "
                 "configurations; first frame = delivery + conversion + BVH build + trace. CPU time per frame is "
                 "read from /proc for every rank.\n" % (r0["triangles"], r0["width"], r0["height"],
                                                          ctx.cfg["mpi_frames"], max(r["rep"] for r in mpi) + 1))
        med = {}
        tab = []
        for ranks, threads in dict.fromkeys((r["ranks"], r["threads_per_rank"]) for r in mpi):
            rs = [r for r in mpi if r["ranks"] == ranks and r["threads_per_rank"] == threads]
            per_rank = [[float(v) for v in str(r["cpu_seconds_per_rank"]).split()] for r in rs]
            med[(ranks, threads)] = statistics.median(r["still_seconds"] for r in rs)
            tab.append(["%d x %d" % (ranks, threads), "%.3f" % med[(ranks, threads)],
                        "%.2f" % statistics.median(r["first_seconds"] for r in rs),
                        " + ".join("%.3f" % statistics.median(p[i] for p in per_rank) for i in range(ranks)),
                        "%.2f" % statistics.median(r["load"] for r in rs)])
        base = med.get((1, 1))
        for row, key in zip(tab, med):
            row.append("%.2f" % (base / med[key]) if base else "")
        L.append(md_table(["ranks x threads per rank", "still frame s", "first frame s", "CPU s per frame (rank 0 + 1)",
                           "load average", "speed-up vs 1 x 1"], tab))
        two = med.get((2, 1))
        hybrid = [k for k in med if k[0] == 1 and k[1] == 2]
        if base and two:
            L.append("\n2 ranks x 1 thread against 1 rank x 1 thread: **%.2fx**%s.\n" % (
                base / two, "; against 1 rank x 2 threads (the same cores, threads instead of ranks): %.2fx" % (
                    med[hybrid[0]] / two) if hybrid else ""))
        L.append(commands_block(ctx, "mpi"))

    # Error
    if err:
        L.append("\n## Error against run time\n")
        L.append("Reference per scene: %d spp, depth %d, threshold 0. Sweep: spp 1/4/16 (4 and 16 also adaptive) x "
                 "depth 1..8 x threshold 0, 1, 4, 16, 64 /255 (scenes without mirrors or glass: sampling only, since "
                 "depth and threshold cannot change them). Error on linear RGB clamped to [0,1]; SSIM: Gaussian 11x11, "
                 "sigma 1.5, mean over RGB. Full data: `error.csv`.\n" % (ctx.cfg["error_ref_spp"], ctx.cfg["error_ref_depth"]))
        tkey, _ = error_time_key(err)
        L.append("Cost is measured as %s. The machine this report was produced on was shared (see load average): "
                 "wall times of millisecond renders scatter by 2x there, CPU time and the ray count (`rays` in "
                 "the CSV, machine-independent) do not. 'Clearly better' = at least 10%% less cost at no more "
                 "RMSE (and fewer rays traced), or at least 10%% less RMSE at no more cost.\n" % (
                     "the CPU time of the render (all threads)" if tkey.startswith("cpu") else "wall time"))
        tab = []
        desc = lambda r: "spp %d%s d%d t%.0f" % (r["spp"], "a" if r["adaptive"] else "", r["depth"], r["threshold"] * 255)
        for scene in dict.fromkeys(r["scene"] for r in err):
            rows = [r for r in err if r["scene"] == scene and not r["is_reference"]]
            ref = [r for r in err if r["scene"] == scene and r["is_reference"]][0]
            d = [r for r in rows if r["is_default"]]
            if not d:
                continue
            d = d[0]
            better = dominated_by(rows, d, tkey)
            # The best alternative: least RMSE among those no costlier than the default, else the cheapest
            alt = min([r for r in better if r[tkey] <= d[tkey]] or better, key=lambda r: (r["rmse"], r[tkey])) \
                if better else None
            tab.append([scene, "%.2f s (%s rays)" % (ref[tkey], "{:,}".format(ref["rays"])),
                        "%.1f ms (%.1f ms wall, %s rays): RMSE %.4f, PSNR %.1f, SSIM %.4f" % (
                            d[tkey] * 1e3, d["seconds_median"] * 1e3, "{:,}".format(d["rays"]), d["rmse"], d["psnr"],
                            d["ssim"]),
                        "no (%d settings clearly better)" % len(better) if better else "yes",
                        "%s: %.1f ms, RMSE %.4f" % (desc(alt), alt[tkey] * 1e3, alt["rmse"]) if alt else "-",
                        "%.0f" % (ref[tkey] / d[tkey])])
        L.append(commands_block(ctx, "error"))
        L.append(md_table(["scene", "reference cost", "default settings (cost)", "default on the Pareto front",
                           "best clearly better setting", "reference / default cost"], tab))
        L.append("")
        for p in error_plots:
            L.append("![%s](%s)" % (p, p))
        # Estimate tightness
        L.append("\n### The renderer's error estimate\n")
        L.append("FrameStats::errorEstimateRms bounds what the depth cap and the threshold leave out (per pixel, "
                 "largest channel, clamped to 1). It is compared with the same quantity measured against a render "
                 "with the same samples at depth %d and threshold 0 (so sampling error cancels), and with the RMSE "
                 "against the high-quality reference (which includes sampling error it does not claim to "
                 "cover).\n" % ctx.cfg["error_ref_depth"])
        tab = []
        for scene in dict.fromkeys(r["scene"] for r in err):
            for adaptive in (0, 1):
                rows = [r for r in err if r["scene"] == scene and not r["is_reference"] and r["adaptive"] == adaptive]
                if not rows:
                    continue
                nz = [r for r in rows if r["trunc_rms"] > 1e-6]
                ratios = [r["est_rms"] / r["trunc_rms"] for r in nz]
                under = [r for r in rows if r["est_rms"] < r["trunc_rms"] - 1e-7]
                under_max = [r for r in rows if r["est_max"] < r["trunc_max"] - 1e-7]
                under_total = [r for r in rows if r["est_rms"] < r["rmse"]]
                tab.append([scene, "adaptive" if adaptive else "fixed", len(rows),
                            "%.3g / %.3g / %.3g" % (min(ratios), statistics.median(ratios), max(ratios)) if ratios else "n/a (no truncation error)",
                            "%d" % len(under), "%d" % len(under_max), "%d" % len(under_total)])
        L.append(md_table(["scene", "sampling", "settings", "estimate / measured (min / median / max)",
                           "underestimates (RMS)", "underestimates (max pixel)",
                           "estimate < RMSE vs reference"], tab))
        fixed = [r for r in err if not r["is_reference"] and not r["adaptive"]]
        L.append("\nThe test of the bound is the fixed-sampling rows: %d settings, %d underestimates of the RMS, %d of the "
                 "largest pixel. With adaptive sampling the comparison is not exact: which pixels get supersampled "
                 "depends on the first-pass image, hence on depth and threshold, so a render and its depth-%d twin "
                 "refine different pixels and their difference includes sampling error the estimate does not "
                 "claim to cover.\n" % (
                     len(fixed), sum(1 for r in fixed if r["est_rms"] < r["trunc_rms"] - 1e-7),
                     sum(1 for r in fixed if r["est_max"] < r["trunc_max"] - 1e-7), ctx.cfg["error_ref_depth"]))
        L.append("\n![estimate](error_estimate.png)\n")

    # Headline first
    H = ["## Headline\n", md_table(["comparison", "Whitted", "anchor", "speed ratio (wall)", "speed ratio (CPU time)"],
                                    head), ""]
    L[head_at:head_at] = H
    L.append("\n## Files\n")
    L.append("\n".join("- `%s`" % f for f in sorted(os.listdir(out)) if os.path.isfile(os.path.join(out, f))))
    with open(os.path.join(out, "benchmark.md"), "w") as f:
        f.write("\n".join(L) + "\n")
    with open(os.path.join(out, "commands.txt"), "w") as f:
        for name in SECTIONS:
            cmds = ctx.prov.get(name, {}).get("commands") or ctx.runner.by_section.get(name, [])
            if cmds:
                f.write("# %s\n%s\n" % (name, "\n".join(cmds)))
    return head


class Ctx:
    pass


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--build-dir", default="build", help="build tree (configured project or empty folder)")
    ap.add_argument("--bench", default="", help="path of an existing whitted_bench (skips building)")
    ap.add_argument("--out", default="results", help="results folder")
    ap.add_argument("--cache", default="", help="folder for generated meshes (default <out>/cache)")
    ap.add_argument("--quick", action="store_true", help="tiny end-to-end run for CI (< 60 s)")
    ap.add_argument("--sections", default=",".join(SECTIONS), help="subset of " + ",".join(SECTIONS))
    ap.add_argument("--whitted-pythonpath", default="", help="folder holding the `whitted` Python package")
    ap.add_argument("--report-only", action="store_true", help="rebuild report and plots from existing CSVs")
    ap.add_argument("--paraview-plugin", default="", help="WhittedView plugin for the mpi section "
                    "(default: found in ../paraview next to --build-dir)")
    ap.add_argument("--pv-pythonpath", default="", help="folder holding ParaView's `paraview` Python package "
                    "(default: ../pvprefix/usr/lib/python3/dist-packages next to --build-dir)")
    args = ap.parse_args()

    t_start = time.perf_counter()
    started = time.strftime("%Y-%m-%d %H:%M:%S")
    ctx = Ctx()
    ctx.args = args
    script = os.path.abspath(sys.argv[0])
    ctx.argv = ["/usr/bin/python3", os.path.relpath(script, REPO) if script.startswith(REPO + os.sep) else script]
    ctx.argv += sys.argv[1:]
    ctx.out = os.path.abspath(args.out)
    os.makedirs(ctx.out, exist_ok=True)
    ctx.cfg = config(args.quick)
    ctx.notes = []
    ctx.threads = os.cpu_count() or 1
    ctx.load_start = "%.2f %.2f %.2f" % os.getloadavg()
    ctx.cpu = platform.processor() or platform.machine()
    try:
        for line in open("/proc/cpuinfo"):
            if line.startswith("model name"):
                ctx.cpu = line.split(":", 1)[1].strip()
                break
    except OSError:
        pass
    ctx.headline_scene = "iso1m" if not args.quick else "iso60k"
    try:
        rev = subprocess.run(["git", "-C", REPO, "log", "-1", "--format=%h %s"], capture_output=True, text=True,
                             timeout=30).stdout.strip()
        dirty = subprocess.run(["git", "-C", REPO, "status", "--porcelain", "core"], capture_output=True, text=True,
                               timeout=30).stdout.strip()
        ctx.git = "commit `%s`%s" % (rev[:80], " with uncommitted changes in core/" if dirty else "")
    except (OSError, subprocess.TimeoutExpired):
        ctx.git = "unknown revision"
    ctx.runner = Runner(ctx.out)
    build = os.path.abspath(args.build_dir)
    ctx.runner.placeholders = [(ctx.out, "<out>"), (REPO, "<repo>"), (build, "<build>")]
    if all(os.path.isdir(os.path.join(os.path.dirname(build), d)) for d in ("paraview", "pvprefix")):
        ctx.runner.placeholders.append((os.path.dirname(build), "<builds>"))  # ./whitted.sh test's build root
    if args.bench:
        ctx.runner.placeholders.append((os.path.abspath(args.bench), "<whitted_bench>"))
    cache = os.path.abspath(args.cache or os.path.join(ctx.out, "cache"))
    os.makedirs(cache, exist_ok=True)
    ctx.runner.placeholders.append((cache, "<cache>"))

    sections = [s for s in args.sections.split(",") if s]
    unknown = [s for s in sections if s not in SECTIONS]
    if unknown:
        sys.exit("unknown sections: %s (known: %s)" % (", ".join(unknown), ",".join(SECTIONS)))
    needs_bench = not args.report_only and any(s != "mpi" for s in sections)  # mpi runs ParaView, not whitted_bench
    ctx.bench = find_bench(args, ctx.runner) if needs_bench else ""
    ctx.data = ensure_meshes(ctx.cfg["meshes"], cache, ctx.runner, ctx.notes) if needs_bench else \
        ",".join([DATA, cache])
    env_path = os.path.join(ctx.out, "environment.json")
    if ctx.bench:
        _, text, _ = ctx.runner.run([ctx.bench, "info", "--scene", "classic"], "info")
        info = json.loads(text)
        if not info.get("embree"):
            ctx.notes.append("whitted_bench was built without Embree: no Embree anchor (install libembree-dev)")
        env = dict(cpu=ctx.cpu, threads=ctx.threads, compiler=info.get("compiler", ""),
                   embree=info.get("embreeVersion") or "not built", kernel=platform.release())
        try:
            p = subprocess.run(["povray", "--version"], capture_output=True, text=True, timeout=30)
            env["povray"] = next((l.strip() for l in (p.stdout + p.stderr).splitlines() if l.startswith("POV-Ray")), "")
        except (OSError, subprocess.TimeoutExpired):
            env["povray"] = "not found"
        try:
            env["vtk"] = subprocess.run([VTK_PYTHON, "-c", "import vtkmodules.vtkCommonCore as c; "
                                         "print(c.vtkVersion.GetVTKVersion())"], capture_output=True, text=True,
                                        timeout=60).stdout.strip() or "not found"
        except (OSError, subprocess.TimeoutExpired):
            env["vtk"] = "not found"
        with open(env_path, "w") as f:
            json.dump(env, f, indent=1)
    ctx.env = json.load(open(env_path)) if os.path.exists(env_path) else {}
    ctx.embree_version = ctx.env.get("embree", "3")

    if not args.report_only:
        prov_path = os.path.join(ctx.out, "sections.json")
        prov = json.load(open(prov_path)) if os.path.exists(prov_path) else {}
        for name in SECTIONS:
            if name in sections:
                print("== %s" % name, flush=True)
                ctx.runner.section = name
                t0 = time.perf_counter()
                when, load = time.strftime("%Y-%m-%d %H:%M:%S"), "%.2f" % os.getloadavg()[0]
                globals()["section_" + name](ctx)
                took = time.perf_counter() - t0
                print("   %s done in %.1f s" % (name, took), flush=True)
                prov[name] = dict(command=ctx.runner.mask(" ".join(shlex.quote(a) for a in ctx.argv)), started=when, seconds=took,
                                  load=load, sources=ctx.git, commands=ctx.runner.by_section.get(name, []))
                with open(prov_path, "w") as f:
                    json.dump(prov, f, indent=1)

    elapsed = time.perf_counter() - t_start
    try:
        head = report(ctx, started, elapsed)
    except ImportError as e:  # matplotlib missing in this interpreter
        sys.exit("cannot write plots (%s): run with /usr/bin/python3 or install python3-matplotlib" % e)
    print("\nHeadline (speed ratio = ours/anchor, > 1: Whitted faster)")
    w = max([len(h[0]) for h in head] + [10])
    print("  %-*s  %-16s %-24s %-6s %s" % (w, "comparison", "Whitted", "anchor", "wall", "CPU"))
    for h in head:
        print("  %-*s  %-16s %-24s %-6s %s" % (w, h[0], h[1], h[2], h[3], h[4] if len(h) > 4 else ""))
    print("\nReport: %s (%.0f s)" % (os.path.join(ctx.out, "benchmark.md"), elapsed))
    # The outputs each section promises (the CI test relies on this check)
    expect = ["benchmark.md", "commands.txt"]
    if not args.report_only:
        per = {"rays": ["rays.csv", "rays.png"], "build": ["build.csv", "build.png"],
               "pov": ["pov.csv", "pov_compare.png"] if shutil.which("povray") else [],
               "vtk": ["frames.csv"] + (["vtk_opengl.csv", "vtk_compare.png"] if shutil.which("xvfb-run") and have_vtk() else []),
               "scaling": ["frames.csv", "scaling.png"], "update": ["update.csv", "update.png"],
               "error": ["error.csv", "error_estimate.png"] + ["error_%s.png" % s for s in ctx.cfg["error_scenes"]],
               "mpi": ["mpi.csv"] if mpi_tools(ctx) else []}
        for name in sections:
            expect += per.get(name, [])
    missing = [f for f in expect if not os.path.exists(os.path.join(ctx.out, f))]
    if missing:
        sys.exit("missing outputs: %s" % ", ".join(missing))
    return 0


if __name__ == "__main__":
    sys.exit(main())
