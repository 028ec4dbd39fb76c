#!/usr/bin/env python3
"""The volume anchor of issue 29: a 256^3 wavelet (vtkRTAnalyticSource, whole extent -128..127) volume-rendered at
1024x768, 1 spp, by VTK's vtkGPUVolumeRayCastMapper (llvmpipe here), by vtkFixedPointVolumeRayCastMapper, and by
vtkWhittedPass tracing the same vtkVolume (GPU mapper input) with its effects off, then with shadows (a floor under
the volume, shadowed by it) and with a mirror floor, so each effect's cost is listed; and the three with Shade on
(gpu-shade, fixedpoint-shade, whitted-shade: VTK's gradient shading, its defaults, under the same light).

Run under Xvfb, with the VTK module on PYTHONPATH for the Whitted modes:

    PYTHONPATH=build/vtk/lib/python3/dist-packages xvfb-run -a -s "-screen 0 1280x1024x24 -noreset" \\
        /usr/bin/python3 testing/benchmark/vtk_volume_bench.py --csv volume.csv

Same volume, transfer function (cool-warm colour over the field's range; opacity 0 below 130, up to 0.2 at 280 per
unit distance 1: the rim of the cube is transparent), sample distance 1 (the voxel spacing; the GPU mapper's
automatic adjustment off), camera and light in every mode. Modes gpu and fixedpoint draw the volume alone (no
floor); whitted draws it alone with shadows, reflections and refractions off (like for like), whitted-shadow adds
the floor and shadows, whitted-mirror a mirror floor (reflections) and shadows. Timing: the first frame reported
apart (upload, conversion); then --warmup untimed and --reps timed frames, each after a 0.5 degree azimuth,
each ending with glFinish; median wall and CPU seconds of this process (llvmpipe and the tracer both use its
threads). Memory: the process's peak resident size after the frames, and its growth over the first frame.
"""
import argparse
import os
import resource
import statistics
import sys
import time

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import vtk_gl_bench  # noqa: E402  (its CSV writer)

FIELDS = ["mode", "width", "height", "dims", "status", "first_frame_seconds", "seconds_median", "seconds_min",
          "seconds_max", "cpu_seconds_median", "runs", "peak_rss_mb", "first_frame_rss_growth_mb", "gl_renderer"]


def rss_mb():
    return resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024.0


def write_row(path, row):
    vtk_gl_bench.write_row(path, row, FIELDS)
    print(", ".join("%s=%s" % (k, row.get(k, "")) for k in FIELDS if row.get(k, "") != ""), flush=True)


def build(mode, size, half):
    shade = mode.endswith("-shade")
    mode = mode[:-len("-shade")] if shade else mode
    import vtk  # noqa: F401  (object factories: OpenGL render window, volume mappers)
    from vtkmodules.vtkImagingCore import vtkRTAnalyticSource
    from vtkmodules.vtkRenderingCore import (vtkActor, vtkColorTransferFunction, vtkLight, vtkPolyDataMapper,
                                             vtkRenderer, vtkRenderWindow, vtkVolume, vtkVolumeProperty)
    from vtkmodules.vtkCommonDataModel import vtkPiecewiseFunction
    from vtkmodules.vtkFiltersSources import vtkPlaneSource
    from vtkmodules.vtkRenderingVolume import vtkFixedPointVolumeRayCastMapper, vtkGPUVolumeRayCastMapper

    src = vtkRTAnalyticSource()
    src.SetWholeExtent(-half, half - 1, -half, half - 1, -half, half - 1)
    src.Update()
    image = src.GetOutput()
    lo, hi = image.GetScalarRange()
    if mode == "fixedpoint":
        mapper = vtkFixedPointVolumeRayCastMapper()
        mapper.SetSampleDistance(1.0)
        mapper.SetAutoAdjustSampleDistances(0)
    else:
        mapper = vtkGPUVolumeRayCastMapper()
        mapper.SetAutoAdjustSampleDistances(0)
        mapper.SetSampleDistance(1.0)
    mapper.SetInputData(image)
    color = vtkColorTransferFunction()
    color.AddRGBPoint(lo, 0.23, 0.30, 0.75)
    color.AddRGBPoint(0.5 * (lo + hi), 0.87, 0.87, 0.87)
    color.AddRGBPoint(hi, 0.71, 0.02, 0.15)
    opacity = vtkPiecewiseFunction()
    opacity.AddPoint(lo, 0.0)
    opacity.AddPoint(130.0, 0.0)
    opacity.AddPoint(hi, 0.2)
    prop = vtkVolumeProperty()
    prop.SetColor(color)
    prop.SetScalarOpacity(opacity)
    prop.SetScalarOpacityUnitDistance(1.0)
    prop.SetInterpolationTypeToLinear()
    prop.SetShade(1 if shade else 0)
    volume = vtkVolume()
    volume.SetMapper(mapper)
    volume.SetProperty(prop)

    ren = vtkRenderer()
    ren.SetBackground(0.32, 0.34, 0.43)
    ren.AddVolume(volume)
    ren.AutomaticLightCreationOff()
    light = vtkLight()
    light.SetLightTypeToSceneLight()
    light.SetPosition(-0.6 * half, 3.0 * half, 1.5 * half)
    light.SetFocalPoint(0.0, 0.0, 0.0)
    ren.AddLight(light)
    if mode in ("whitted-shadow", "whitted-mirror"):
        plane = vtkPlaneSource()
        s = 3.0 * half
        plane.SetOrigin(-s, -1.2 * half, s)
        plane.SetPoint1(s, -1.2 * half, s)
        plane.SetPoint2(-s, -1.2 * half, -s)
        pm = vtkPolyDataMapper()
        pm.SetInputConnection(plane.GetOutputPort())
        floor = vtkActor()
        floor.SetMapper(pm)
        floor.GetProperty().SetColor(0.8, 0.8, 0.75)
        ren.AddActor(floor)
    if mode.startswith("whitted"):
        from whitted import vtkWhittedPass, vtkWhittedMaterialKeys

        p = vtkWhittedPass()
        p.SetSamplesPerPixel(1)
        p.SetShadows(mode != "whitted")
        p.SetReflections(mode == "whitted-mirror")
        p.SetRefractions(False)
        ren.SetPass(p)
        if mode == "whitted-mirror":
            info = floor.GetProperty().GetInformation()
            info.Set(vtkWhittedMaterialKeys.REFLECTANCE(), [0.6], 1)
    win = vtkRenderWindow()
    win.SetSize(*size)
    win.SetMultiSamples(0)
    win.AddRenderer(ren)
    cam = ren.GetActiveCamera()
    cam.SetFocalPoint(0.0, 0.0, 0.0)
    cam.SetPosition(2.4 * half, 1.8 * half, 4.8 * half)
    cam.SetViewUp(0.0, 1.0, 0.0)
    ren.ResetCameraClippingRange()
    return win, ren, cam


def run(mode, args, size, half):
    row = {"mode": mode, "width": size[0], "height": size[1], "dims": "%d^3" % (2 * half)}
    try:
        win, ren, cam = build(mode, size, half)
    except ImportError as e:
        row["status"] = "unavailable: %s" % e
        write_row(args.csv, row)
        return
    before = rss_mb()
    t = time.perf_counter()
    win.Render()
    win.WaitForCompletion()
    row["first_frame_seconds"] = "%.4f" % (time.perf_counter() - t)
    row["first_frame_rss_growth_mb"] = "%.1f" % (rss_mb() - before)
    row["gl_renderer"] = (win.ReportCapabilities().split("OpenGL renderer string:")[-1].split("\n")[0].strip()
                          if hasattr(win, "ReportCapabilities") else "")
    for _ in range(args.warmup):
        cam.Azimuth(0.5)
        win.Render()
        win.WaitForCompletion()
    wall, cpu = [], []
    for _ in range(args.reps):
        cam.Azimuth(0.5)
        t, c = time.perf_counter(), time.process_time()
        win.Render()
        win.WaitForCompletion()
        wall.append(time.perf_counter() - t)
        cpu.append(time.process_time() - c)
    row.update(status="ok", seconds_median="%.4f" % statistics.median(wall), seconds_min="%.4f" % min(wall),
               seconds_max="%.4f" % max(wall), cpu_seconds_median="%.4f" % statistics.median(cpu), runs=len(wall),
               peak_rss_mb="%.1f" % rss_mb())
    if args.png:
        from vtkmodules.vtkIOImage import vtkPNGWriter
        from vtkmodules.vtkRenderingCore import vtkWindowToImageFilter

        w2i = vtkWindowToImageFilter()
        w2i.SetInput(win)
        w2i.ReadFrontBufferOff()
        w = vtkPNGWriter()
        w.SetInputConnection(w2i.GetOutputPort())
        w.SetFileName("%s_%s.png" % (args.png, mode))
        w.Write()
    write_row(args.csv, row)


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--csv", required=True)
    ap.add_argument("--size", default="1024x768")
    ap.add_argument("--dims", type=int, default=256, help="points per axis (even)")
    ap.add_argument("--modes", default="gpu,fixedpoint,whitted,whitted-shadow,whitted-mirror,gpu-shade,"
                    "fixedpoint-shade,whitted-shade")
    ap.add_argument("--reps", type=int, default=5)
    ap.add_argument("--warmup", type=int, default=1)
    ap.add_argument("--png", default="", help="prefix: write each mode's last frame")
    ap.add_argument("--one", default="", help=argparse.SUPPRESS)  # internal: run this mode in this process
    args = ap.parse_args()
    size = [int(x) for x in args.size.split("x")]
    half = args.dims // 2
    if args.one:
        run(args.one, args, size, half)
        return 0
    # Each mode in a process of its own: memory and caches start equal
    import subprocess

    for mode in args.modes.split(","):
        subprocess.call([sys.executable, os.path.abspath(__file__), "--one", mode] +
                        [a for a in sys.argv[1:] if not a.startswith("--one")])
    return 0


if __name__ == "__main__":
    sys.exit(main())
