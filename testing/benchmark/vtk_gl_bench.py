#!/usr/bin/env python3
"""Times VTK's own OpenGL rendering of a .whtmesh isosurface (the whole-frame anchor), and -- when the VTK module
is importable -- vtkWhittedPass on the same scene, so both can be joined in one table.

Run it under Xvfb (Debian's VTK has no EGL/OSMesa; without a display VTK aborts):

    xvfb-run -a -s "-screen 0 1280x1024x24 -noreset" /usr/bin/python3 vtk_gl_bench.py \
        --mesh wavelet_1m.whtmesh --info iso1m.json --size 1024x1024 --mode opengl --msaa 0 --csv vtk.csv

--info is the JSON written by `whitted_bench info --scene iso1m` (camera, lights, material, background), so VTK
renders exactly the scene whitted_bench traces. Lights: the scene's headlight (the fill light at the camera)
becomes a VTK headlight, the others scene lights; a light that casts no shadow in whitted_bench gets
ShadowAttenuation 0, so vtkWhittedPass (shadow rays toward lights with ShadowAttenuation > 0) and
vtkShadowMapPass (no shadow map for headlights, maps weighted by ShadowAttenuation) shadow exactly the lights
whitted_bench shadows. Modes:
  opengl     VTK's default pipeline (no shadows), --msaa 0 or 8 (VTK's default multisampling)
  shadowmap  VTK's vtkShadowMapPass (OpenGL shadow maps), closest OpenGL equivalent of a frame with shadows
  whitted    vtkWhittedPass (`from whitted import vtkWhittedPass`) with --spp samples per pixel, depth 5,
             threshold 1/255, shadows; writes a row with status 'unavailable: ...' and exits 0 while the module
             is not built or not on PYTHONPATH

Timing: the first frame (shader compilation, upload; for Whitted scene conversion and BVH build) is reported
separately; then --warmup untimed and --reps timed frames, each after a 0.5 degree camera azimuth (so nothing can
be served from a cache), each ending with WaitForCompletion (glFinish), median reported, as wall time and as
CPU time of this process (llvmpipe rasterises on threads of the calling process).
"""
import argparse
import csv
import json
import os
import statistics
import sys
import time

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from gen_wavelet import read_whtmesh  # noqa: E402

FIELDS = ["mode", "msaa", "spp", "width", "height", "triangles", "status", "first_frame_seconds", "seconds_median",
          "seconds_min", "seconds_max", "runs", "gl_renderer", "screenshot", "breakdown", "cpu_seconds_median",
          "first_frame_cpu_seconds"]
PHASES = ["Conversion", "Build", "Trace", "Composite"]  # vtkWhittedFrameStatistics::Get<Phase>Time()


def phases(p):
    """The pass's own per-phase times of the last frame (seconds)."""
    stats = p.GetLastFrameStatistics()
    return {k: getattr(stats, "Get%sTime" % k)() for k in PHASES}


def write_row(path, row, fields=FIELDS):
    new = not os.path.exists(path) or os.path.getsize(path) == 0
    with open(path, "a", newline="") as f:
        w = csv.DictWriter(f, fieldnames=fields)
        if new:
            w.writeheader()
        w.writerow({k: row.get(k, "") for k in fields})


def make_polydata(path):
    import numpy as np
    from vtkmodules.util.numpy_support import numpy_to_vtk, numpy_to_vtkIdTypeArray
    from vtkmodules.vtkCommonCore import vtkPoints
    from vtkmodules.vtkCommonDataModel import vtkCellArray, vtkPolyData

    pos, nrm, tris = read_whtmesh(path)
    pts = vtkPoints()
    pts.SetData(numpy_to_vtk(np.ascontiguousarray(pos), deep=True))
    n = len(tris)
    offsets = numpy_to_vtkIdTypeArray(np.arange(0, 3 * n + 1, 3, dtype=np.int64), deep=True)
    conn = numpy_to_vtkIdTypeArray(np.ascontiguousarray(tris.reshape(-1).astype(np.int64)), deep=True)
    cells = vtkCellArray()
    cells.SetData(offsets, conn)
    pd = vtkPolyData()
    pd.SetPoints(pts)
    pd.SetPolys(cells)
    if nrm is not None:
        a = numpy_to_vtk(np.ascontiguousarray(nrm), deep=True)
        a.SetName("Normals")
        pd.GetPointData().SetNormals(a)
    return pd, n


def gl_renderer_name(win):
    try:
        caps = win.ReportCapabilities() or ""
        for line in caps.splitlines():
            if line.startswith("OpenGL renderer string"):
                return line.split(":", 1)[-1].strip()
    except Exception:  # noqa: BLE001 - only informational
        pass
    return ""


def parse_args():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--mesh", required=True)
    ap.add_argument("--info", required=True, help="JSON from `whitted_bench info`")
    ap.add_argument("--size", default="1024x1024")
    ap.add_argument("--mode", choices=["opengl", "shadowmap", "whitted"], default="opengl")
    ap.add_argument("--msaa", type=int, default=0)
    ap.add_argument("--spp", type=int, default=1, help="samples per pixel of vtkWhittedPass (mode whitted)")
    ap.add_argument("--reps", type=int, default=10)
    ap.add_argument("--warmup", type=int, default=2)
    ap.add_argument("--csv", required=True)
    ap.add_argument("--png", default="", help="screenshot of the last frame")
    return ap.parse_args()


def make_whitted_pass(spp):
    """vtkWhittedPass with whitted_bench frame's settings, explicitly (like for like with the core's rows); raises
    when the module cannot be imported."""
    from whitted import vtkWhittedPass  # the VTK module's Python wrapping (plugin/)
    whitted_pass = vtkWhittedPass()
    whitted_pass.SetSamplesPerPixel(spp)
    whitted_pass.SetMaxDepth(5)
    whitted_pass.SetShadows(True)
    whitted_pass.SetContributionThreshold(1.0 / 255.0)
    return whitted_pass


def make_renderer(info, pd):
    """The scene whitted_bench traces (from its info JSON): the mesh's actor, lights, background, camera."""
    from vtkmodules.vtkRenderingCore import vtkActor, vtkLight, vtkPolyDataMapper, vtkRenderer
    mapper = vtkPolyDataMapper()
    mapper.SetInputData(pd)
    mapper.ScalarVisibilityOff()
    actor = vtkActor()
    actor.SetMapper(mapper)
    m = info["material"]
    p = actor.GetProperty()
    p.SetColor(*m["diffuseColor"])
    p.SetAmbient(m["ambient"])
    p.SetDiffuse(m["diffuse"])
    p.SetSpecular(m["specular"])
    p.SetSpecularPower(m["specularPower"])
    p.SetInterpolationToGouraud()

    ren = vtkRenderer()
    ren.AddActor(actor)
    ren.SetBackground(*info["background"])
    for L in info["lights"]:
        light = vtkLight()
        if L["headlight"]:
            light.SetLightTypeToHeadlight()  # follows the camera; VTK updates its position every frame
        else:
            light.SetLightTypeToSceneLight()
        light.SetShadowAttenuation(1.0 if L["castShadows"] else 0.0)
        light.SetPositional(bool(L["positional"]))
        light.SetPosition(*L["position"])
        light.SetFocalPoint(*L["focalPoint"])
        light.SetColor(*L["color"])
        light.SetIntensity(L["intensity"])
        light.SetConeAngle(L["coneAngle"])
        ren.AddLight(light)
    ren.GetActiveCamera().SetViewAngle(info["camera"]["viewAngle"])
    look_at(ren, info["camera"])
    return ren


def look_at(ren, c):
    """The camera of whitted_bench's info (eye, focal point, view-up), clipping range reset."""
    cam = ren.GetActiveCamera()
    cam.SetPosition(*c["eye"])
    cam.SetFocalPoint(*c["focal"])
    cam.SetViewUp(*c["up"])
    ren.ResetCameraClippingRange()


def use_shadow_maps(ren):
    """VTK's vtkShadowMapPass: the closest OpenGL equivalent of a frame with shadows."""
    from vtkmodules.vtkRenderingOpenGL2 import (vtkCameraPass, vtkRenderPassCollection, vtkSequencePass,
                                                vtkShadowMapPass)
    shadows = vtkShadowMapPass()
    seq = vtkSequencePass()
    passes = vtkRenderPassCollection()
    passes.AddItem(shadows.GetShadowMapBakerPass())
    passes.AddItem(shadows)
    seq.SetPasses(passes)
    cpass = vtkCameraPass()
    cpass.SetDelegatePass(seq)
    ren.SetPass(cpass)


def time_frames(args, win, ren, whitted_pass, row):
    """The first frame, then --warmup untimed and --reps timed frames each after a 0.5 degree azimuth, into row."""
    t0, c0 = time.perf_counter(), time.process_time()
    win.Render()
    win.WaitForCompletion()
    row["first_frame_seconds"] = time.perf_counter() - t0
    row["first_frame_cpu_seconds"] = time.process_time() - c0
    row["gl_renderer"] = gl_renderer_name(win).replace(",", ";")
    first_phases = phases(whitted_pass) if whitted_pass is not None else {}

    times, cpu, steady_phases = [], [], []
    cam = ren.GetActiveCamera()
    for i in range(args.warmup + args.reps):
        cam.Azimuth(0.5)
        ren.ResetCameraClippingRange()
        t0, c0 = time.perf_counter(), time.process_time()  # process time includes llvmpipe's threads
        win.Render()
        win.WaitForCompletion()
        dt, dc = time.perf_counter() - t0, time.process_time() - c0
        if i >= args.warmup:
            times.append(dt)
            cpu.append(dc)
            if whitted_pass is not None:
                steady_phases.append(phases(whitted_pass))
    row.update(status="ok", seconds_median=statistics.median(times), seconds_min=min(times),
               seconds_max=max(times), runs=len(times), cpu_seconds_median=statistics.median(cpu))
    if first_phases:
        steady = {k: statistics.median(f[k] for f in steady_phases) for k in first_phases}
        row["breakdown"] = "first frame: %s; steady (median): %s" % tuple(
            " ".join("%s %.1f ms" % (k.lower(), v * 1e3) for k, v in d.items()) for d in (first_phases, steady))


def screenshot(win, path):
    """The window as a PNG, rendered again."""
    from vtkmodules.vtkIOImage import vtkPNGWriter
    from vtkmodules.vtkRenderingCore import vtkWindowToImageFilter
    win.Render()
    grab = vtkWindowToImageFilter()
    grab.SetInput(win)
    grab.ReadFrontBufferOff()
    grab.Update()
    wr = vtkPNGWriter()
    wr.SetFileName(path)
    wr.SetInputConnection(grab.GetOutputPort())
    wr.Write()


def main():
    args = parse_args()
    w, h = (int(v) for v in args.size.lower().split("x"))
    row = {"mode": args.mode, "msaa": args.msaa, "spp": args.spp if args.mode == "whitted" else 1, "width": w,
           "height": h}

    whitted_pass = None
    if args.mode == "whitted":
        try:
            whitted_pass = make_whitted_pass(args.spp)
        except Exception as e:  # noqa: BLE001 - any import failure means "not available yet"
            row["status"] = "unavailable: %s" % str(e).replace(",", ";")
            write_row(args.csv, row)
            print("vtkWhittedPass not importable (%s); row marked unavailable" % e)
            return 0

    from vtkmodules.vtkRenderingCore import vtkRenderWindow
    import vtkmodules.vtkRenderingOpenGL2  # noqa: F401 - registers the OpenGL factory overrides

    # Scene and window
    with open(args.info) as f:
        info = json.load(f)
    pd, ntri = make_polydata(args.mesh)
    row["triangles"] = ntri
    ren = make_renderer(info, pd)
    if args.mode == "shadowmap":
        use_shadow_maps(ren)
    elif whitted_pass is not None:
        ren.SetPass(whitted_pass)
    win = vtkRenderWindow()
    win.SetSize(w, h)
    win.SetMultiSamples(args.msaa)
    win.AddRenderer(ren)

    # Frames; the screenshot from the initial camera, the view whitted_bench renders
    time_frames(args, win, ren, whitted_pass, row)
    if args.png:
        look_at(ren, info["camera"])
        screenshot(win, args.png)
        row["screenshot"] = os.path.basename(args.png)
    write_row(args.csv, row)
    print("%s msaa %d spp %d %dx%d: first frame %.1f ms, median %.1f ms (min %.1f, %d runs) on %s %s" % (
        args.mode, args.msaa, row["spp"], w, h, row["first_frame_seconds"] * 1e3, row["seconds_median"] * 1e3,
        row["seconds_min"] * 1e3, row["runs"], row["gl_renderer"], row.get("breakdown", "")))
    return 0


if __name__ == "__main__":
    sys.exit(main())
