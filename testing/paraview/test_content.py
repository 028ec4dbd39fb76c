"""ParaView content in the Whitted view: Surface With Edges, backface representation, PBR interpolation and
interactive selection, each against the Render View (ParaView's OpenGL view) of the same pipeline.

    pvbatch test_content.py --plugin P --tmp DIR

- Surface With Edges (EdgeColor, LineWidth 1 and 3): nearly every edge pixel of either view lies within a pixel of
  an edge pixel of the other (no speckles, no triangulation diagonals of the quads, no missing edges); edge pixel
  counts within 25%.
- Backface Representation "Surface" with its own colour on an open cylinder: ParaView draws it as a second actor
  culling front faces over the same data; the Whitted view traces the pair as one surface with a back material:
  the inside shows the back colour, the images agree (at most 1% of pixels more than 24/255 apart); so do
  "Cull Backface" and "Cull Frontface".
- PBR interpolation (Metallic 1, Roughness 0) of a quad facing an unlit wall: the quad mirrors the wall, tinted by
  its base colour (the documented mapping: reflectance = base colour).
- Selection: SelectSurfaceCells / SelectSurfacePoints / SelectCellsThrough / SelectPointsThrough on a sphere in
  the Whitted view give the same ids as in the Render View, and the selection colour (magenta) covers at least
  80% as many pixels as there.
"""
import argparse
import os
import sys

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import whitted_pvtest as wt  # noqa: E402

# The image helpers of the VTK tests (pure numpy: edge masks and their agreement)
sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "vtk", "Python"))
from whitted_imagetest import edge_mask, near  # noqa: E402

ap = argparse.ArgumentParser()
ap.add_argument("--plugin", required=True)
ap.add_argument("--tmp", required=True)
args = ap.parse_args()

import paraview.simple  # noqa: E402
from paraview.simple import (ClearSelection, CreateView, Cylinder, Delete, ExtractSelection, Hide, Plane,  # noqa
                             Render, SelectCellsThrough, SelectPointsThrough, SelectSurfaceCells,
                             SelectSurfacePoints, Show, Sphere)

os.makedirs(args.tmp, exist_ok=True)
wt.load_plugin(args.plugin)
paraview.simple._DisableFirstRenderCameraReset()
failures = []
SIZE = [240, 240]


def check(ok, msg):
    print(("ok    " if ok else "FAIL  ") + msg)
    if not ok:
        failures.append(msg)


def views():
    out = {}
    for kind in ("RenderView", "WhittedRayTraceView"):
        v = CreateView(kind)
        v.ViewSize = SIZE
        v.OrientationAxesVisibility = 0
        v.UseColorPaletteForBackground = 0
        v.Background = [0.32, 0.34, 0.43]
        if kind != "RenderView":
            v.Shadows = 0
        out[kind] = v
    return out


def look(view, position, focal=(0, 0, 0), up=(0, 1, 0)):
    view.CameraPosition = list(position)
    view.CameraFocalPoint = list(focal)
    view.CameraViewUp = list(up)
    view.CameraViewAngle = 30.0


def shot(view, name):
    return wt.screenshot(view, os.path.join(args.tmp, "content_%s.png" % name), SIZE).astype(float)


# Surface With Edges -------------------------------------------------------------------------------------------
V = views()
sphere = Sphere(Center=[-0.6, 0, 0], Radius=0.5, ThetaResolution=16, PhiResolution=10)
plane = Plane(Origin=[0.2, -0.5, 0], Point1=[1.2, -0.5, 0.3], Point2=[0.2, 0.5, 0], XResolution=4, YResolution=4)
for width in (1, 3):
    masks = {}
    for kind, v in V.items():
        for src in (sphere, plane):
            d = Show(src, v)
            d.Representation = "Surface With Edges"
            d.DiffuseColor = [0.2, 0.3, 1.0]
            d.AmbientColor = [0.2, 0.3, 1.0]
            d.EdgeColor = [1.0, 0.0, 0.0]
            d.LineWidth = width
        look(v, (0.1, 0.4, 4), (0.1, 0, 0))
        img = shot(v, "edges%d_%s" % (width, kind))
        masks[kind] = edge_mask(img)
    g, r = masks["RenderView"], masks["WhittedRayTraceView"]
    recall, precision = near(g, r), near(r, g)
    print("edges width %d: Render View %d edge pixels, Whitted %d, near: %.3f / %.3f"
          % (width, g.sum(), r.sum(), recall, precision))
    check(g.sum() > 150, "edges %d: the Render View shows edges" % width)
    check(recall > 0.9 and precision > 0.97, "edges %d: edge pixels agree with the Render View" % width)
    check(abs(r.sum() / max(1, g.sum()) - 1) < 0.25, "edges %d: edge width as in the Render View" % width)
for v in V.values():
    Hide(sphere, v)
    Hide(plane, v)

# Backface representation --------------------------------------------------------------------------------------
tube = Cylinder(Resolution=48, Height=1.5, Radius=0.6, Capping=0)
for backface in ("Surface", "Cull Backface", "Cull Frontface"):
    images = {}
    for kind, v in V.items():
        d = Show(tube, v)
        d.Representation = "Surface"
        d.DiffuseColor = [1.0, 0.4, 0.2]
        d.AmbientColor = [1.0, 0.4, 0.2]
        d.BackfaceRepresentation = backface
        d.BackfaceDiffuseColor = [0.1, 0.9, 0.2]
        d.BackfaceAmbientColor = [0.1, 0.9, 0.2]
        look(v, (0.3, 3.2, 2.2))
        images[kind] = shot(v, "backface_%s_%s" % (backface.replace(" ", "_"), kind))
        Hide(tube, v)
    diff = np.abs(images["RenderView"] - images["WhittedRayTraceView"]).max(axis=2)
    rt = images["WhittedRayTraceView"]
    green = ((rt[:, :, 1] > 1.5 * rt[:, :, 0]) & (rt[:, :, 1] > 60)).sum()
    print("backface %s: %d green pixels, %.3f%% more than 24/255 from the Render View"
          % (backface, green, 100 * (diff > 24).mean()))
    if backface == "Surface":
        check(green > 1500, "backface: the inside shows the back colour")
    check((diff > 24).mean() < 0.01, "backface %s: agrees with the Render View" % backface)

# PBR ------------------------------------------------------------------------------------------------------------
v = V["WhittedRayTraceView"]
quad = Plane(Origin=[-0.5, -0.5, 0.5], Point1=[0.5, -0.5, -0.5], Point2=[-0.5, 0.5, 0.5])
wall = Plane(Origin=[3, -20, -20], Point1=[3, 20, -20], Point2=[3, -20, 20])
dw = Show(wall, v)
dw.AmbientColor = [0.2, 0.6, 0.9]
dw.DiffuseColor = [0.2, 0.6, 0.9]
dw.Ambient = 1.0
dw.Diffuse = 0.0
dq = Show(quad, v)
dq.DiffuseColor = [1.0, 0.71, 0.29]
dq.AmbientColor = [1.0, 0.71, 0.29]
dq.Interpolation = "PBR"
dq.Metallic = 1.0
dq.Roughness = 0.0
look(v, (0, 0, 5))
img = shot(v, "pbr")
centre = img[SIZE[1] // 2 - 5:SIZE[1] // 2 + 5, SIZE[0] // 2 - 5:SIZE[0] // 2 + 5].reshape(-1, 3).mean(axis=0)
expected = np.array([0.2 * 1.0, 0.6 * 0.71, 0.9 * 0.29]) * 255
print("PBR metallic mirror: centre", centre, "expected", expected)
check(np.abs(centre - expected).max() < 4, "PBR: metallic smooth quad mirrors the wall tinted by its base colour")
Hide(quad, v)
Hide(wall, v)

# Selection ------------------------------------------------------------------------------------------------------
ball = Sphere(ThetaResolution=32, PhiResolution=16)
results = {}
for kind, v in V.items():
    d = Show(ball, v)
    d.Representation = "Whitted Surface" if kind != "RenderView" else "Surface"
    look(v, (0, 0, 4))
    Render(v)
    for name, select in (("surface cells", SelectSurfaceCells), ("surface points", SelectSurfacePoints),
                         ("frustum cells", SelectCellsThrough), ("frustum points", SelectPointsThrough)):
        ClearSelection(ball)
        select(Rectangle=[100, 100, 140, 140], View=v)
        extract = ExtractSelection(Input=ball)
        extract.UpdatePipeline()
        fetched = paraview.servermanager.Fetch(extract)
        ids = set()
        for arr in ("vtkOriginalCellIds", "vtkOriginalPointIds"):
            a = fetched.GetCellData().GetArray(arr) if "Cell" in arr else fetched.GetPointData().GetArray(arr)
            if a is not None:
                ids |= {(arr, int(a.GetTuple1(i))) for i in range(a.GetNumberOfTuples())}
        Delete(extract)
        img = shot(v, "selection_%s_%s" % (name.replace(" ", "_"), kind))
        magenta = ((img[:, :, 0] > 200) & (img[:, :, 2] > 200) & (img[:, :, 1] < 90)).sum()
        results[(kind, name)] = (ids, magenta)
    ClearSelection(ball)
    Hide(ball, v)
for name in ("surface cells", "surface points", "frustum cells", "frustum points"):
    gl_ids, gl_mag = results[("RenderView", name)]
    rt_ids, rt_mag = results[("WhittedRayTraceView", name)]
    print("selection %s: Render View %d ids, %d magenta pixels; Whitted %d ids, %d magenta pixels"
          % (name, len(gl_ids), gl_mag, len(rt_ids), rt_mag))
    check(len(gl_ids) > 0 and gl_ids == rt_ids, "selection %s: same ids as the Render View" % name)
    check(rt_mag >= 0.8 * gl_mag and gl_mag > 50, "selection %s: highlight visible in the traced image" % name)

if failures:
    wt.fail("%d check(s) failed: %s" % (len(failures), "; ".join(failures)))
print("test_content: all checks passed")
