"""3D glyphs (vtkGlyph3DMapper) traced as instances by vtkWhittedPass against VTK's OpenGL glyph mapper
(vtk_glyph_bench.py): first frame, frame after a camera turn and the memory each process grows by, per glyph
count."""
import os

from ..markdown import commands_block, fmt_ratio, md_table, ms, ratio
from ..runner import HERE, VTK_PYTHON, XVFB, fresh, read_csv, vtk_tools_ok, whitted_env

LABELS = {"opengl": "VTK OpenGL (vtkOpenGLGlyph3DMapper)", "whitted": "vtkWhittedPass (1 spp, shadows)"}


def run(ctx):
    c = ctx.cfg
    path = fresh(ctx.path("glyphs.csv"))
    if not vtk_tools_ok():
        ctx.notes.append("xvfb-run or VTK Python missing: glyph comparison skipped")
        return
    env = whitted_env(ctx.args)
    # Full: one process per renderer and count (the memory of that process alone); quick: both in one process
    modes = ["opengl,whitted"] if c["quick"] else ["opengl", "whitted"]
    for n in c["glyph_counts"]:
        for mode in modes:
            cmd = XVFB + [VTK_PYTHON, os.path.join(HERE, "vtk_glyph_bench.py"), "--glyphs", str(n), "--mode", mode,
                          "--size", c["glyph_size"], "--reps", str(c["glyph_reps"]), "--csv", path]
            rc, _, _ = ctx.runner.run(cmd, "glyphs %s %d" % (mode, n), env=env, check=False, timeout=1800)
            if rc != 0:
                ctx.notes.append("glyphs %s %d failed (exit %d), see logs/" % (mode, n, rc))


def outputs(ctx):
    return ["glyphs.csv"] if vtk_tools_ok() else []


def report(ctx, head):
    rows = read_csv(ctx.path("glyphs.csv"))
    if not rows:
        return []
    r0 = rows[0]
    L = ["\n## 3D glyphs against VTK's OpenGL glyph mapper\n",
         "N cones (8 sides, 16 triangles) placed by a vtkGlyph3DMapper (oriented by a vector array, scaled and "
         "coloured by a scalar) over a floor with one positional light, %dx%d "
         "(`testing/benchmark/vtk_glyph_bench.py`). vtkWhittedPass traces each glyph as an instance of the cone "
         "(one instance record and one per-instance colour per glyph, one material) with shadows, 1 sample per "
         "pixel, depth 5; VTK OpenGL draws them instanced on llvmpipe (MultiSamples 0, no shadows). The window "
         "first renders the floor alone; first frame = Render() once the glyphs are shown (Whitted: conversion, "
         "one instance per glyph, top-level BVH build, trace); frame = median over %s frames after a 0.5 degree "
         "azimuth. Memory = the process's resident set growth from showing the glyphs to its last frame (one "
         "process per row in the full run; the quick run measures both in one).\n" % (
             r0["width"], r0["height"], r0["runs"])]
    tab = []
    for r in rows:
        if r["status"] != "ok":
            tab.append([r["glyphs"], LABELS.get(r["mode"], r["mode"]), "", "", "", "", r["status"]])
            continue
        extra = "%s instances, %s triangles, BVH %.1f MB; first frame: %s; frame: %s" % (
            r["instances"], r["triangles"], r["bvh_mb"], r["first_breakdown"], r["breakdown"]) \
            if r["mode"] == "whitted" else "%s polygons per glyph" % r["triangles"]
        tab.append([r["glyphs"], LABELS.get(r["mode"], r["mode"]),
                    "%s / %s" % (ms(r["first_frame_seconds"]), ms(r["first_frame_cpu_seconds"])),
                    "%s / %s" % (ms(r["seconds_median"]), ms(r["cpu_seconds_median"])),
                    "%.0f" % r["rss_growth_mb"], extra, r["status"]])
    L.append(md_table(["glyphs", "renderer", "first frame ms (wall / CPU)", "frame ms (wall / CPU)",
                       "memory growth MB",
                       "scene", "status"], tab))
    for n in sorted({r["glyphs"] for r in rows}):
        sel = {m: [r for r in rows if r["glyphs"] == n and r["mode"] == m and r["status"] == "ok"]
               for m in ("whitted", "opengl")}
        if sel["whitted"] and sel["opengl"]:
            w, g = sel["whitted"][0], sel["opengl"][0]
            head.append(["%d glyphs, vtkWhittedPass (shadows) vs VTK OpenGL glyph mapper, %dx%d; memory %.0f MB vs "
                         "%.0f MB" % (n, w["width"], w["height"], w["rss_growth_mb"], g["rss_growth_mb"]),
                         "%s ms" % ms(w["seconds_median"]), "%s ms" % ms(g["seconds_median"]),
                         fmt_ratio(ratio(g["seconds_median"], w["seconds_median"])),
                         fmt_ratio(ratio(g["cpu_seconds_median"], w["cpu_seconds_median"]))])
    L.append(commands_block(ctx, "glyphs"))
    return L
