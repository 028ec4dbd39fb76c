"""Whole frame against VTK's own OpenGL renderer (llvmpipe under Xvfb) on the isosurface: the Whitted core's frame
and vtkWhittedPass's whole VTK frame, each against VTK OpenGL with matching antialiasing (MSAA off vs 1 sample per
pixel, MSAA 8 vs 8 samples) and against VTK's shadow-map pass; the same lights cast shadows on every side."""
import json
import os
import statistics

from .. import plots
from ..markdown import commands_block, fmt_ratio, md_table, ms, ratio
from ..runner import (HERE, VTK_PYTHON, XVFB, available_scenes, drop_tags, fresh, is_num, mesh_path, read_csv,
                     write_csv, vtk_tools_ok, whitted_env)
from .pov import image_difference

LABELS = {"opengl": "VTK OpenGL", "shadowmap": "VTK OpenGL + vtkShadowMapPass", "whitted": "vtkWhittedPass"}


def run(ctx):
    c = ctx.cfg
    vtk_csv = fresh(ctx.path("vtk_opengl.csv"))
    diff_csv = fresh(ctx.path("vtk_image_difference.csv"))
    frames = ctx.path("frames.csv")
    drop_tags(frames, ["vtk"])
    scene, size = c["vtk_scene"], c["vtk_size"]
    if not available_scenes([scene], ctx.data):
        ctx.notes.append("mesh for %s missing: VTK comparison skipped" % scene)
        return
    spps = sorted({spp for _, spp in c["vtk_pairs"]})

    def ours(label):
        for spp in spps:
            ctx.runner.run([ctx.bench, "frame", "--scene", scene, "--data", ctx.data, "--sizes", size, "--spp",
                            str(spp), "--threads-list", "0", "--reps", str(c["frame_reps"]), "--warmup", "1", "--tag",
                            "vtk", "--csv", frames, "--png", ctx.path("vtk_ours_%s_spp%d.png" % (scene, spp))],
                           "ours %s %s spp %d%s" % (scene, size, spp, label))

    ours("")  # again after the VTK runs: the report uses the mean of both medians
    if not vtk_tools_ok():
        ctx.notes.append("xvfb-run or VTK Python missing: VTK OpenGL comparison skipped")
        return
    info = ctx.path(os.path.join("cache", scene + ".json"))
    os.makedirs(os.path.dirname(info), exist_ok=True)
    _, text, _ = ctx.runner.run([ctx.bench, "info", "--scene", scene, "--data", ctx.data], "info " + scene)
    with open(info, "w") as f:
        f.write(text)
    modes = [("opengl", msaa, 1) for msaa, _ in c["vtk_pairs"]] + [("shadowmap", 0, 1)]
    modes += [("whitted", 0, spp) for spp in spps]
    env = whitted_env(ctx.args)
    for mode, msaa, spp in modes:
        png = ctx.path("vtk_%s_msaa%d_spp%d.png" % (mode, msaa, spp))
        cmd = XVFB + [VTK_PYTHON, os.path.join(HERE, "vtk_gl_bench.py"), "--mesh", mesh_path(scene, ctx.data),
                      "--info", info, "--size", size, "--mode", mode, "--msaa", str(msaa), "--spp", str(spp), "--reps",
                      str(c["vtk_reps"]), "--warmup", "2", "--csv", vtk_csv, "--png", png]
        rc, _, _ = ctx.runner.run(cmd, "vtk %s msaa %d spp %d" % (mode, msaa, spp), env=env, check=False,
                                  timeout=900)
        if rc != 0:
            ctx.notes.append("VTK %s (MultiSamples %d, spp %d) failed (exit %d), see logs/" % (mode, msaa, spp, rc))
    # First frames again, each configuration in turn in a fresh process (one frame after the first to end the
    # script's loop): one process's first frame swings with its page faults (the pass's first build took 43-290 ms
    # over five processes) and with Mesa's on-disk shader cache, cold only for a configuration's first process
    first_csv = fresh(ctx.path("vtk_first.csv"))
    for k in range(c.get("vtk_first_runs", 0)):
        for mode, msaa, spp in modes:
            cmd = XVFB + [VTK_PYTHON, os.path.join(HERE, "vtk_gl_bench.py"), "--mesh", mesh_path(scene, ctx.data),
                          "--info", info, "--size", size, "--mode", mode, "--msaa", str(msaa), "--spp", str(spp),
                          "--reps", "1", "--warmup", "0", "--csv", first_csv]
            ctx.runner.run(cmd, "vtk first frame %d: %s msaa %d spp %d" % (k + 1, mode, msaa, spp), env=env,
                           check=False, timeout=900)
    ours(" again")
    # Each VTK image against our image with the same samples: shows the same scene, lights and shadows
    diffs = []
    for r in read_csv(vtk_csv):
        if r["status"] == "ok" and r.get("screenshot"):
            spp = r["spp"] if r["mode"] == "whitted" else (8 if r["msaa"] else 1)
            d = image_difference(ctx, ctx.path(r["screenshot"]), ctx.path("vtk_ours_%s_spp%d.png" % (scene, spp)))
            diffs.append(dict(mode=r["mode"], msaa=r["msaa"], spp=r["spp"], against_ours_spp=spp, **d))
    write_csv(diff_csv, diffs)


def outputs(ctx):
    return ["frames.csv"] + (["vtk_opengl.csv", "vtk_first.csv", "vtk_image_difference.csv", "vtk_compare.png"]
                             if vtk_tools_ok() else [])


def _first_frames(ctx, vtk):
    """Each row's first frame (wall, CPU) replaced by the median over its own process and the first-frame-only
    processes of the same configuration (vtk_first.csv); first_frames = how many, first_range = min-max wall."""
    extra = [r for r in read_csv(ctx.path("vtk_first.csv")) if r["status"] == "ok"]
    for r in vtk:
        if r["status"] != "ok":
            continue
        same = [r] + [x for x in extra if (x["mode"], x["msaa"], x.get("spp", 1)) == (r["mode"], r["msaa"],
                                                                                     r.get("spp", 1))]
        walls = [x["first_frame_seconds"] for x in same if is_num(x.get("first_frame_seconds"))]
        cpus = [x["first_frame_cpu_seconds"] for x in same if is_num(x.get("first_frame_cpu_seconds"))]
        r["first_frames"] = len(walls)
        r["first_range"] = "%s-%s" % (ms(min(walls)), ms(max(walls))) if walls else ""
        if walls:
            r["first_frame_seconds"] = statistics.median(walls)
        if cpus:
            r["first_frame_cpu_seconds"] = statistics.median(cpus)
    return vtk


def _ours(frames):
    """Our frames per samples per pixel: the mean of the medians measured before and after the VTK runs."""
    out = {}
    for spp in sorted({r["spp"] for r in frames}):
        rs = [r for r in frames if r["spp"] == spp]
        o = dict(rs[-1])
        for k in ["seconds_median", "cpu_seconds_median", "commit_seconds"]:
            vals = [r[k] for r in rs if is_num(r.get(k))]
            o[k] = statistics.mean(vals) if vals else float("nan")
        o["each"] = " / ".join(ms(r["seconds_median"]) for r in rs)
        out[spp] = o
    return out


def _setup_text(ctx, o1):
    """What was measured and how: scene, lights, shadows, the VTK and core frame definitions."""
    info_path = ctx.path(os.path.join("cache", o1["scene"] + ".json"))
    info = json.load(open(info_path)) if os.path.exists(info_path) else {}
    lights = info.get("lights", [])
    casting = [i for i, l in enumerate(lights) if l.get("castShadows")]
    light_text = "; ".join("light %d: %s%s, %s" % (
        i + 1, "headlight" if l.get("headlight") else ("positional" if l["positional"] else "directional"),
        " (intensity %g)" % l["intensity"], "casts shadows" if l.get("castShadows") else "casts no shadow")
        for i, l in enumerate(lights))
    return ("%s (%d triangles) at %dx%d, same camera, lights and material (from `whitted_bench info`). Lights: %s. "
            "Shadows: the Whitted core, vtkWhittedPass (a light casts shadows when its ShadowAttenuation > 0; the "
            "script sets 0 for the lights that cast none) and vtkShadowMapPass (headlights cast no shadow map) all "
            "shadow the same %s; plain VTK OpenGL draws no shadows. VTK: Mesa llvmpipe under `%s`, one window per "
            "configuration, frame = Render() + WaitForCompletion() after a 0.5 degree azimuth, median of %d; first "
            "frame (shader compile, upload; for the pass also conversion and BVH build) separately, the median over "
            "%d fresh processes per configuration taken in turn (Mesa's on-disk shader cache is cold only in a "
            "configuration's first process, as for a user's first session); CPU time = the "
            "VTK process's (llvmpipe renders on its threads). Whitted core: `whitted_bench frame`, depth 5, all "
            "cores; steady frame = trace time (no rebuild; mean of the medians measured before and after the VTK "
            "runs), first frame = BVH build + trace. Antialiasing is compared like for like: MSAA off against 1 "
            "sample per pixel, MSAA 8 against 8 samples per pixel (MSAA shades each pixel once and supersamples "
            "only coverage; 8 spp shades 8 times).\n" % (
                o1["scene"], o1["primitives"], o1["width"], o1["height"], light_text or "see info",
                "light" if len(casting) == 1 else "lights",
                " ".join(XVFB), ctx.cfg["vtk_reps"], 1 + ctx.cfg.get("vtk_first_runs", 0)))


def _frame_table(ctx, ours, vtk):
    """One row per renderer and sample count: first and steady frame, image difference against the core."""
    diffs = read_csv(ctx.path("vtk_image_difference.csv"))
    tab = []
    for spp, o in ours.items():
        tab.append(["Whitted core", "%d spp" % spp, ms(o["commit_seconds"] + o["seconds_median"]),
                    "%s / %s" % (ms(o["seconds_median"]), ms(o["cpu_seconds_median"])), "",
                    o["each"] + " ms (before / after)"])
    for r in vtk:
        samples = "%d spp" % r.get("spp", 1) if r["mode"] == "whitted" else "MSAA %d" % r["msaa"]
        if r["status"] != "ok":
            tab.append([LABELS.get(r["mode"], r["mode"]), samples, "", "", "", r["status"]])
            continue
        d = [x for x in diffs if (x["mode"], x["msaa"], x["spp"]) == (r["mode"], r["msaa"], r.get("spp", 1))]
        tab.append([LABELS.get(r["mode"], r["mode"]), samples,
                    "%s / %s (median of %d; %s)" % (ms(r["first_frame_seconds"]), ms(r.get("first_frame_cpu_seconds")),
                                                   r.get("first_frames", 1), r.get("first_range", "")),
                    "%s / %s" % (ms(r["seconds_median"]), ms(r.get("cpu_seconds_median"))),
                    "%.3g (SSIM %.3f, max %d/255)" % (d[0]["rmse"], d[0]["ssim"], d[0]["max_levels"]) if d else "",
                    r.get("breakdown") or r.get("gl_renderer", "")])
    return md_table(["renderer", "samples", "first frame ms (wall / CPU)", "frame ms (wall / CPU)",
                     "image vs Whitted core, same samples (RMSE)", "GL renderer / status / pass phases"], tab)


def _comparisons(ctx, ours, vtk, o1):
    """(label, ours row, anchor row, time key, CPU time key) for each like-for-like pair measured."""
    def vrow(mode, msaa, spp=1):
        m = [r for r in vtk if r["mode"] == mode and r["msaa"] == msaa and r.get("spp", 1) == spp and
             r["status"] == "ok"]
        return m[0] if m else None

    comp = []
    where = "%s %dx%d" % (o1["scene"], o1["width"], o1["height"])
    for msaa, spp in ctx.cfg["vtk_pairs"]:
        o, gl, wp = ours.get(spp), vrow("opengl", msaa), vrow("whitted", 0, spp)
        if wp and gl:
            comp.append(("vtkWhittedPass %d spp (whole VTK frame, shadows) vs VTK OpenGL MSAA %d, %s" % (
                spp, msaa, where), wp, gl, "seconds_median", "cpu_seconds_median"))
            comp.append(("vtkWhittedPass %d spp first frame vs VTK OpenGL MSAA %d first frame, %s" % (
                spp, msaa, where), wp, gl, "first_frame_seconds", "first_frame_cpu_seconds"))
        if o and gl:
            comp.append(("Whitted core %d spp (shadows) vs VTK OpenGL MSAA %d, %s" % (spp, msaa, where), o, gl,
                         "seconds_median", "cpu_seconds_median"))
    sm = vrow("shadowmap", 0)
    if sm and 1 in ours:
        comp.append(("Whitted core 1 spp vs VTK OpenGL + shadow maps, %s" % where, ours[1], sm, "seconds_median",
                     "cpu_seconds_median"))
    wp1 = vrow("whitted", 0, 1)
    if sm and wp1:
        comp.append(("vtkWhittedPass 1 spp vs VTK OpenGL + shadow maps, %s" % where, wp1, sm, "seconds_median",
                     "cpu_seconds_median"))
    return comp


def report(ctx, head):
    frames = [r for r in read_csv(ctx.path("frames.csv")) if r["tag"] == "vtk"]
    vtk = _first_frames(ctx, read_csv(ctx.path("vtk_opengl.csv")))
    if not frames:
        return []
    plots.vtk(ctx, frames, vtk)
    ours = _ours(frames)
    o1 = ours[min(ours)]
    L = ["\n## Whole frame against VTK's OpenGL renderer\n", _setup_text(ctx, o1), _frame_table(ctx, ours, vtk)]

    # Comparisons (speed ratio = anchor time / ours), also into the headline table
    ctab = []
    for label, o, a, key, cpu_key in _comparisons(ctx, ours, vtk, o1):
        rw = ratio(a[key], o[key])
        rc = ratio(a.get(cpu_key), o.get(cpu_key))
        ctab.append([label, ms(o[key]), ms(a[key]), fmt_ratio(rw), fmt_ratio(rc)])
        head.append([label, "%s ms" % ms(o[key]), "%s ms" % ms(a[key]), fmt_ratio(rw), fmt_ratio(rc)])
    if ctab:
        L.append("\nComparisons (speed ratio = anchor time / Whitted time, > 1: Whitted faster):\n")
        L.append(md_table(["comparison", "Whitted ms", "anchor ms", "speed ratio (wall)", "speed ratio (CPU)"],
                          ctab))
    if not any(r["mode"] == "whitted" and r["status"] == "ok" for r in vtk):
        L.append("\nThe vtkWhittedPass rows are filled in once `from whitted import vtkWhittedPass` works (pass "
                 "`--whitted-pythonpath DIR` or build the VTK module in --build-dir).\n")
    else:
        L.append("\nvtkWhittedPass = the whole VTK frame through the pass (scene conversion, tracing, compositing "
                 "into the GL framebuffer), same window setup as the OpenGL rows (MultiSamples 0: the pass "
                 "antialiases by its own samples); its phases are the pass's own timers.\n")
    L.append(commands_block(ctx, "vtk"))
    if os.path.exists(ctx.path("vtk_compare.png")):
        L.append("![vtk](vtk_compare.png)\n")
    return L
