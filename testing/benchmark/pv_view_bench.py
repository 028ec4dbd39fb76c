"""The Whitted Ray Trace view against ParaView's Render View in one pvbatch process (not part of ctest on its own;
run by run_benchmark.py's paraview section):

    xvfb-run -a -s "-screen 0 1280x1024x24 -noreset" env PYTHONPATH=<pvprefix>/usr/lib/python3/dist-packages \
        pvbatch pv_view_bench.py --plugin WhittedView.so --csv pv.csv [--extent 122] [--size 1024x768] \
        [--still 5] [--changes 3] [--first whitted|render] [--rep 0] [--all-lights] [--fresh]

Both views with ParaView's defaults (light kit, background, orientation axes; the Whitted view traces shadows
from the key light, depth 5, 1 sample per pixel, all cores; with --all-lights a third Whitted view, whitted_all,
traces shadows from all five lights of the light kit), the same camera, showing the same Contour of a Wavelet over
[-N, N]^3 at 157 (N = 122: 1,007,456 triangles) as a plain Surface. Before timing, each view renders a small
sphere once (window, OpenGL context, shaders) that is then hidden, so "first frame" is what a user waits for when
a new 1M-triangle result appears in an open view; unless --fresh, each view has also shown (and hidden) an earlier
result of the same size (the contour at 150), so the timed first frame is not the process's first large one.
The contour filter runs before, untimed; the camera is set from its bounds without rendering any view
(share_camera: paraview.simple.ResetCamera would render the view), so neither view has seen the contour before
its timed first frame. Timed per view, as Render() wall time and the process CPU time during it (all threads: the
tracer's and llvmpipe's):
  first     the first frame of the contour: the representation's update (ParaView's geometry filter) and data
            delivery, then upload and draw (Render View) or conversion, BVH build and trace (Whitted view)
  still     a frame after the camera turns 2 degrees (--still of them)
  geometry  a frame after the contour value changes (--changes of them; the filter runs before, untimed, once
            for both views)
The views alternate frame by frame; --first says which one renders first (the driver alternates it between
processes). One CSV row per timed frame.
"""
import argparse
import os
import sys
import time

ap = argparse.ArgumentParser()
ap.add_argument("--plugin", required=True)
ap.add_argument("--csv", required=True)
ap.add_argument("--extent", type=int, default=122)
ap.add_argument("--size", default="1024x768")
ap.add_argument("--still", type=int, default=5)
ap.add_argument("--changes", type=int, default=3)
ap.add_argument("--first", choices=["whitted", "render"], default="whitted")
ap.add_argument("--rep", type=int, default=0)
ap.add_argument("--all-lights", action="store_true",
                help="a third view, whitted_all: every light of the light kit casts shadows")
ap.add_argument("--fresh", action="store_true",
                help="no earlier result: the timed first frame is the process's first large one in each view")
args = ap.parse_args()
size = [int(v) for v in args.size.split("x")]

from paraview.simple import Contour, Hide, Render, Show, Wavelet  # noqa: E402

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from pv_bench_views import append_csv, make_views, share_camera  # noqa: E402

views, order = make_views(args.plugin, size, args.first, args.all_lights)

n = args.extent
wavelet = Wavelet(WholeExtent=[-n, n, -n, n, -n, n])
if not args.fresh:
    # An earlier result of the same size, shown, rendered and hidden in every view (untimed): a process's first
    # large frame in a view pays for its first large allocations (the Render View's took 1.5x as long as its next
    # new result's, at load 9), which a session that has shown data before has behind it
    earlier = Contour(Input=wavelet, ContourBy=["POINTS", "RTData"], Isosurfaces=[150.0], ComputeScalars=0)
    for name in order:
        Show(earlier, views[name])
        Render(views[name])
        Hide(earlier, views[name])
contour = Contour(Input=wavelet, ContourBy=["POINTS", "RTData"], Isosurfaces=[157.0], ComputeScalars=0)
contour.UpdatePipeline()  # the filter is not what is compared
triangles = contour.GetDataInformation().GetNumberOfCells()
for name in order:
    Show(contour, views[name])
share_camera(views, contour)

rows = []


def timed(name, event, index):
    view = views[name]
    t0, c0 = time.perf_counter(), time.process_time()
    Render(view)
    rows.append(dict(rep=args.rep, view=name, event=event, index=index, seconds=time.perf_counter() - t0,
                     cpu_seconds=time.process_time() - c0, triangles=triangles, width=size[0], height=size[1],
                     first=args.first, load=os.getloadavg()[0]))


for name in order:
    timed(name, "first", 0)
for i in range(args.still):
    for name in (order if i % 2 == 0 else order[::-1]):
        views[name].GetActiveCamera().Azimuth(2.0)
        timed(name, "still", i)
for i in range(args.changes):
    contour.Isosurfaces = [157.0 + (i + 1)]
    contour.UpdatePipeline()
    for name in (order if i % 2 == 0 else order[::-1]):
        timed(name, "geometry", i)

append_csv(args.csv, rows)
for r in rows:
    print("%-8s %-9s %d: %8.1f ms (CPU %8.1f ms)" % (r["view"], r["event"], r["index"], r["seconds"] * 1e3,
                                                      r["cpu_seconds"] * 1e3))
print("%d triangles, %dx%d" % (triangles, size[0], size[1]))
