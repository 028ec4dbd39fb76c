"""The command line of the benchmark (run_benchmark.py calls main())."""
import argparse
import json
import os
import platform
import shlex
import subprocess
import sys
import time

from . import report
from .config import config
from .runner import REPO, VTK_PYTHON, Context, Runner, ensure_meshes, find_bench
from .sections import BY_NAME, NAMES


def parse_args(doc):
    ap = argparse.ArgumentParser(description=doc, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--build-dir", default="build", help="build tree (configured project or empty folder)")
    ap.add_argument("--bench", default="", help="path of an existing whitted_bench (skips building)")
    ap.add_argument("--out", default="results", help="results folder")
    ap.add_argument("--cache", default="", help="folder for generated meshes (default <out>/cache)")
    ap.add_argument("--quick", action="store_true", help="tiny end-to-end run for CI")
    ap.add_argument("--sections", default=",".join(NAMES), help="subset of " + ",".join(NAMES))
    ap.add_argument("--whitted-pythonpath", default="", help="folder holding the `whitted` Python package")
    ap.add_argument("--report-only", action="store_true", help="rebuild report and plots from existing CSVs")
    ap.add_argument("--readme", default="", help="also rewrite the benchmark-figures block of this README from "
                    "the results (e.g. README.md with --report-only --out data/benchmark/results)")
    ap.add_argument("--error-scenes", default="", help="error section: these scenes (comma-separated) instead of "
                    "the configured ones")
    ap.add_argument("--error-progressive-only", action="store_true", help="error section: of the fixed settings "
                    "only the default (the progressive mode's starting point), then the progressive mode")
    ap.add_argument("--error-budgets", default="", help="error section: the progressive mode's time budgets as "
                    "multiples of the default frame's time, comma-separated (default 1.5,3,6,12)")
    ap.add_argument("--paraview-plugin", default="", help="WhittedView plugin for the paraview and mpi sections "
                    "(default: found in ../paraview next to --build-dir)")
    ap.add_argument("--pv-pythonpath", default="", help="folder holding ParaView's `paraview` Python package "
                    "(default: ../pvprefix/usr/lib/python3/dist-packages next to --build-dir)")
    return ap.parse_args()


def git_description():
    try:
        rev = subprocess.run(["git", "-C", REPO, "log", "-1", "--format=%h %s"], capture_output=True, text=True,
                             timeout=30).stdout.strip()
        dirty = subprocess.run(["git", "-C", REPO, "status", "--porcelain", "core", "plugin", "testing/benchmark"],
                               capture_output=True, text=True, timeout=30).stdout.strip()
        return "commit `%s`%s" % (rev[:80], " with uncommitted changes" if dirty else "")
    except (OSError, subprocess.TimeoutExpired):
        return "unknown revision"


def cpu_name():
    try:
        for line in open("/proc/cpuinfo"):
            if line.startswith("model name"):
                return line.split(":", 1)[1].strip()
    except OSError:
        pass
    return platform.processor() or platform.machine()


def environment(ctx):
    """Versions of everything measured, from whitted_bench info and the tools themselves (environment.json)."""
    _, text, _ = ctx.runner.run([ctx.bench, "info", "--scene", "classic"], "info")
    info = json.loads(text)
    if not info.get("embree"):
        ctx.notes.append("whitted_bench was built without Embree: no Embree anchor (install libembree-dev)")
    env = dict(cpu=cpu_name(), threads=ctx.threads, compiler=info.get("compiler", ""),
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
    return env


def main(doc=""):
    args = parse_args(doc)
    t_start = time.perf_counter()
    started = time.strftime("%Y-%m-%d %H:%M:%S")
    out = os.path.abspath(args.out)
    os.makedirs(out, exist_ok=True)
    ctx = Context(args, config(args.quick), out, Runner(out))
    if args.error_scenes:
        ctx.cfg["error_scenes"] = [s for s in args.error_scenes.split(",") if s]
        if args.sections == "error":  # only the meshes these scenes need
            ctx.cfg["meshes"] = [m for m in ctx.cfg["meshes"] if "iso" + m in ctx.cfg["error_scenes"]]
    ctx.cfg["error_progressive_only"] = args.error_progressive_only
    ctx.cfg["error_budgets"] = args.error_budgets
    script = os.path.abspath(sys.argv[0])
    ctx.argv = ["/usr/bin/python3", os.path.relpath(script, REPO) if script.startswith(REPO + os.sep) else script]
    ctx.argv += sys.argv[1:]
    ctx.git = git_description()
    build = os.path.abspath(args.build_dir)
    ctx.runner.placeholders = [(out, "<out>"), (REPO, "<repo>"), (build, "<build>")]
    if all(os.path.isdir(os.path.join(os.path.dirname(build), d)) for d in ("paraview", "pvprefix")):
        ctx.runner.placeholders.append((os.path.dirname(build), "<builds>"))  # ./whitted.sh test's build root
    if args.bench:
        ctx.runner.placeholders.append((os.path.abspath(args.bench), "<whitted_bench>"))
    for path, name in [(args.whitted_pythonpath, "<whitted-pythonpath>"), (args.paraview_plugin, "<plugin>"),
                       (args.pv_pythonpath, "<pv-pythonpath>")]:
        if path:
            ctx.runner.placeholders.append((os.path.abspath(path), name))
    cache = os.path.abspath(args.cache or os.path.join(out, "cache"))
    os.makedirs(cache, exist_ok=True)
    ctx.runner.placeholders.append((cache, "<cache>"))

    sections = [s for s in args.sections.split(",") if s]
    unknown = [s for s in sections if s not in BY_NAME]
    if unknown:
        sys.exit("unknown sections: %s (known: %s)" % (", ".join(unknown), ",".join(NAMES)))
    # The ParaView sections run pvbatch, not whitted_bench
    needs_bench = not args.report_only and any(s not in ("mpi", "paraview", "timeseries") for s in sections)
    ctx.bench = find_bench(args, ctx.runner) if needs_bench else ""
    ctx.data = ensure_meshes(ctx.cfg["meshes"], cache, ctx.runner, ctx.notes) if needs_bench else \
        ",".join([os.path.join(REPO, "data", "benchmark"), cache])
    env_path = ctx.path("environment.json")
    if ctx.bench:
        with open(env_path, "w") as f:
            json.dump(environment(ctx), f, indent=1)
    ctx.env = json.load(open(env_path)) if os.path.exists(env_path) else {}

    prov_path = ctx.path("sections.json")
    ctx.prov = json.load(open(prov_path)) if os.path.exists(prov_path) else {}
    if not args.report_only:
        for name in NAMES:
            if name not in sections:
                continue
            print("== %s" % name, flush=True)
            ctx.runner.section = name
            t0 = time.perf_counter()
            when, load = time.strftime("%Y-%m-%d %H:%M:%S"), "%.2f" % os.getloadavg()[0]
            BY_NAME[name].run(ctx)
            took = time.perf_counter() - t0
            print("   %s done in %.1f s" % (name, took), flush=True)
            ctx.prov[name] = dict(command=ctx.runner.mask(" ".join(shlex.quote(a) for a in ctx.argv)),
                                  started=when, seconds=took, load=load, sources=ctx.git,
                                  commands=ctx.runner.by_section.get(name, []))
            with open(prov_path, "w") as f:
                json.dump(ctx.prov, f, indent=1)

    elapsed = time.perf_counter() - t_start
    try:
        head = report.write(ctx, started, elapsed)
    except ImportError as e:  # matplotlib missing in this interpreter
        sys.exit("cannot write plots (%s): run with /usr/bin/python3 or install python3-matplotlib" % e)
    print("\nHeadline (speed ratio = ours/anchor, > 1: Whitted faster)")
    w = max([len(h[0]) for h in head] + [10])
    print("  %-*s  %-18s %-28s %-6s %s" % (w, "comparison", "Whitted", "anchor", "wall", "CPU"))
    for h in head:
        print("  %-*s  %-18s %-28s %-6s %s" % (w, h[0], h[1], h[2], h[3], h[4]))
    print("\nReport: %s (%.0f s)" % (ctx.path("benchmark.md"), elapsed))
    if args.readme:
        report.update_readme(args.readme, ctx, head)
        print("README figures: %s" % args.readme)
    # The outputs each section promises (the CI test relies on this check)
    expect = ["benchmark.md", "commands.txt"]
    if not args.report_only:
        for name in sections:
            if name not in ctx.skipped:
                expect += BY_NAME[name].outputs(ctx)
    missing = [f for f in expect if not os.path.exists(ctx.path(f))]
    if missing:
        sys.exit("missing outputs: %s" % ", ".join(missing))
    return 0
