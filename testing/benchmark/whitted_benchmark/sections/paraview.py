"""The Whitted Ray Trace view against ParaView's Render View in the same pvbatch process (pv_view_bench.py):
first frame of a new 1M-triangle contour, still frame after a camera turn, frame after the contour value changes;
ParaView's defaults (light kit, 1024x768)."""
import statistics

from ..markdown import commands_block, fmt_ratio, md_table, ms, ratio
from ..runner import read_csv, run_view_bench

EVENTS = [("first", "first frame (new contour shown)"), ("still", "still frame after a 2-degree camera turn"),
          ("geometry", "frame after the contour value changes")]


def run(ctx):
    c = ctx.cfg
    run_view_bench(ctx, "paraview", "pv_view_bench.py", "paraview.csv",
                   ["--extent", str(c["pv_extent"]), "--size", c["pv_size"], "--still", str(c["pv_still"]),
                    "--changes", str(c["pv_changes"]), "--all-lights"], c["pv_reps"], timeout=2400)


def outputs(ctx):
    return ["paraview.csv"]


def report(ctx, head):
    rows = read_csv(ctx.path("paraview.csv"))
    if not rows:
        return []
    r0 = rows[0]
    reps = len({r["rep"] for r in rows})
    L = ["\n## ParaView: Whitted view against the Render View (pvbatch)\n",
         "One `pvbatch` process holds both views with ParaView's defaults (light kit, background, orientation "
         "axes; the Whitted view: shadows from the light kit's key light (its default, ShadowsFromBrightestLightOnly), "
         "depth 5, 1 sample per pixel, all cores; a second Whitted view with shadows from all five lights of the "
         "light kit is timed beside it (rows marked 'all lights'); the "
         "Render View: OpenGL on llvmpipe, no shadows), the same camera, %dx%d, showing the same Contour "
         "(Wavelet, %d triangles) as a plain Surface (`testing/benchmark/pv_view_bench.py`). Each view first "
         "renders a small sphere (window, context, shaders) and shows, renders and hides an earlier result of the "
         "same size (the contour at 150), untimed, so the first frame is that of a new result in an open view of "
         "a session that has shown data: the representation's update and data delivery, then upload + draw "
         "(Render View) or conversion + BVH build + trace; the camera is set from the contour's bounds without "
         "rendering (runs before 2026-12-04 reset it with ResetCamera, which rendered the Render View: its "
         "'first' frame was then a repeat frame of data already delivered and uploaded, and no earlier result "
         "was shown). Geometry change = "
         "contour value +1 (the filter runs once before, untimed). Frames alternate between the views; %d "
         "process%s, alternating which view goes first. Time = Render() wall time, median over all frames of "
         "all processes; CPU = the process's CPU time during Render().\n" % (
             r0["width"], r0["height"], r0["triangles"], reps, "" if reps == 1 else "es")]
    tab = []
    for event, label in EVENTS:
        for view, suffix in (("whitted", ""), ("whitted_all", " (all lights)")):
            sel = {v: [r for r in rows if r["event"] == event and r["view"] == v] for v in (view, "render")}
            if not sel[view] or not sel["render"]:
                continue
            med = {v: (statistics.median(r["seconds"] for r in rs), statistics.median(r["cpu_seconds"] for r in rs))
                   for v, rs in sel.items()}
            rw, rc = ratio(med["render"][0], med[view][0]), ratio(med["render"][1], med[view][1])
            tab.append([label + suffix, len(sel[view]), "%s / %s" % (ms(med[view][0]), ms(med[view][1])),
                        "%s / %s" % (ms(med["render"][0]), ms(med["render"][1])), fmt_ratio(rw), fmt_ratio(rc)])
            if view == "whitted" or event == "still":
                head.append(["ParaView %s%s, Whitted view vs Render View, %d triangles %dx%d" % (
                    label, suffix, r0["triangles"], r0["width"], r0["height"]), "%s ms" % ms(med[view][0]),
                    "%s ms" % ms(med["render"][0]), fmt_ratio(rw), fmt_ratio(rc)])
    L.append(md_table(["frame", "frames per view", "Whitted view ms (wall / CPU)", "Render View ms (wall / CPU)",
                       "speed ratio (wall)", "speed ratio (CPU)"], tab))
    L.append("\nLoad average during the frames: %.2f-%.2f.\n" % (min(r["load"] for r in rows),
                                                                 max(r["load"] for r in rows)))
    L.append(commands_block(ctx, "paraview"))
    return L
