"""Shared helpers of the ParaView plugin tests: the test scene, image comparison, plugin loading.

Imported by the test scripts, which run under pvbatch, /usr/bin/python3 or mpirun pvbatch with
PYTHONPATH=<python3-paraview prefix>/usr/lib/python3/dist-packages (see README).
"""
import os
import sys

# Image size of every regression image: small, so the suite stays fast on 2 cores.
SIZE = [400, 300]


def load_plugin(plugin):
    """Loads the plugin on the client and, when connected to a server, on the server."""
    from paraview import servermanager as sm
    from paraview.simple import LoadPlugin

    LoadPlugin(plugin, remote=False, ns=globals())
    if sm.ActiveConnection.IsRemote():
        LoadPlugin(plugin, remote=True, ns=globals())


def make_view(size=SIZE, proxy="WhittedRayTraceView"):
    """A Whitted view (or another render view, e.g. proxy "RenderView", with the same look) with a fixed
    camera-independent look: no orientation axes, solid background, no light kit, one directional scene light
    (so shadows are crisp and the image does not depend on ParaView's light kit defaults)."""
    from paraview.simple import AddLight, CreateView

    view = CreateView(proxy)
    view.ViewSize = list(size)
    view.OrientationAxesVisibility = 0
    view.UseColorPaletteForBackground = 0
    view.BackgroundColorMode = "Single Color"
    view.Background = [0.32, 0.34, 0.43]
    view.UseLight = 0
    light = AddLight(view=view)
    light.Coords = "Scene"
    light.Type = "Directional"
    light.Position = [-2.0, 5.0, 3.0]
    light.FocalPoint = [0.0, 0.0, 0.0]
    light.Intensity = 1.0
    if proxy == "WhittedRayTraceView":
        view.MaxDepth = 5
    return view


def build_scene(view, opacity=1.0):
    """Ground plane, a mirror sphere, a glass sphere and a matte box: shadows, a reflection and a refraction.
    With opacity < 1 the matte box is translucent (ParaView then composites with ordered blending)."""
    from paraview.simple import Box, Plane, Show, Sphere

    ground = Plane(Origin=[-3.0, -1.0, 3.0], Point1=[3.0, -1.0, 3.0], Point2=[-3.0, -1.0, -3.0],
                   XResolution=24, YResolution=24)
    mirror = Sphere(Center=[-0.9, -0.1, 0.0], Radius=0.9, ThetaResolution=64, PhiResolution=32)
    glass = Sphere(Center=[0.9, -0.45, 1.0], Radius=0.55, ThetaResolution=64, PhiResolution=32)
    box = Box(Center=[1.2, -0.5, -1.0], XLength=1.0, YLength=1.0, ZLength=1.0)

    shown = {}
    for name, src, color in (("ground", ground, [0.85, 0.85, 0.8]), ("mirror", mirror, [0.9, 0.9, 0.95]),
                             ("glass", glass, [0.06, 0.08, 0.09]), ("box", box, [0.9, 0.35, 0.2])):
        d = Show(src, view)
        d.Representation = "Whitted Surface"
        d.DiffuseColor = color
        d.AmbientColor = color
        d.Specular = 0.3
        d.SpecularPower = 30.0
        shown[name] = d
    shown["mirror"].Reflectance = 0.7
    shown["glass"].Transmittance = 0.85
    shown["glass"].Reflectance = 0.1
    shown["glass"].Specular = 0.8
    shown["glass"].SpecularPower = 80.0
    shown["glass"].IndexOfRefraction = 1.5
    shown["box"].Opacity = opacity

    set_camera(view)
    return shown


def add_view_features(view, shown):
    """The standard render-view features on top of the scene: gradient background, light kit (with the scene
    light), orientation axes, a text annotation, scalar colouring with its colour legend, parallel
    projection."""
    from paraview.simple import ColorBy, GetColorTransferFunction, GetScalarBar, Show, Text

    view.BackgroundColorMode = "Gradient"
    view.Background2 = [0.05, 0.05, 0.2]
    view.UseLight = 1
    view.KeyLightIntensity = 0.35
    view.AdditionalLights[0].Intensity = 0.5
    view.OrientationAxesVisibility = 1
    text = Text(Text="Whitted Ray Trace")
    label = Show(text, view)
    label.WindowLocation = "Upper Center"
    label.FontSize = 14
    box = shown["box"]
    ColorBy(box, ("POINTS", "Normals", "X"))
    box.RescaleTransferFunctionToDataRange(True)
    lut = GetColorTransferFunction("Normals")
    lut.ApplyPreset("Cool to Warm", True)
    box.SetScalarBarVisibility(view, True)
    bar = GetScalarBar(lut, view)
    bar.ScalarBarLength = 0.3
    bar.TitleFontSize = 10
    bar.LabelFontSize = 9
    view.CameraParallelProjection = 1
    view.CameraParallelScale = 2.2


def set_camera(view, position=(0.8, 3.6, 8.2), focal_point=(0.1, -0.45, 0.1)):
    """The test camera, or a perspective camera at position looking at focal_point (view-up +y, 30 degrees), and
    no automatic camera reset on the first render."""
    import paraview.simple

    paraview.simple._DisableFirstRenderCameraReset()
    view.CameraPosition = list(position)
    view.CameraFocalPoint = list(focal_point)
    view.CameraViewUp = [0.0, 1.0, 0.0]
    view.CameraViewAngle = 30.0
    view.CameraParallelProjection = 0


def read_png(path):
    """A PNG file's RGB as an int32 numpy array (rows, columns, 3), bottom row first (as vtkPNGReader reads it)."""
    import numpy as np
    from vtkmodules.util.numpy_support import vtk_to_numpy
    from vtkmodules.vtkIOImage import vtkPNGReader

    r = vtkPNGReader()
    r.SetFileName(path)
    r.Update()
    img = r.GetOutput()
    dims = img.GetDimensions()
    arr = vtk_to_numpy(img.GetPointData().GetScalars()).reshape(dims[1], dims[0], -1)
    return arr[:, :, :3].astype(np.int32)


def screenshot(view, path, size):
    """Renders view, saves it to path at size (width, height) and returns its RGB as read_png does."""
    from paraview.simple import Render, SaveScreenshot

    Render(view)
    SaveScreenshot(path, view, ImageResolution=list(size))
    return read_png(path)


# Image tolerances, each set from a measurement (testing/paraview/measure_compositing.py; numbers in
# testing/paraview/README.md) with a stated margin. Each is a pair: a pixel "differs" when a channel is off by more
# than `tolerance` (0-255), and the check fails when more than `max_bad_fraction` of the pixels differ.
#
# COMPOSITING: an MPI (2 ranks, IceT) or client/server image against the single-process image of the same scene by
# the same build. Measured (measure_compositing.py, opaque test scene, 3 runs each of builtin pvbatch and mpirun -np
# 2 pvbatch): max difference 0, 0 pixels differ -- IceT's depth compositing and image delivery copy 8-bit pixels.
# Tolerance: 2 (one 8-bit step either way, for a machine whose GL rounds differently), and no more than 1 pixel in
# 10000 beyond it. Not yet measured: the translucent (ordered blending) and view-features scenes.
# CHANGE_GUARD: an image against its committed baseline (a change guard, not an oracle: the baseline was produced
# by this code). Measured: 0 pixels differ from scene, scene_translucent, glyphs baselines on this machine. 12 and
# 0.1%: fails on a change of 29/255 over 1% of the pixels (29 > 12, 1% > 0.1%) and on 13/255 over 0.1%.
COMPOSITING = dict(tolerance=2, max_bad_fraction=0.0001)
CHANGE_GUARD = dict(tolerance=12, max_bad_fraction=0.001)


def compare_image(image, baseline, tmpdir, max_bad_fraction=0.002, tolerance=24, mask=None):
    """Compares two PNG files pixel by pixel: fails when more than max_bad_fraction of the pixels differ by
    more than tolerance (0-255, any channel). With mask (bool array, rows bottom first), only those pixels
    count. Returns (ok, fraction of differing pixels). A missing baseline fails and leaves the image in place.
    On failure a difference image is written to tmpdir."""
    import numpy as np
    from vtkmodules.vtkIOImage import vtkPNGWriter

    if not os.path.exists(baseline):
        print("ERROR: baseline %s missing; the test image is %s" % (baseline, image))
        return False, 1.0

    a, b = read_png(image), read_png(baseline)
    if a.shape != b.shape:
        print("image %s is %s, baseline %s is %s" % (image, a.shape, baseline, b.shape))
        return False, 1.0
    delta = np.abs(a - b).max(axis=2)
    if mask is not None:
        delta = np.where(mask, delta, 0)
    counted = int(mask.sum()) if mask is not None else delta.size
    bad = float((delta > tolerance).sum()) / max(counted, 1)
    ok = bad <= max_bad_fraction
    print("image %s vs %s: %.4f%% of %d pixels differ by more than %d (limit %.3f%%), max difference %d, "
          "%d pixels differ at all -> %s" % (image, baseline, 100 * bad, counted, tolerance, 100 * max_bad_fraction,
                                             delta.max(), int((delta > 0).sum()), "ok" if ok else "FAILED"))
    if not ok:
        from vtkmodules.vtkCommonDataModel import vtkImageData
        from vtkmodules.util.numpy_support import numpy_to_vtk

        os.makedirs(tmpdir, exist_ok=True)
        diff = vtkImageData()
        diff.SetDimensions(a.shape[1], a.shape[0], 1)
        scaled = np.clip(delta * 4, 0, 255).astype(np.uint8).reshape(-1)
        diff.GetPointData().SetScalars(numpy_to_vtk(scaled))
        w = vtkPNGWriter()
        w.SetInputData(diff)
        w.SetFileName(os.path.join(tmpdir, os.path.basename(image).replace(".png", ".diff.png")))
        w.Write()
    return ok, bad


# Time series made of ParaView filters (no files): a programmable filter that reports time steps 0, 1, ...,
# steps - 1 and, at time t, either displaces the points of its polygonal input along z by
# amplitude * sin(0.15 x + 0.9 t) (same connectivity every step: "deform"), or contours its image input at
# value + 8 t (new connectivity every step: "contour"). pvbatch runs a programmable filter's script in the main
# script's namespace (after `from numpy import *`, which shadows abs, all, any, max, min, sum there): the scripts
# keep their names inside one function, and the scripts using them keep theirs inside main().
_TIME_STEPS_SCRIPT = """
def _whitted_time_steps(algorithm, steps):
    ex = algorithm.GetExecutive()
    out = ex.GetOutputInformation(0)
    out.Remove(ex.TIME_STEPS())
    out.Remove(ex.TIME_RANGE())
    for k in range(steps):
        out.Append(ex.TIME_STEPS(), float(k))
    out.Append(ex.TIME_RANGE(), 0.0)
    out.Append(ex.TIME_RANGE(), float(steps - 1))
_whitted_time_steps(self, %d)
"""
_REQUESTED_TIME = """
    ex = algorithm.GetExecutive()
    out = ex.GetOutputInformation(0)
    t = out.Get(ex.UPDATE_TIME_STEP()) if out.Has(ex.UPDATE_TIME_STEP()) else 0.0
"""
_DEFORM_SCRIPT = """
def _whitted_deform(algorithm, amplitude):
    import numpy
    from vtkmodules.util.numpy_support import numpy_to_vtk, vtk_to_numpy
    from vtkmodules.vtkCommonCore import vtkPoints""" + _REQUESTED_TIME + """\
    poly = algorithm.GetPolyDataOutput()
    poly.ShallowCopy(algorithm.GetPolyDataInput())
    xyz = vtk_to_numpy(poly.GetPoints().GetData()).astype(numpy.float32)
    xyz[:, 2] += amplitude * numpy.sin(0.15 * xyz[:, 0] + 0.9 * t)
    points = vtkPoints()
    points.SetData(numpy_to_vtk(xyz, deep=1))
    poly.SetPoints(points)
_whitted_deform(self, %r)
"""
_CONTOUR_SCRIPT = """
def _whitted_contour(algorithm, value):
    from vtkmodules.vtkFiltersCore import vtkContourFilter""" + _REQUESTED_TIME + """\
    c = vtkContourFilter()
    c.SetInputData(algorithm.GetInput())
    c.SetValue(0, value + 8.0 * t)
    c.ComputeScalarsOff()
    c.Update()
    algorithm.GetPolyDataOutput().ShallowCopy(c.GetOutput())
_whitted_contour(self, %r)
"""


def time_series(source, mode, steps, amplitude=1.5, value=157.0):
    """A time-varying filter over source with time steps 0 .. steps-1 (see above): mode "deform" (source
    polygonal) or "contour" (source an image, e.g. a Wavelet)."""
    from paraview.simple import ProgrammableFilter

    script = _DEFORM_SCRIPT % amplitude if mode == "deform" else _CONTOUR_SCRIPT % value
    return ProgrammableFilter(Input=source, OutputDataSetType="Same as Input" if mode == "deform" else "vtkPolyData",
                              Script=script, RequestInformationScript=_TIME_STEPS_SCRIPT % steps)


def material_keys(display):
    """The Whitted information keys the representation put on its actor's vtkProperty (what the pass renders), as
    {name: [values rounded to 1e-6]}."""
    rep = display.GetClientSideObject().GetActiveRepresentation()
    keys = {}
    for line in str(rep.GetActor().GetProperty().GetInformation()).splitlines():
        name, _, values = line.strip().partition(":")
        if name in ("REFLECTANCE", "TRANSMITTANCE", "INDEX_OF_REFRACTION", "ATTENUATION_COLOR",
                    "ATTENUATION_DISTANCE"):
            keys[name] = [round(float(v), 6) for v in values.split()]
    return keys


def info(view, name):
    """An information-only property of the view, fetched again (in client/server mode: the client's view object)"""
    view.UpdatePropertyInformation()
    return view.GetProperty(name).GetData()


def fail(msg):
    """Reports a failure and exits 1 (os._exit: pvbatch can crash while finalizing after sys.exit)."""
    print("FAILED: " + msg)
    sys.stdout.flush()
    os._exit(1)


def parse_args(tmp=False):
    """The arguments every test takes: --plugin P, and --tmp DIR (created) if tmp."""
    import argparse

    ap = argparse.ArgumentParser()
    ap.add_argument("--plugin", required=True)
    if tmp:
        ap.add_argument("--tmp", required=True)
    args = ap.parse_args()
    if tmp:
        os.makedirs(args.tmp, exist_ok=True)
    return args


class Checks:
    """Named checks: prints each, and finish() fails the test (exit 1) if any failed."""

    def __init__(self):
        self.failures = []

    def __call__(self, ok, message):
        print(("ok    " if ok else "FAIL  ") + message)
        if not ok:
            self.failures.append(message)

    def finish(self, name):
        if self.failures:
            fail("%d failures" % len(self.failures))
        print(name + ": ok")


# RENDER_VIEW: the Whitted view with its effects off (no shadows, reflections, refractions) against ParaView's own
# Render View raster of the same scene, on the pixels outside the mirror and glass spheres and away from
# silhouettes (check_against_render_view). Measured: test scene 0 of 100727 compared pixels differ (max 0); glyphs
# 6 of 53304 pixels (0.011%), max 58 (impostor vs traced sphere rims that the edge mask misses); translucent box
# (ground lowered by 1e-3, see check_against_render_view) 15 of 100613 (0.015%), max 14. Tolerance 6 and
# 0.1% (9x the glyphs' share): a 10/255 error on 1% of the pixels fails (paraview.negative_control).
RENDER_VIEW = dict(tolerance=6, max_bad_fraction=0.001)
# Effects on against effects off on the same pixels: shadows only darken; nothing may get lighter by more than this
EFFECTS_LIGHTER = 2


def silhouette_mask(pixels, threshold=16):
    """Pixels next to a colour step of more than threshold (any channel) in pixels: a one-pixel shift of a
    silhouette or shadow edge changes them; comparisons away from edges leave them out."""
    import numpy as np

    p = pixels.astype(np.int32)
    edge = np.zeros(p.shape[:2], dtype=bool)
    for dy in (-1, 0, 1):
        for dx in (-1, 0, 1):
            shifted = np.roll(np.roll(p, dy, axis=0), dx, axis=1)
            edge |= np.abs(p - shifted).max(axis=2) > threshold
    edge[0, :] = edge[-1, :] = True
    edge[:, 0] = edge[:, -1] = True
    return edge


def dilate(mask, steps=1):
    import numpy as np

    m = mask.copy()
    for _ in range(steps):
        grown = m.copy()
        for dy, dx in ((1, 0), (-1, 0), (0, 1), (0, -1)):
            grown |= np.roll(np.roll(m, dy, axis=0), dx, axis=1)
        m = grown
    return m


def off_props_and_edges(raster, without):
    """The pixels a Render View comparison uses: off the props that raster shows and without lacks (the difference,
    dilated by 2 pixels) and off the colour edges of either image (silhouette_mask)."""
    import numpy as np

    covered = dilate(np.abs(raster - without).max(axis=2) > 0, 2)
    return ~(covered | silhouette_mask(raster) | silhouette_mask(without))


def check_against_render_view(view, shown, args, image):
    """The independent check of a single-process Whitted image (test_render --render-view-oracle; see there).
    Returns a list of failures (empty if none)."""
    import numpy as np
    from paraview.simple import Hide, Render

    failures = []
    tmp = args.tmp
    name = args.name
    size = SIZE
    # The Render View's raster of the same scene, with and without the mirror and glass spheres
    rv = make_view(proxy="RenderView")
    rv.EnableRenderOnInteraction = 0
    rv_shown = build_scene(rv, opacity=0.5 if args.translucent else 1.0)
    # The box stands on the ground: its bottom face and the ground are coplanar. OpenGL draws a translucent face
    # over an opaque one at equal depth (translucent geometry comes after, depth test LEQUAL), the tracer keeps one
    # of two coplanar hits (the lower instance and primitive id, README "Coplanar surfaces"), so seen through the
    # translucent box the two differ by design (measured: 0.32% of the compared pixels by up to 34/255). The oracle
    # compares the scene without that tie: the ground lowered by 1e-3 in both views.
    lowered = []
    if args.translucent:
        for s in (shown, rv_shown):
            plane = s["ground"].Input
            for prop in ("Origin", "Point1", "Point2"):
                p = list(getattr(plane, prop))
                p[1] -= 1e-3
                setattr(plane, prop, p)
            lowered.append(plane)
    if args.view_features:
        add_view_features(rv, rv_shown)
    raster = screenshot(rv, os.path.join(tmp, name + "_renderview.png"), size)
    Hide(rv_shown["mirror"].Input, rv)
    Hide(rv_shown["glass"].Input, rv)
    without = screenshot(rv, os.path.join(tmp, name + "_renderview_matte.png"), size)
    compared = off_props_and_edges(raster, without)
    share = float(compared.mean())
    print("render-view oracle: %.1f%% of the pixels compared (not on the mirror or glass spheres, not on an edge)"
          % (100 * share))
    if share < 0.5:
        failures.append("render-view oracle compares only %.1f%% of the pixels" % (100 * share))
    # The Whitted view with its effects off
    view.Shadows = 0
    view.Reflections = 0
    view.Refractions = 0
    off_png = os.path.join(tmp, name + "_effects_off.png")
    off = screenshot(view, off_png, size)
    ok, _ = compare_image(off_png, os.path.join(tmp, name + "_renderview.png"), tmp, mask=compared, **RENDER_VIEW)
    if not ok:
        failures.append("effects off, the Whitted view differs from the Render View where effects cannot matter")
    # Effects on: shadows may only darken those pixels
    if lowered:  # the test's own image has the ground where it was: the same view with effects, ground lowered
        view.Shadows = 1
        view.Reflections = 1
        view.Refractions = 1
        on = screenshot(view, os.path.join(tmp, name + "_effects_on_lowered.png"), size)
    else:
        on = read_png(image)
    lighter = np.where(compared, (on - off).max(axis=2), 0)
    n_lighter = int((lighter > EFFECTS_LIGHTER).sum())
    print("effects on vs off: %d compared pixels lighter by more than %d (max %d), %d darker (shadows)" % (
        n_lighter, EFFECTS_LIGHTER, lighter.max(), int((np.where(compared, (off - on).max(axis=2), 0) > 8).sum())))
    if n_lighter:
        failures.append("effects on, %d pixels outside mirror and glass are lighter than without effects" % n_lighter)
    view.Shadows = 1
    view.Reflections = 1
    view.Refractions = 1
    for plane in lowered:
        for prop in ("Origin", "Point1", "Point2"):
            p = list(getattr(plane, prop))
            p[1] += 1e-3
            setattr(plane, prop, p)
    return failures
