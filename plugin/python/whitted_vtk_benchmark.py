#!/usr/bin/python3
"""Frame times of vtkWhittedPass against VTK's own OpenGL rendering of the same view.

    xvfb-run -a -s "-screen 0 1280x1024x24 -noreset" \\
        env PYTHONPATH=<build>/lib/python3/dist-packages /usr/bin/python3 whitted_vtk_benchmark.py

Scenes: the classic Whitted scene at 800x600 (the demo's default), and VTK's wavelet (vtkRTAnalyticSource,
extent [-122,122]^3) contoured at 157, about 1.0 M triangles, at 1024x1024 with a directional scene light
(shadow rays on). Each frame is a full window.Render() after a camera nudge (so nothing is cached but the
scene); the first frame (conversion + BVH build, or OpenGL buffer upload) is reported separately, then the
median of --frames frames. MultiSamples 0 for both.
"""
import argparse
import statistics
import sys
import time


def wavelet_scene(renderer, extent):
    from vtkmodules.vtkFiltersCore import vtkContourFilter
    from vtkmodules.vtkImagingCore import vtkRTAnalyticSource
    from vtkmodules.vtkRenderingCore import vtkActor, vtkLight, vtkPolyDataMapper

    source = vtkRTAnalyticSource()
    source.SetWholeExtent(-extent, extent, -extent, extent, -extent, extent)
    contour = vtkContourFilter()
    contour.SetInputConnection(source.GetOutputPort())
    contour.SetValue(0, 157.0)
    contour.ComputeNormalsOn()
    contour.ComputeScalarsOff()
    contour.Update()
    mapper = vtkPolyDataMapper()
    mapper.SetInputConnection(contour.GetOutputPort())
    actor = vtkActor()
    actor.SetMapper(mapper)
    actor.GetProperty().SetColor(0.85, 0.75, 0.6)
    actor.GetProperty().SetSpecular(0.3)
    actor.GetProperty().SetSpecularPower(20)
    renderer.AddActor(actor)
    light = vtkLight()
    light.SetLightTypeToSceneLight()
    light.SetPosition(-1.0, 1.5, 1.0)
    light.SetFocalPoint(0.0, 0.0, 0.0)
    renderer.AddLight(light)
    renderer.SetBackground(0.2, 0.25, 0.3)
    renderer.ResetCamera()
    renderer.GetActiveCamera().Azimuth(30)
    renderer.GetActiveCamera().Elevation(20)
    renderer.ResetCameraClippingRange()
    return contour.GetOutput().GetNumberOfCells()


def time_frames(window, renderer, frames, whitted_pass=None):
    camera = renderer.GetActiveCamera()
    t0 = time.perf_counter()
    window.Render()
    first = time.perf_counter() - t0
    if whitted_pass is not None:
        stats = whitted_pass.GetLastFrameStatistics()
        print("    first frame: conversion %.1f ms, BVH build %.1f ms, trace %.1f ms, composite %.1f ms"
              % (stats.GetConversionTime() * 1e3, stats.GetBuildTime() * 1e3,
                 stats.GetTraceTime() * 1e3, stats.GetCompositeTime() * 1e3))
    times = []
    for i in range(frames):
        camera.Azimuth(0.5 if i % 2 == 0 else -0.5)  # a camera change: nothing but the image is redone
        t0 = time.perf_counter()
        window.Render()
        times.append(time.perf_counter() - t0)
    return first, statistics.median(times)


def run(name, build, size, frames, use_pass, spp=1):
    from vtkmodules.vtkRenderingCore import vtkRenderer, vtkRenderWindow
    import vtkmodules.vtkRenderingOpenGL2  # noqa: F401
    from whitted import vtkWhittedPass

    renderer = vtkRenderer()
    window = vtkRenderWindow()
    window.SetOffScreenRendering(True)
    window.SetMultiSamples(0)
    window.SetSize(*size)
    window.AddRenderer(renderer)
    extra = build(renderer)
    whitted_pass = None
    if use_pass:
        whitted_pass = vtkWhittedPass()
        whitted_pass.SetSamplesPerPixel(spp)
        renderer.SetPass(whitted_pass)
    first, median = time_frames(window, renderer, frames, whitted_pass)
    label = "vtkWhittedPass" if use_pass else "VTK OpenGL"
    print("%-22s %-15s %dx%d  first frame %8.1f ms, median of %d frames %8.1f ms%s"
          % (name, label, size[0], size[1], first * 1e3, frames, median * 1e3,
             "" if extra is None else "  (%d triangles)" % extra))
    if whitted_pass is not None:
        print("    " + whitted_pass.GetLastFrameReport().replace("\n", "\n    ").rstrip())
    return median


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--frames", type=int, default=5)
    ap.add_argument("--extent", type=int, default=122, help="wavelet half extent (122: about 1.0 M triangles)")
    ap.add_argument("--skip-wavelet", action="store_true")
    args = ap.parse_args(argv)
    from whitted.scenes import classic_scene

    run("classic", lambda r: classic_scene(r) and None, (800, 600), args.frames, False)
    run("classic", lambda r: classic_scene(r) and None, (800, 600), args.frames, True)
    if not args.skip_wavelet:
        run("wavelet isosurface", lambda r: wavelet_scene(r, args.extent), (1024, 1024), args.frames, False)
        run("wavelet isosurface", lambda r: wavelet_scene(r, args.extent), (1024, 1024), args.frames, True)
    return 0


if __name__ == "__main__":
    sys.exit(main())
