"""Correct pixels at several samples per pixel in the Whitted Ray Trace view, on ParaView's default background.

    pvbatch test_supersampling.py --plugin P --tmp DIR

The shared scene (mirror sphere, glass sphere, translucent box, ground) on ParaView's default background
(0.32, 0.34, 0.43), with the gradient of the view-features scene as a second background, is rendered at
200x150 with 4 and 16 samples per pixel, adaptive sampling off and on, and compared with an independent
reference: the same view traced at 1 sample per pixel at 800x600 and box-filtered 4x4. Over edge pixels (a
reference 4x4 block spanning more than 24/255) the mean signed error must be within +-1/255 (no dark fringes);
over the other pixels the mean absolute error must be at most 1/255 (no grey glass, no dark mirrors).
"""
import argparse
import os
import sys

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import whitted_pvtest as wt  # noqa: E402

ap = argparse.ArgumentParser()
ap.add_argument("--plugin", required=True)
ap.add_argument("--tmp", required=True)
args = ap.parse_args()

from paraview.simple import Render, SaveScreenshot  # noqa: E402
from vtkmodules.util.numpy_support import vtk_to_numpy  # noqa: E402
from vtkmodules.vtkIOImage import vtkPNGReader  # noqa: E402

wt.load_plugin(args.plugin)
os.makedirs(args.tmp, exist_ok=True)
view = wt.make_view([200, 150])
wt.build_scene(view, opacity=0.5)
failures = []


def shot(size, spp, adaptive, name):
    view.ViewSize = list(size)
    view.SamplesPerPixel = spp
    view.AdaptiveSampling = 1 if adaptive else 0
    Render(view)
    path = os.path.join(args.tmp, name + ".png")
    SaveScreenshot(path, view, ImageResolution=list(size))
    r = vtkPNGReader()
    r.SetFileName(path)
    r.Update()
    img = r.GetOutput()
    w, h, _ = img.GetDimensions()
    return vtk_to_numpy(img.GetPointData().GetScalars()).reshape(h, w, -1)[:, :, :3].astype(float)


def check(ok, msg):
    print(("ok    " if ok else "FAIL  ") + msg)
    if not ok:
        failures.append(msg)


for background in ("default", "gradient"):
    if background == "gradient":
        view.BackgroundColorMode = "Gradient"
        view.Background2 = [0.05, 0.05, 0.2]
    big = shot([800, 600], 1, False, "ss_reference_" + background)
    blocks = big.reshape(150, 4, 200, 4, 3)
    reference = blocks.mean(axis=(1, 3))
    edge = (blocks.max(axis=(1, 3)) - blocks.min(axis=(1, 3))).max(axis=2) > 24
    for spp in (4, 16):
        for adaptive in (False, True):
            image = shot([200, 150], spp, adaptive, "ss_%s_%d_%d" % (background, spp, adaptive))
            diff = image - reference
            signed = diff[edge].mean()
            mae = np.abs(diff[~edge]).mean()
            label = "%s background, %d spp, adaptive %s" % (background, spp, "on" if adaptive else "off")
            check(abs(signed) <= 1.0, "%s: edge mean signed error %+.3f/255 over %d pixels" % (label, signed,
                                                                                             edge.sum()))
            check(mae <= 1.0, "%s: other pixels' mean absolute error %.3f/255" % (label, mae))

print("%d failed" % len(failures))
sys.stdout.flush()
os._exit(1 if failures else 0)
