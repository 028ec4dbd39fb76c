"""Still-frame benchmark of the Whitted Ray Trace view (serial or under MPI); not part of ctest.

    [mpirun -np N] pvbatch bench_still.py --plugin P [--extent 122] [--size 800x600] [--threads T] [--frames K]

Wavelet over [-N, N]^3 contoured at 157 (N = 122: 1,007,456 triangles) as "Whitted Surface" (Reflectance 0.2)
with ParaView's light kit and shadows. After a first frame (delivery, conversion, BVH build), the camera
turns 2 degrees per frame and K still frames are timed on rank 0 (Render() wall time, which includes IceT
compositing under MPI), and the CPU time every rank spent per frame (read from /proc for all pvbatch
processes started by the same mpirun: the ranks of one node). On a machine shared with other work the
wall time depends on the load, while the CPU time per rank shows how the work is divided.
"""
import argparse
import os
import re
import statistics
import sys
import time

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import whitted_pvtest as wt  # noqa: E402

ap = argparse.ArgumentParser()
ap.add_argument("--plugin", required=True)
ap.add_argument("--extent", type=int, default=122)
ap.add_argument("--size", default="800x600")
ap.add_argument("--threads", type=int, default=0, help="tracing threads per rank (0 = all cores)")
ap.add_argument("--frames", type=int, default=5)
ap.add_argument("--replicate", type=int, default=1)
args = ap.parse_args()
size = [int(v) for v in args.size.split("x")]

from paraview import servermanager as sm  # noqa: E402
from paraview.simple import Contour, CreateView, Render, Show, Wavelet  # noqa: E402

wt.load_plugin(args.plugin)
ranks = sm.vtkProcessModule.GetProcessModule().GetNumberOfLocalPartitions()
view = CreateView("WhittedRayTraceView")
view.ViewSize = size
view.OrientationAxesVisibility = 0
view.NumberOfThreads = args.threads
view.ReplicateGeometry = args.replicate
n = args.extent
contour = Contour(Input=Wavelet(WholeExtent=[-n, n, -n, n, -n, n]), ContourBy=["POINTS", "RTData"],
                  Isosurfaces=[157.0], ComputeScalars=0)
display = Show(contour, view)
display.Representation = "Whitted Surface"
display.Reflectance = 0.2
display.Specular = 0.4
view.ResetCamera()



def rank_pids():
    """pvbatch processes with our parent (the ranks on this node), rank 0 (this process) first."""
    pids = [os.getpid()]
    for entry in os.listdir("/proc"):
        if entry.isdigit() and int(entry) != os.getpid():
            try:
                with open("/proc/%s/stat" % entry) as f:
                    fields = f.read().rsplit(")", 1)[1].split()
                with open("/proc/%s/comm" % entry) as f:
                    comm = f.read().strip()
            except OSError:
                continue
            if int(fields[1]) == os.getppid() and comm.startswith("pvbatch"):
                pids.append(int(entry))
    return pids


def cpu_seconds(pid):
    with open("/proc/%d/stat" % pid) as f:
        fields = f.read().rsplit(")", 1)[1].split()
    return (int(fields[11]) + int(fields[12])) / os.sysconf("SC_CLK_TCK")


start = time.perf_counter()
Render(view)
first = time.perf_counter() - start
pids = rank_pids()
cpu0 = [cpu_seconds(p) for p in pids]
times = []
for i in range(args.frames):
    view.GetActiveCamera().Azimuth(2.0)
    start = time.perf_counter()
    Render(view)
    times.append(time.perf_counter() - start)
cpu = [(cpu_seconds(p) - c) / args.frames for p, c in zip(pids, cpu0)]
print("CPU seconds per frame and rank: %s (load average %s)" %
      (" ".join("%.3f" % c for c in cpu), open("/proc/loadavg").read().split()[0]))
triangles = contour.GetDataInformation().GetNumberOfCells()
view.UpdatePropertyInformation()
report = view.GetProperty("LastFrameReport").GetData()
trace = re.search(r"trace ([0-9.]+) ms", report)
samples = re.search(r"([0-9]+) samples", report)
print("rank 0 traced %s samples in %s ms (last frame)" % (samples.group(1) if samples else "?",
                                                          trace.group(1) if trace else "?"))
print("ranks %d, threads/rank %s, replicate %d, %d triangles, %dx%d: first frame %.2f s, still frame median "
      "%.3f s (%s)" % (ranks, args.threads or "all", args.replicate, triangles, size[0], size[1], first,
                       statistics.median(times), " ".join("%.3f" % t for t in times)))
