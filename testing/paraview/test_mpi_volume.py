"""A volume under MPI: the Wavelet as Volume with an opaque sphere inside it, above a mirror floor, traced on two
ranks equals the single-process image (issue 29: a volume split over ranks).

    pvbatch test_mpi_volume.py --plugin P --tmp DIR --name NAME                     (the single-process reference)
    mpirun -np 2 pvbatch test_mpi_volume.py --plugin P --tmp DIR --name NAME --reference R --expect-ranks 2

Under MPI the Wavelet's image data is split between the ranks (checked: Process Id Scalars sees ids 0 and 1).
The view delivers every representation's data to every rank (ReplicateGeometry), the volume's image data included,
and splits the image; IceT assembles it. Checks:
  - every run: the volume and the sphere are traced (frame report: 1 volume, no prop drawn by OpenGL... on the
    single process; under MPI rank 0's report), and the mirror shows the volume;
  - --reference: the image equals the single-process image within the compositing round-off
    (whitted_pvtest.COMPOSITING), the same rule as the surface scenes' MPI tests;
  - --expect-ranks: the data is split between the ranks, and with ReplicateGeometry off the image changes (each rank
    would trace its own block alone): the replication is what makes the image right.
"""
import argparse
import os
import re
import sys

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import whitted_pvtest as wt  # noqa: E402

ap = argparse.ArgumentParser()
ap.add_argument("--plugin", required=True)
ap.add_argument("--tmp", required=True)
ap.add_argument("--name", required=True)
ap.add_argument("--reference", help="the single-process image (compositing oracle)")
ap.add_argument("--expect-ranks", type=int, default=0)
args = ap.parse_args()
os.makedirs(args.tmp, exist_ok=True)

from paraview import servermanager as sm  # noqa: E402
from paraview.simple import (ColorBy, GetColorTransferFunction, Plane, ProcessIdScalars, Render, Show,  # noqa: E402
                             Sphere, Wavelet)

wt.load_plugin(args.plugin)
check = wt.Checks()
SIZE = [300, 240]
view = wt.make_view(SIZE)
wavelet = Wavelet()
volume = Show(wavelet, view)
volume.Representation = "Volume"
ColorBy(volume, ("POINTS", "RTData"))
GetColorTransferFunction("RTData").ApplyPreset("Cool to Warm", True)
ball = Show(Sphere(Center=[0.0, 0.0, 4.0], Radius=4.0, ThetaResolution=32, PhiResolution=32), view)
ball.DiffuseColor = [0.9, 0.9, 0.2]
floor = Show(Plane(Origin=[-40.0, -14.0, 40.0], Point1=[40.0, -14.0, 40.0], Point2=[-40.0, -14.0, -40.0]), view)
floor.Representation = "Whitted Surface"
floor.DiffuseColor = [0.0, 0.0, 0.0]
floor.AmbientColor = [0.0, 0.0, 0.0]
floor.Specular = 0.0
floor.Reflectance = 1.0
wt.set_camera(view, (0.0, 14.0, 75.0), (0.0, -6.0, 0.0))
Render(view)
image = os.path.join(args.tmp, args.name + ".png")
pixels = wt.screenshot(view, image, SIZE)

view.UpdatePropertyInformation()
text = view.GetProperty("LastFrameReport").GetData()
m = re.search(r"(\d+) actors traced .*?(\d+) volumes traced \((\d+) converted, (\d+) transfer updates\)", text)
if not m:
    print(text)
    wt.fail("no vtk line in the frame report")
actors, volumes = int(m.group(1)), int(m.group(2))
print("frame report (rank 0): %d actors traced, %d volumes traced" % (actors, volumes))
check(actors == 2 and volumes == 1, "the sphere, the floor and the volume are traced")
# The mirror floor shows the volume: reflected volume colours below the floor's horizon (the lower third here)
background = np.array([0.32, 0.34, 0.43]) * 255.0
lower = pixels[: SIZE[1] // 3]  # rows bottom to top
seen = int((np.abs(lower - background).max(axis=2) > 8).sum())
print("pixels of the lower third off the background (the reflection): %d" % seen)
check(seen > 1000, "the mirror shows the volume")

if args.reference:
    ok, err = wt.compare_image(image, args.reference, args.tmp, **wt.COMPOSITING)
    print("against the single-process image: %.4f%% of the pixels beyond %d/255" % (
        100.0 * err, wt.COMPOSITING["tolerance"]))
    check(ok, "the image equals the single-process image within the compositing round-off")

if args.expect_ranks:
    ranks = sm.vtkProcessModule.GetProcessModule().GetNumberOfLocalPartitions()
    print("ranks: %d" % ranks)
    check(ranks == args.expect_ranks, "runs on %d ranks" % args.expect_ranks)
    pid = ProcessIdScalars(Input=wavelet)
    pid.UpdatePipeline()
    rng = pid.PointData["ProcessId"].GetRange()
    print("ProcessId range of the Wavelet: %s" % (rng,))
    check(rng[1] >= args.expect_ranks - 1, "the image data is split between the ranks")
    view.ReplicateGeometry = 0
    alone = wt.screenshot(view, os.path.join(args.tmp, args.name + "_noreplication.png"), SIZE)
    changed = int((np.abs(alone - pixels).max(axis=2) > 8).sum())
    print("without replication %d pixels differ by more than 8/255" % changed)
    check(changed > 500, "without replication the image changes (each rank would trace its own block)")

check.finish("mpi volume")
