"""The Volume representation of image data in the Whitted view: traced (not left to OpenGL), seen in a mirror,
and a transfer-function edit reflected in the next frame without converting the grid again.

    pvbatch test_volume.py --plugin P --tmp DIR

A Wavelet (21^3 image data, RTData) shown as Volume above a mirror floor (Whitted Surface, Reflectance 1, black).
Checks, from the frame report and screenshots:
  - the volume is traced: "1 volumes traced", nothing drawn by OpenGL;
  - the mirror shows it: with the volume shown, pixels outside its direct footprint (where it is seen without the
    mirror, dilated by 3 pixels) change against the volume hidden: only its reflection can change them;
  - a colour-map edit (another preset) converts no grid, updates one transfer function, and changes the
    reflection's pixels;
  - Shade on is traced too (a transfer update) and agrees with the Render View's shaded volume within MAE 3/255;
  - the Wavelet cut to tetrahedra (an unstructured grid) as Volume is traced too, resampled to image data, and
    agrees with the Render View's own projected tetrahedra within MAE 3/255.
"""
import os
import re
import sys

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import whitted_pvtest as wt  # noqa: E402

args = wt.parse_args(tmp=True)

import paraview.simple  # noqa: E402,F401
from paraview.simple import (ColorBy, GetColorTransferFunction, Hide, Plane, Render, Show,  # noqa: E402
                             Tetrahedralize, Wavelet)

wt.load_plugin(args.plugin)
check = wt.Checks()
SIZE = [300, 240]
EYE, FOCUS = (0.0, 14.0, 75.0), (0.0, -6.0, 0.0)  # the test camera


def report(view):
    view.UpdatePropertyInformation()
    text = view.GetProperty("LastFrameReport").GetData()
    m = re.search(r"(\d+) volumes traced \((\d+) converted, (\d+) transfer updates\), (\d+) props drawn by OpenGL",
                  text)
    if not m:
        print(text)
        wt.fail("no volume line in the frame report")
    return tuple(int(g) for g in m.groups())


view = wt.make_view(SIZE)
wavelet = Wavelet()
volume = Show(wavelet, view)
volume.Representation = "Volume"
ColorBy(volume, ("POINTS", "RTData"))
lut = GetColorTransferFunction("RTData")
lut.ApplyPreset("Cool to Warm", True)
wt.set_camera(view, EYE, FOCUS)

# The volume alone: its direct footprint
Render(view)
alone = wt.screenshot(view, os.path.join(args.tmp, "volume_alone.png"), SIZE)
background = np.array([0.32, 0.34, 0.43]) * 255.0
footprint = np.abs(alone - background).max(axis=2) > 3
footprint = wt.dilate(footprint, 3)
traced, converted, transfers, opengl = report(view)
print("volume alone: %d traced, %d converted, %d transfer updates, %d OpenGL props; footprint %d pixels" % (
    traced, converted, transfers, opengl, int(footprint.sum())))
check(traced == 1 and opengl == 0, "the volume is traced, not drawn by OpenGL")
check(footprint.sum() > 2000, "the volume covers pixels")


def render_view_mae(source, traced, name, shade=False):
    """MAE (8-bit levels) between traced and ParaView's Render View of source shown as Volume (the oracle), over
    the pixels either covers, and how many."""
    rv = wt.make_view(SIZE, proxy="RenderView")
    display = Show(source, rv)
    display.Representation = "Volume"
    ColorBy(display, ("POINTS", "RTData"))
    if shade:
        display.Shade = 1
    wt.set_camera(rv, EYE, FOCUS)
    raster = wt.screenshot(rv, os.path.join(args.tmp, name + "_render_view.png"), SIZE)
    covered = (np.abs(traced - background).max(axis=2) > 1) | (np.abs(raster - background).max(axis=2) > 1)
    paraview.simple.Delete(rv)
    paraview.simple.SetActiveView(view)
    return float(np.abs(traced - raster)[covered].mean()), int(covered.sum())


# ParaView's own Render View of the same volume (the oracle)
mae, count = render_view_mae(wavelet, alone, "volume")
print("against the Render View: MAE %.3f/255 over %d covered pixels (limit 3)" % (mae, count))
check(mae <= 3.0, "the traced volume agrees with ParaView's Render View (MAE <= 3/255)")

# Shade (the Volume Rendering section's checkbox): traced too, lit by ParaView's light kit, and toggling it is a
# transfer update; against the Render View's shaded volume
volume.Shade = 1
Render(view)
traced, converted, transfers, opengl = report(view)
shaded = wt.screenshot(view, os.path.join(args.tmp, "volume_shaded.png"), SIZE)
print("Shade: %d traced, %d converted, %d transfer updates, %d OpenGL props" % (traced, converted, transfers, opengl))
check(traced == 1 and opengl == 0, "a shaded volume is traced, not drawn by OpenGL")
check(converted == 0 and transfers == 1, "turning Shade on updates the transfer function only")
mae, count = render_view_mae(wavelet, shaded, "volume_shaded", shade=True)
changed = int((np.abs(shaded - alone).max(axis=2) > 8).sum())
print("shaded against the Render View: MAE %.3f/255 over %d covered pixels (limit 3); %d pixels differ from the "
      "unshaded frame" % (mae, count, changed))
check(mae <= 3.0, "the shaded volume agrees with ParaView's Render View (MAE <= 3/255)")
check(changed > 1000, "Shade changes the image")
volume.Shade = 0

# A mirror floor under it
floor_source = Plane(Origin=[-40.0, -14.0, 40.0], Point1=[40.0, -14.0, 40.0], Point2=[-40.0, -14.0, -40.0])
floor = Show(floor_source, view)
floor.Representation = "Whitted Surface"
floor.DiffuseColor = [0.0, 0.0, 0.0]
floor.AmbientColor = [0.0, 0.0, 0.0]
floor.Specular = 0.0
floor.Reflectance = 1.0
wt.set_camera(view, EYE, FOCUS)
with_volume = wt.screenshot(view, os.path.join(args.tmp, "volume_mirror.png"), SIZE)
Hide(wavelet, view)
without = wt.screenshot(view, os.path.join(args.tmp, "volume_mirror_hidden.png"), SIZE)
Show(wavelet, view)
reflection = (np.abs(with_volume - without).max(axis=2) > 8) & ~footprint
print("mirror: %d pixels outside the volume's footprint change when it is shown" % int(reflection.sum()))
check(reflection.sum() > 1000, "the mirror shows the volume")

# A transfer-function edit: the next frame updates the transfer function only, and the reflection changes
Render(view)
report(view)
lut.ApplyPreset("Viridis (matplotlib)", True)
Render(view)
traced, converted, transfers, opengl = report(view)
edited = wt.screenshot(view, os.path.join(args.tmp, "volume_mirror_edited.png"), SIZE)
changed = int(((np.abs(edited - with_volume).max(axis=2) > 8) & reflection).sum())
print("colour-map edit: %d converted, %d transfer updates; %d reflection pixels changed" % (
    converted, transfers, changed))
check(converted == 0 and transfers == 1, "the edit updates the transfer function only (no grid conversion)")
check(changed > 0.3 * reflection.sum(), "the edit shows in the mirror in the next frame")
# An unstructured grid (the Wavelet cut to tetrahedra) as Volume: ParaView draws it with projected tetrahedra by
# default; the Whitted view traces it resampled to image data (vtkResampleToImage, 128^3), against the Render
# View's own projected tetrahedra
Hide(wavelet, view)
Hide(floor_source, view)
tets = Tetrahedralize(Input=wavelet)
ug = Show(tets, view)
ug.Representation = "Volume"
ColorBy(ug, ("POINTS", "RTData"))
wt.set_camera(view, EYE, FOCUS)
traced_ug = wt.screenshot(view, os.path.join(args.tmp, "volume_unstructured.png"), SIZE)
traced, converted, transfers, opengl = report(view)
print("unstructured grid (%s): %d traced, %d OpenGL props" % (ug.SelectMapper, traced, opengl))
check(traced == 1 and opengl == 0, "an unstructured grid shown as Volume is traced (resampled), not left to OpenGL")
mae, count = render_view_mae(tets, traced_ug, "volume_unstructured")
print("unstructured against the Render View (projected tetrahedra): MAE %.3f/255 over %d covered pixels (limit 3)"
      % (mae, count))
check(count > 2000 and mae <= 3.0, "the resampled unstructured volume agrees with the Render View")
check.finish("volume")
