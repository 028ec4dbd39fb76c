"""Interaction test and benchmark of the Whitted Ray Trace view on a wavelet isosurface.

    pvbatch test_interaction.py --plugin P [--extent N] [--size WxH] [--frames K] [--max-interactive S]

Wavelet (RTAnalyticSource) over [-N, N]^3 contoured at 157 (N = 30: 60k triangles, the ctest default;
N = 122: 1,007,456 triangles, the benchmark), shown as "Whitted Surface" with ParaView's light kit.
Measures a still frame, then K interactive frames while the camera orbits (vtkSMViewProxy::InteractiveRender,
what the GUI calls while the mouse drags), then the still frame that ends the interaction, and checks:
  - interactive frames convert no geometry and build no BVH (the pass's cache is hit every frame),
  - ParaView's level of detail is not used, even with LODThreshold 0 (no decimated geometry to convert),
  - interactive frames are traced at reduced quality and the final still frame at full resolution,
  - optionally, the median interactive frame is below --max-interactive seconds.
"""
import argparse
import os
import statistics
import sys
import time

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import whitted_pvtest as wt  # noqa: E402

ap = argparse.ArgumentParser()
ap.add_argument("--plugin", required=True)
ap.add_argument("--extent", type=int, default=30)
ap.add_argument("--size", default="800x600")
ap.add_argument("--frames", type=int, default=12)
ap.add_argument("--max-interactive", type=float, default=0.0, help="fail if the median exceeds this (s)")
ap.add_argument("--screenshot", help="save the final still frame here")
args = ap.parse_args()
size = [int(v) for v in args.size.split("x")]

from paraview.simple import Contour, CreateView, Render, SaveScreenshot, Show, Wavelet  # noqa: E402

wt.load_plugin(args.plugin)
view = CreateView("WhittedRayTraceView")
view.ViewSize = size
view.OrientationAxesVisibility = 0
view.LODThreshold = 0.0  # ParaView would now use decimated geometry while interacting; the view must not

n = args.extent
wavelet = Wavelet(WholeExtent=[-n, n, -n, n, -n, n])
contour = Contour(Input=wavelet, ContourBy=["POINTS", "RTData"], Isosurfaces=[157.0], ComputeScalars=0)
t0 = time.perf_counter()
contour.UpdatePipeline()
triangles = contour.GetDataInformation().GetNumberOfCells()
print("isosurface: %d triangles (extent %d, %.2f s)" % (triangles, n, time.perf_counter() - t0))
display = Show(contour, view)
display.Representation = "Whitted Surface"
display.Reflectance = 0.2
display.Specular = 0.4
view.ResetCamera()
smview = view.SMProxy
client_view = view.GetClientSideObject()


def info(name):
    view.UpdatePropertyInformation()
    return view.GetProperty(name).GetData()


def timed(fn):
    start = time.perf_counter()
    fn()
    return time.perf_counter() - start


first = timed(lambda: Render(view))
print("first still frame (conversion + BVH + trace): %.3f s; converted %d, rebuilt %d" %
      (first, info("LastGeometriesConverted"), info("LastObjectsRebuilt")))
cam = view.GetActiveCamera()
cam.Azimuth(1.0)
still = timed(lambda: Render(view))
print("still frame: %.3f s (view %dx%d, max depth %d, shadows %d)" % (still, size[0], size[1], view.MaxDepth,
                                                                       view.Shadows))

times, reductions, problems = [], [], []
for i in range(args.frames):
    cam.Azimuth(3.0)
    cam.Elevation(0.5)
    times.append(timed(smview.InteractiveRender))
    reductions.append(info("LastImageReduction"))
    converted, rebuilt = info("LastGeometriesConverted"), info("LastObjectsRebuilt")
    if converted or rebuilt:
        problems.append("interactive frame %d converted %d geometries / built %d BVHs" % (i, converted, rebuilt))
    if client_view.GetUsedLODForLastRender():
        problems.append("interactive frame %d used level-of-detail geometry" % i)
print("interactive frames (s): " + " ".join("%.3f" % t for t in times))
print("image reduction per frame: " + " ".join(str(r) for r in reductions))
median = statistics.median(times[2:] if len(times) > 4 else times)
print("interactive median: %.3f s (target %.3f s)" % (median, view.InteractiveFrameTime))

final = timed(lambda: Render(view))
print("still frame after interaction: %.3f s, reduction %d" % (final, info("LastImageReduction")))
if info("LastImageReduction") != 1:
    problems.append("the still frame after interaction was not traced at full resolution")
if args.screenshot:
    SaveScreenshot(args.screenshot, view, ImageResolution=size)
print(info("LastFrameReport"))

if args.max_interactive and median > args.max_interactive:
    problems.append("median interactive frame %.3f s > %.3f s" % (median, args.max_interactive))
if problems:
    wt.fail("; ".join(problems))
print("OK")
