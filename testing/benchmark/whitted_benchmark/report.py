"""benchmark.md from the results folder: provenance (which command, commit and load produced each section),
versions, the headline table, each section's text in order, the file list; also commands.txt."""
import os
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
    L += ["## Headline\n", md_table(["comparison", "Whitted", "anchor", "speed ratio (wall)",
                                     "speed ratio (CPU time)"], head), ""]
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
