#!/usr/bin/env python3
"""Times N 3D glyphs (vtkGlyph3DMapper: cones oriented by a vector, scaled and coloured by a scalar, over a
floor, one positional light) drawn by VTK's OpenGL glyph mapper and traced by vtkWhittedPass (1 spp, shadows,
depth 5), and the memory each needs. One process per (mode, N), so the memory figure is that process's alone.

    xvfb-run -a -s "-screen 0 1280x1024x24 -noreset" /usr/bin/python3 vtk_glyph_bench.py \
        --glyphs 100000 --mode whitted --size 1024x768 --reps 3 --csv glyphs.csv

The window first renders the floor alone (context, shaders, the pass's set-up), then the glyphs are shown.
Timing: first frame with the glyphs (OpenGL: glyph shader compile and instance upload; Whitted: conversion of
the source, one instance per glyph, top-level BVH build, trace) then --reps frames each after a 0.5 degree
azimuth, median, wall and CPU time of this process. Memory: resident set growth of this process from before
the glyphs were shown to after the last frame (VmRSS: Mesa's buffers for OpenGL; the scene's instance records,
top-level BVH and the converter's state for Whitted), plus, for Whitted, the pass's BVH bytes.
"""
import argparse
import csv
import os
import resource
import statistics
import time

FIELDS = ["mode", "glyphs", "width", "height", "status", "first_frame_seconds", "seconds_median", "cpu_seconds_median",
          "rss_growth_mb", "bvh_mb", "instances", "triangles", "runs", "first_breakdown", "breakdown",
          "first_frame_cpu_seconds"]


def breakdown(p):
    """The pass's own phase times of its last frame."""
    stats = p.GetLastFrameStatistics()
    return " ".join("%s %.0f ms" % (k.lower(), 1e3 * getattr(stats, "Get%sTime" % k)())
                    for k in ("Conversion", "Build", "Trace", "Composite"))


def rss_mb():
    with open("/proc/self/status") as f:
        for line in f:
            if line.startswith("VmRSS:"):
                return int(line.split()[1]) / 1024.0
    return float("nan")


def cpu():
    r = resource.getrusage(resource.RUSAGE_SELF)
    return r.ru_utime + r.ru_stime


def build(n, size):
    import numpy as np
    from vtkmodules.util.numpy_support import numpy_to_vtk
    from vtkmodules.vtkCommonCore import vtkLookupTable, vtkPoints
    from vtkmodules.vtkCommonDataModel import vtkPolyData
    from vtkmodules.vtkFiltersSources import vtkConeSource, vtkPlaneSource
    from vtkmodules.vtkRenderingCore import (vtkActor, vtkGlyph3DMapper, vtkLight, vtkPolyDataMapper,
                                             vtkRenderer, vtkRenderWindow)
    import vtkmodules.vtkRenderingOpenGL2  # noqa: F401

    rng = np.random.default_rng(1)
    side = max(1.0, n ** (1.0 / 3.0))
    xyz = rng.random((n, 3)) * [10.0, 4.0, 10.0] - [5.0, -0.3, 5.0]
    points = vtkPoints()
    points.SetData(numpy_to_vtk(xyz, deep=True))
    poly = vtkPolyData()
    poly.SetPoints(points)
    speed = numpy_to_vtk(0.5 + rng.random(n), deep=True)
    speed.SetName("speed")
    velocity = numpy_to_vtk(rng.standard_normal((n, 3)), deep=True)
    velocity.SetName("velocity")
    poly.GetPointData().AddArray(speed)
    poly.GetPointData().AddArray(velocity)
    poly.GetPointData().SetActiveScalars("speed")
    cone = vtkConeSource()
    cone.SetResolution(8)
    mapper = vtkGlyph3DMapper()
    mapper.SetInputData(poly)
    mapper.SetSourceConnection(cone.GetOutputPort())
    mapper.SetScaleArray("speed")
    mapper.SetScaleFactor(2.4 / side)
    mapper.SetOrientationArray("velocity")
    lut = vtkLookupTable()
    lut.SetHueRange(0.65, 0.0)
    lut.Build()
    mapper.SetLookupTable(lut)
    mapper.SetScalarRange(0.5, 1.5)
    glyphs = vtkActor()
    glyphs.SetMapper(mapper)
    plane = vtkPlaneSource()
    plane.SetOrigin(-6, 0, 6)
    plane.SetPoint1(6, 0, 6)
    plane.SetPoint2(-6, 0, -6)
    fm = vtkPolyDataMapper()
    fm.SetInputConnection(plane.GetOutputPort())
    floor = vtkActor()
    floor.SetMapper(fm)
    ren = vtkRenderer()
    ren.AddActor(glyphs)
    ren.AddActor(floor)
    light = vtkLight()
    light.SetPositional(True)
    light.SetConeAngle(180)
    light.SetPosition(3, 12, 6)
    ren.AddLight(light)
    cam = ren.GetActiveCamera()
    cam.SetPosition(0, 9, 14)
    cam.SetFocalPoint(0, 1.5, 0)
    ren.ResetCameraClippingRange()
    win = vtkRenderWindow()
    win.SetOffScreenRendering(True)
    win.SetMultiSamples(0)
    win.SetSize(*size)
    win.AddRenderer(ren)
    cone.Update()
    return win, ren, glyphs, cone.GetOutput().GetNumberOfPolys()


def measure(mode, n, size, reps):
    """One row: the glyph scene rendered by mode ('opengl' or 'whitted')."""
    row = dict(mode=mode, glyphs=n, width=size[0], height=size[1], status="ok")
    win, ren, glyphs, source_polys = build(n, size)
    p = None
    if mode == "whitted":
        try:
            from whitted import vtkWhittedPass
        except ImportError as e:
            row["status"] = "unavailable: %s" % e
            return row
        p = vtkWhittedPass()
        ren.SetPass(p)
    glyphs.VisibilityOff()
    win.Render()
    win.WaitForCompletion()
    glyphs.VisibilityOn()
    before = rss_mb()
    t, c = time.perf_counter(), cpu()
    win.Render()
    win.WaitForCompletion()
    row["first_frame_seconds"] = time.perf_counter() - t
    row["first_frame_cpu_seconds"] = cpu() - c
    if p is not None:
        row["first_breakdown"] = breakdown(p)
    walls, cpus = [], []
    for _ in range(reps):
        ren.GetActiveCamera().Azimuth(0.5)
        t, c = time.perf_counter(), cpu()
        win.Render()
        win.WaitForCompletion()
        walls.append(time.perf_counter() - t)
        cpus.append(cpu() - c)
    row["seconds_median"] = statistics.median(walls)
    row["cpu_seconds_median"] = statistics.median(cpus)
    row["runs"] = reps
    row["rss_growth_mb"] = rss_mb() - before
    if p is not None:
        stats = p.GetLastFrameStatistics()
        row["bvh_mb"] = stats.GetBVHBytes() / 2.0 ** 20
        row["instances"] = stats.GetNumberOfInstances()
        row["triangles"] = stats.GetNumberOfTriangles()
        row["breakdown"] = breakdown(p)
        if stats.GetNumberOfOpenGLProps() != 0:
            row["status"] = "glyphs were drawn by OpenGL, not traced"
    else:
        row["triangles"] = source_polys
    win.Finalize()
    return row


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--glyphs", type=int, required=True)
    ap.add_argument("--mode", required=True,
                    help="opengl, whitted, or both comma-separated (one process: the quick run; the memory figure "
                         "of the second then includes what the first left)")
    ap.add_argument("--size", default="1024x768")
    ap.add_argument("--reps", type=int, default=3)
    ap.add_argument("--csv", required=True)
    a = ap.parse_args()
    size = [int(v) for v in a.size.split("x")]
    for mode in a.mode.split(","):
        row = measure(mode, a.glyphs, size, a.reps)
        new = not os.path.exists(a.csv) or os.path.getsize(a.csv) == 0
        with open(a.csv, "a", newline="") as f:
            w = csv.DictWriter(f, fieldnames=FIELDS)
            if new:
                w.writeheader()
            w.writerow({k: row.get(k, "") for k in FIELDS})
        print(row)


if __name__ == "__main__":
    main()
