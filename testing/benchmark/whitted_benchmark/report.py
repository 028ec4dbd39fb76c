"""benchmark.md from the results folder: provenance (which command, commit and load produced each section),
versions, the headline table, each section's text in order, the file list; also commands.txt."""
import os
import re
import shlex

from .markdown import md_table
from .sections import MODULES, NAMES


def write(ctx, started, elapsed):
    """Writes benchmark.md and commands.txt; returns the headline rows."""
    head = []  # [comparison, Whitted, anchor, speed ratio wall, speed ratio CPU]
    body = []
    for module in MODULES:
        body += module.report(ctx, head)
    L = ["# Whitted benchmark%s\n" % (" (quick mode: tiny inputs, not for quoting)" if ctx.cfg["quick"] else "")]
    L += provenance(ctx, started, elapsed)
    if ctx.env:
        L.append("Versions: whitted_bench built with %s; Embree %s; %s; VTK %s; Linux %s.\n" % (
            ctx.env.get("compiler", "?"), ctx.env.get("embree", "?"), ctx.env.get("povray", "POV-Ray ?"),
            ctx.env.get("vtk", "?"), ctx.env.get("kernel", "?")))
    L.append("Machine: %s, %d usable cores. Other jobs running on the machine are not excluded (load average above, "
             "1-minute): ours and the anchors are measured alternately in the same run so wall-time ratios stay "
             "comparable, and every comparison is also given in CPU time, which waiting for a core does not "
             "inflate.\n" % (ctx.env.get("cpu", "?"), ctx.threads))
    L.append("Speed ratio = ours/anchor speed (anchor time / our time): **> 1 means Whitted is faster**. Times are "
             "medians over repeated runs after a warm-up; every command is listed in `commands.txt`, raw output in "
             "`logs/`. Every figure here is computed from the CSV files of this folder (`--report-only` redraws "
             "this report from them).\n")
    if ctx.notes:
        L.append("Notes:\n" + "\n".join("- " + n for n in ctx.notes) + "\n")
    L += ["## Headline\n", "The comparisons a user reads first (at most %d rows; every comparison is in the next "
          "table).\n" % MAX_KEY_ROWS, md_table(HEAD_COLUMNS, key_rows(head)), "",
          "## All comparisons\n", md_table(HEAD_COLUMNS, head), ""]
    L += body
    L.append("\n## Files\n")
    L.append("\n".join("- `%s`" % f for f in sorted(os.listdir(ctx.out)) if os.path.isfile(ctx.path(f))))
    with open(ctx.path("benchmark.md"), "w") as f:
        f.write("\n".join(L) + "\n")
    with open(ctx.path("commands.txt"), "w") as f:
        for name in NAMES:
            cmds = ctx.prov.get(name, {}).get("commands") or ctx.runner.by_section.get(name, [])
            if cmds:
                f.write("# %s\n%s\n" % (name, "\n".join(cmds)))
    return head


def provenance(ctx, started, elapsed):
    if not ctx.prov:
        return ["Produced by `%s` on %s in %.0f s; sources: %s.\n" % (
            ctx.runner.mask(" ".join(shlex.quote(a) for a in ctx.argv)), started, elapsed, ctx.git)]
    cmds = list(dict.fromkeys(p["command"] for p in ctx.prov.values()))
    srcs = list(dict.fromkeys(p["sources"] for p in ctx.prov.values()))
    many = len(cmds) > 1
    L = ["Produced by %s; sources: %s.\n" % (
        " and ".join("`%s`" % c for c in cmds) + (" (see the table for which section came from which)" if many
                                                   else ""), "; ".join(srcs)),
         "| section | started | took | load average (1 min) at start%s |\n|---|---|---|---|%s" % (
             " | command" if many else "", "---|" if many else "")]
    for name in NAMES:
        p = ctx.prov.get(name)
        if p:
            L.append("| %s | %s | %.0f s | %s |%s" % (name, p["started"], p["seconds"], p["load"],
                                                      " %d |" % (cmds.index(p["command"]) + 1) if many else ""))
    L.append("")
    return L


HEAD_COLUMNS = ["comparison", "Whitted", "anchor", "speed ratio (wall)", "speed ratio (CPU time)"]
MAX_KEY_ROWS = 10
# The headline, in the order a VTK or ParaView user asks: frames against what they use today, then the rays and
# builds against Embree and the memory. Each pattern picks the first row of the full table it matches.
KEY_PATTERNS = [
    r"^vtkWhittedPass 1 spp \(whole VTK frame",
    r"^vtkWhittedPass 1 spp first frame",
    r"^vtkWhittedPass 1 spp frames 2-6",
    r"^ParaView still frame(?!.*all lights)",
    r"^ParaView still frame.*\(all lights\)",
    r"^ParaView first frame(?!.*all lights)",
    r"^ParaView frame after the contour value changes(?!.*all lights)",
    r"^\S+ volume, vtkWhittedPass \(effects off\) vs the faster VTK mapper",
    r"^classic \S+ vs POV-Ray 3.7, frame CPU",
]
RAY_KINDS = ["primary", "shadow", "incoherent"]


def key_rows(head):
    """At most MAX_KEY_ROWS rows of head: the KEY_PATTERNS rows, one row joining the single-thread ray rates
    against Embree's default mode (primary / shadow / incoherent, the headline scene) and the first SAH build row
    (with the memory)."""
    def first(pattern):
        return next((r for r in head if re.search(pattern, r[0])), None)
    rows = [r for r in (first(p) for p in KEY_PATTERNS) if r]
    rays = [first(r"^%s rays, 1 thr, \S+ vs Embree \(" % k) for k in RAY_KINDS]
    if all(rays):
        scene = rays[0][0].split(", ")[2].split(" ")[0]
        joined = lambda i, unit="": " / ".join(r[i].replace(" Mrays/s", "").replace("Embree ", "") for r in rays) + unit
        rows.append(["rays, 1 thr, %s vs Embree: %s" % (scene, " / ".join(RAY_KINDS)), joined(1, " Mrays/s"),
                     joined(2, " Mrays/s"), joined(3), joined(4)])
    build = first(r"^SAH build .* vs Embree medium, 1 thr")
    if build:
        rows.append(build)
    return rows[:MAX_KEY_ROWS]


README_BEGIN = "<!-- benchmark figures: generated by run_benchmark.py --readme; do not edit by hand -->"
README_END = "<!-- end of benchmark figures -->"


def readme_block(ctx, head, link):
    """The README's figures: the headline table of this results folder, where it came from, and a link to the
    full report."""
    if not ctx.prov:
        raise SystemExit("%s has no sections.json: which commit produced these results is unknown" % ctx.out)
    srcs = list(dict.fromkeys(p["sources"] for p in ctx.prov.values()))
    when = sorted(p["started"] for p in ctx.prov.values())
    loads = [float(p["load"]) for p in ctx.prov.values() if p.get("load")]
    L = [README_BEGIN,
         ("Quick mode (tiny inputs, not for quoting). " if ctx.cfg["quick"] else "") + "From %s, %s%s on %s (%d usable cores); full report: [%s](%s)." % (
             "; ".join(srcs), "run %s to %s" % (when[0], when[-1]),
             ", load average %.2f-%.2f at section starts" % (min(loads), max(loads)) if loads else "",
             ctx.env.get("cpu", "?"), ctx.threads, "benchmark.md", link),
         "",
         md_table(HEAD_COLUMNS, key_rows(head)),
         "",
         "All %d comparisons of that run: [benchmark.md, All comparisons](%s#all-comparisons)." % (len(head), link),
         README_END]
    return "\n".join(L)


def update_readme(path, ctx, head):
    """Replaces the block between README_BEGIN and README_END in path with readme_block(); the link to the full
    report is made relative to the README. Exits with a message if the markers are missing."""
    text = open(path).read()
    i, j = text.find(README_BEGIN), text.find(README_END)
    if i < 0 or j < i:
        raise SystemExit("%s has no benchmark-figures block (%s ... %s)" % (path, README_BEGIN, README_END))
    link = os.path.relpath(ctx.path("benchmark.md"), os.path.dirname(os.path.abspath(path)))
    block = readme_block(ctx, head, link)
    with open(path, "w") as f:
        f.write(text[:i] + block + text[j + len(README_END):])
    written = open(path).read()
    missing = [row[0] for row in key_rows(head) if "| %s |" % row[0] not in written]
    if missing or not key_rows(head):
        raise SystemExit("%s: the benchmark-figures block lacks rows: %s" % (path, ", ".join(missing) or "all"))
