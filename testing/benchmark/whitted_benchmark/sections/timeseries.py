"""Time series in ParaView (pv_time_bench.py): per time step, the Whitted view against the Render View in the same
pvbatch process, first pass and replay, for a deforming isosurface (points move: refit) and an isosurface whose
value changes (new connectivity: rebuild); the replay restores each step from the view's time cache."""
import statistics

from ..markdown import commands_block, fmt_ratio, md_table, ms, ratio
from ..runner import read_csv, run_view_bench

MODES = [("deform", "points move (same connectivity)"), ("contour", "contour value changes (new connectivity)")]
RUNS = [("first", "first pass"), ("replay", "replay")]


def run(ctx):
    c = ctx.cfg
    run_view_bench(ctx, "timeseries", "pv_time_bench.py", "timeseries.csv",
                   ["--extent", str(c["ts_extent"]), "--size", c["ts_size"], "--steps", str(c["ts_steps"])],
                   c["ts_reps"], timeout=3600)


def outputs(ctx):
    return ["timeseries.csv"]


def report(ctx, head):
    rows = read_csv(ctx.path("timeseries.csv"))
    if not rows:
        return []
    r0 = rows[0]
    reps = len({r["rep"] for r in rows})
    steps = len({r["step"] for r in rows})
    L = ["\n## ParaView: time series, per time step (pvbatch)\n",
         "One `pvbatch` process holds the Whitted view and the Render View with ParaView's defaults (as in the "
         "section above), %dx%d, showing one time series of %d steps built from ParaView filters "
         "(`testing/benchmark/pv_time_bench.py`): the Wavelet's isosurface (about %d triangles) whose points move "
         "along a travelling sine wave (same connectivity: the Whitted view refits its BVH), or whose value changes "
         "every step (new connectivity: rebuilt with the fast builder). Each series is played twice: the first pass "
         "(every step new) and the replay (every step seen before: the Whitted view restores it from its time "
         "cache, the Render View delivers and uploads it again). The filter runs before each step, untimed. Time = "
         "Render() wall time per step, median over the steps after the first (the first step of a first pass is "
         "a new object: see the section above) of %d process%s; the Whitted view's own split comes from its frame "
         "report.\n" % (r0["width"], r0["height"], steps, r0["triangles"], reps, "" if reps == 1 else "es")]
    tab = []
    for mode, mlabel in MODES:
        for run_, rlabel in RUNS:
            sel = {v: [r for r in rows if r["mode"] == mode and r["run"] == run_ and r["view"] == v and
                       (run_ == "replay" or r["step"] > 0)] for v in ("whitted", "render")}
            if not sel["whitted"] or not sel["render"]:
                continue
            med = lambda rs, k: statistics.median(r[k] for r in rs)  # noqa: E731
            w, rv = sel["whitted"], sel["render"]
            rw = ratio(med(rv, "seconds"), med(w, "seconds"))
            rc = ratio(med(rv, "cpu_seconds"), med(w, "cpu_seconds"))
            what = "%g converted, %g rebuilt, %g refit, %g cache hits" % tuple(
                med(w, k) for k in ("converted", "rebuilt", "refit", "cache_hits"))
            tab.append(["%s, %s" % (mlabel, rlabel), len(w), "%s / %s" % (ms(med(w, "seconds")),
                                                                          ms(med(w, "cpu_seconds"))),
                        "%s / %s / %s" % (ms(med(w, "convert_seconds")), ms(med(w, "build_seconds")),
                                          ms(med(w, "trace_seconds"))), what,
                        "%s / %s" % (ms(med(rv, "seconds")), ms(med(rv, "cpu_seconds"))), fmt_ratio(rw),
                        fmt_ratio(rc)])
            head.append(["ParaView time step (%s, %s), Whitted view vs Render View, %d triangles %dx%d" % (
                mode, rlabel, r0["triangles"], r0["width"], r0["height"]), "%s ms" % ms(med(w, "seconds")),
                "%s ms" % ms(med(rv, "seconds")), fmt_ratio(rw), fmt_ratio(rc)])
    L.append(md_table(["time series", "steps per view", "Whitted view ms (wall / CPU)",
                       "Whitted convert / build / trace ms", "Whitted per step (median)",
                       "Render View ms (wall / CPU)", "speed ratio (wall)", "speed ratio (CPU)"], tab))
    L.append("\nLoad average during the frames: %.2f-%.2f.\n" % (min(r["load"] for r in rows),
                                                                 max(r["load"] for r in rows)))
    L.append(commands_block(ctx, "timeseries"))
    return L
