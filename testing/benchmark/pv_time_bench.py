"""Time series: the Whitted Ray Trace view against ParaView's Render View in one pvbatch process (run by
run_benchmark.py's timeseries section):

    xvfb-run -a -s "-screen 0 1280x1024x24 -noreset" env PYTHONPATH=<pvprefix>/usr/lib/python3/dist-packages \
        pvbatch pv_time_bench.py --plugin WhittedView.so --csv time.csv [--extent 122] [--size 1024x768] \
        [--steps 4] [--first whitted|render] [--rep 0]

Both views with ParaView's defaults (light kit, background, orientation axes; the Whitted view traces shadows,
depth 5, 1 sample per pixel, all cores, time cache 1024 MB), the same camera, showing one time series made of
ParaView filters (testing/paraview/whitted_pvtest.time_series, no files) over the Contour of a Wavelet over
[-N, N]^3 at 157 (N = 122: about 1M triangles) as a plain Surface:
  deform    the isosurface's points move along z by a sine wave that travels with time (same connectivity)
  contour   the isosurface of value 157 + 8 t (new connectivity every step)
Each series is animated through its steps twice: the first pass (every step new to both views) and the replay
(every step seen before). Per step, the filter runs first, untimed, once for both views; then each view renders
at that time (its ViewTime), timed as Render() wall time and process CPU time; for the Whitted view the frame's
conversion, build and trace times and what it converted, rebuilt, refit and took from its time cache are
recorded too. The views alternate step by step; --first says which one renders first. One CSV row per frame.
Everything runs inside main(): pvbatch runs the programmable filters' scripts in this script's namespace.
"""
import argparse
import os
import re
import sys
import time

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path[:0] = [HERE, os.path.join(HERE, "..", "paraview")]
import whitted_pvtest as wt  # noqa: E402


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--plugin", required=True)
    ap.add_argument("--csv", required=True)
    ap.add_argument("--extent", type=int, default=122)
    ap.add_argument("--size", default="1024x768")
    ap.add_argument("--steps", type=int, default=4)
    ap.add_argument("--first", choices=["whitted", "render"], default="whitted")
    ap.add_argument("--rep", type=int, default=0)
    args = ap.parse_args()
    size = [int(v) for v in args.size.split("x")]

    from paraview.simple import Contour, Hide, Render, Show, Wavelet
    from pv_bench_views import append_csv, make_views, share_camera

    views, order = make_views(args.plugin, size, args.first)

    n = args.extent
    wavelet = Wavelet(WholeExtent=[-n, n, -n, n, -n, n])
    base = Contour(Input=wavelet, ContourBy=["POINTS", "RTData"], Isosurfaces=[157.0], ComputeScalars=0)
    series = {"deform": wt.time_series(base, "deform", args.steps, amplitude=0.04 * n),
              "contour": wt.time_series(wavelet, "contour", args.steps)}
    rows = []


    def whitted_info():
        v = views["whitted"]
        v.UpdatePropertyInformation()
        get = lambda name: v.GetProperty(name).GetData()  # noqa: E731
        report = get("LastFrameReport")
        phase = {k: float(m.group(1)) * 1e-3 if m else 0.0
                 for k, m in ((k, re.search(r"\b%s ([0-9.]+) ms" % k, report)) for k in ("conversion", "build", "trace"))}
        return dict(converted=get("LastGeometriesConverted"), rebuilt=get("LastObjectsRebuilt"),
                    refit=get("LastObjectsRefit"), cache_hits=get("LastTimeCacheHits"),
                    convert_seconds=phase["conversion"], build_seconds=phase["build"], trace_seconds=phase["trace"])


    def timed(name, mode, rep_pass, t, triangles):
        view = views[name]
        view.ViewTime = float(t)
        t0, c0 = time.perf_counter(), time.process_time()
        Render(view)
        row = dict(rep=args.rep, mode=mode, run=rep_pass, step=t, view=name, seconds=time.perf_counter() - t0,
                   cpu_seconds=time.process_time() - c0, triangles=triangles, width=size[0], height=size[1],
                   first=args.first, load=os.getloadavg()[0], converted=0, rebuilt=0, refit=0, cache_hits=0,
                   convert_seconds=0.0, build_seconds=0.0, trace_seconds=0.0)
        if name == "whitted":
            row.update(whitted_info())
        rows.append(row)


    for mode, src in series.items():
        for name in order:
            Show(src, views[name])
        src.UpdatePipeline(0.0)  # its bounds at the first step set the camera (untimed, as every step's filter)
        share_camera(views, src)
        for rep_pass in ("first", "replay"):
            for t in range(args.steps):
                src.UpdatePipeline(float(t))  # the filter is not what is compared
                triangles = src.GetDataInformation().GetNumberOfCells()
                for name in (order if t % 2 == 0 else order[::-1]):
                    timed(name, mode, rep_pass, t, triangles)
        for name in order:
            Hide(src, views[name])

    append_csv(args.csv, rows)
    for r in rows:
        print("%-8s %-7s %-6s t=%d %-7s: %8.1f ms (CPU %8.1f ms) converted %d rebuilt %d refit %d hits %d" % (
            r["mode"], r["run"], r["view"], r["step"], "", r["seconds"] * 1e3, r["cpu_seconds"] * 1e3, r["converted"],
            r["rebuilt"], r["refit"], r["cache_hits"]))


main()
sys.stdout.flush()
os._exit(0)
