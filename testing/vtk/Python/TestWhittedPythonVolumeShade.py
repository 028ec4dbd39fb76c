#!/usr/bin/env python3
"""Shaded volumes (vtkVolumeProperty Shade) and gradient opacity are traced, and agree with VTK's own GPU mapper.

A lumpy blob (41^3 floats) drawn by vtkGPUVolumeRayCastMapper at a fixed sample distance. Each case compares the
pass's image with VTK's image of the same renderer without the pass (the independent reference), MAE over the
pixels either covers, shadows and reflections off:
- the renderer's own headlight (VTK 9.1 lights a lone headlight along each viewing ray): Shade with the defaults,
  then with a strong highlight (specular 0.6, power 30), within 1/255 (measured 0.05);
- a vtkLightKit (ParaView's lights) and a user's scene light, diffuse only, within 1/255 (measured 0.07-0.08), and
  the scene light with an ambient colour, ambient only (VTK 9.1 then adds ambient x the light's ambient colour, not
  times the sample colour) within 1/255. With a
  highlight these differ more (kit 2.9/255, scene light 1.5/255, measured): VTK 9.1 keeps only the last light's
  highlight and takes the view direction from a mirrored position there, the tracer sums every light's highlight
  with the true view direction (checked against the formula in the core's VolumeShade tests);
- gradient opacity, with and without Shade, within 1/255 (measured 0.09-0.13);
- the users' settings beyond one sample per pixel: 4 samples per pixel, and Target Error 0.005 (refined until met,
  the volume's step estimate part of it), within 1/255 of VTK's one-sample image (measured 0.14 and 0.18);
- turning Shade on and off is a transfer update of the traced grid, not a conversion, and each frame agrees again;
- a mirror floor shows the shaded volume.
"""
import re

import numpy as np
from vtkmodules.test import Testing
from vtkmodules.util.numpy_support import numpy_to_vtk
from vtkmodules.vtkCommonDataModel import vtkImageData, vtkPiecewiseFunction
from vtkmodules.vtkRenderingCore import (vtkColorTransferFunction, vtkLight, vtkLightKit, vtkRenderer,
                                         vtkRenderWindow, vtkVolume, vtkVolumeProperty)
import vtkmodules.vtkRenderingOpenGL2  # noqa: F401
import vtkmodules.vtkRenderingVolumeOpenGL2  # noqa: F401
from vtkmodules.vtkRenderingVolume import vtkGPUVolumeRayCastMapper
from whitted import vtkWhittedPass
from whitted_imagetest import grab, offscreen_render, plain_pass, quad_actor

SIZE = 220
BACKGROUND = (0.32, 0.34, 0.43)  # ParaView's default background


def lumpy_blob(n=41, spacing=0.05):
    c = (np.arange(n) - 0.5 * (n - 1)) / (0.5 * (n - 1))
    z, y, x = np.meshgrid(c, c, c, indexing="ij")
    s = np.maximum(0.0, 1.0 - np.sqrt(x * x + y * y + z * z)) * (0.75 + 0.25 * np.sin(5 * x) * np.cos(4 * y))
    img = vtkImageData()
    img.SetDimensions(n, n, n)
    img.SetSpacing(spacing, spacing, spacing)
    h = 0.5 * spacing * (n - 1)
    img.SetOrigin(-h, -h, -h)
    img.GetPointData().SetScalars(numpy_to_vtk(s.astype(np.float32).ravel(), deep=1))
    return img


def make_volume(img):
    mapper = vtkGPUVolumeRayCastMapper()
    mapper.SetInputData(img)
    mapper.AutoAdjustSampleDistancesOff()
    mapper.SetSampleDistance(0.025)
    color = vtkColorTransferFunction()
    color.AddRGBPoint(0.0, 0.1, 0.2, 0.9)
    color.AddRGBPoint(0.5, 0.9, 0.4, 0.1)
    color.AddRGBPoint(1.0, 1.0, 1.0, 0.8)
    opacity = vtkPiecewiseFunction()
    for x, a in ((0.0, 0.0), (0.15, 0.02), (0.4, 0.3), (1.0, 0.8)):
        opacity.AddPoint(x, a)
    prop = vtkVolumeProperty()
    prop.SetColor(color)
    prop.SetScalarOpacity(opacity)
    prop.SetScalarOpacityUnitDistance(0.1)
    prop.SetInterpolationTypeToLinear()
    prop.ShadeOn()
    volume = vtkVolume()
    volume.SetMapper(mapper)
    volume.SetProperty(prop)
    return volume


def make_renderer(volume, lights="headlight", floor=False):
    ren = vtkRenderer()
    ren.SetBackground(*BACKGROUND)
    ren.AddVolume(volume)
    if lights == "kit":
        vtkLightKit().AddLightsToRenderer(ren)
    elif lights in ("scene", "scene-ambient"):
        light = vtkLight()
        light.SetPosition(1.0, 2.0, 1.0)
        light.SetFocalPoint(0.0, 0.0, 0.0)
        if lights == "scene-ambient":
            light.SetAmbientColor(0.8, 0.6, 0.4)
        ren.AddLight(light)
    if floor:  # a black mirror under the blob
        actor = quad_actor((-4.0, -1.0, 4.0), (4.0, -1.0, 4.0), (-4.0, -1.0, -4.0), (0.0, 0.0, 0.0), 1.0)
        actor.GetProperty().SetAmbient(0.0)
        actor.GetProperty().SetDiffuse(0.0)
        ren.AddActor(actor)
    # (with the floor: looking down on it, so that the volume's reflection is in view)
    eye, focal = ((0.3, 1.2, 4.5), (0.0, -0.9, 0.0)) if floor else ((0.6, 0.8, 3.2), (0.0, 0.0, 0.0))
    cam = ren.GetActiveCamera()
    cam.SetPosition(*eye)
    cam.SetFocalPoint(*focal)
    cam.SetViewUp(0.0, 1.0, 0.0)
    cam.SetViewAngle(40.0)
    ren.ResetCameraClippingRange()
    return ren


def frame_counts(p):
    text = p.GetLastFrameReport()
    m = re.search(r"(\d+) volumes traced \((\d+) converted, (\d+) transfer updates\), (\d+) props drawn by OpenGL",
                  text)
    assert m, text
    return tuple(int(g) for g in m.groups())


def covered_mae(a, b):
    background = np.array(BACKGROUND) * 255.0
    covered = (np.abs(a - background).max(axis=2) > 1) | (np.abs(b - background).max(axis=2) > 1)
    return float(np.abs(a - b)[covered].mean()), int(covered.sum())


class TestWhittedPythonVolumeShade(Testing.vtkTest):
    def agreement(self, name, lights="headlight", setup=None, limit=1.0, spp=1, target=0.0):
        volume = make_volume(lumpy_blob())
        if setup:
            setup(volume.GetProperty())
        p = plain_pass()
        p.SetSamplesPerPixel(spp)
        p.SetTargetError(target)
        def after(pass_):
            stats = pass_.GetLastFrameStatistics()
            return frame_counts(pass_), stats.GetNumberOfSamples(), stats.GetTargetErrorMet()

        traced, (counts, samples, met) = offscreen_render(make_renderer(volume, lights), SIZE, p, after)
        raster, _ = offscreen_render(make_renderer(volume, lights), SIZE)
        mae, covered = covered_mae(traced, raster)
        print("%-40s MAE %.3f/255 over %d covered pixels (limit %g); %d traced, %d OpenGL props" % (
            name, mae, covered, limit, counts[0], counts[3]))
        self.assertEqual(counts[0], 1, name)
        self.assertEqual(counts[3], 0, name + ": drawn by OpenGL, not traced")
        self.assertGreater(covered, 10000, name)
        self.assertLessEqual(mae, limit, name)
        if target > 0.0:  # refined until met: more samples than one per pixel
            print("  target met %s with %d samples (%.2f per pixel)" % (met, samples, samples / SIZE / SIZE))
            self.assertTrue(met, name)
            self.assertGreater(samples, SIZE * SIZE, name)
        else:
            self.assertEqual(samples, spp * SIZE * SIZE, name)

    def test(self):
        def highlight(prop):
            prop.SetSpecular(0.6)
            prop.SetSpecularPower(30.0)

        def diffuse_only(prop):
            prop.SetSpecular(0.0)

        def gradient_opacity(prop):
            g = vtkPiecewiseFunction()
            g.AddPoint(0.0, 0.0)
            g.AddPoint(0.05, 1.0)
            prop.SetGradientOpacity(g)

        def gradient_opacity_unshaded(prop):
            gradient_opacity(prop)
            prop.ShadeOff()

        self.agreement("headlight, Shade with VTK's defaults")
        self.agreement("headlight, specular 0.6 power 30", setup=highlight)
        self.agreement("headlight, Shade, 4 samples per pixel", spp=4)
        self.agreement("headlight, Shade, Target Error 0.005", target=0.005)
        self.agreement("light kit, diffuse", "kit", diffuse_only)
        self.agreement("scene light, diffuse", "scene", diffuse_only)

        def ambient_only(prop):
            prop.SetAmbient(0.5)
            prop.SetDiffuse(0.0)
            prop.SetSpecular(0.0)

        self.agreement("scene light with an ambient colour, ambient", "scene-ambient", ambient_only)
        self.agreement("gradient opacity, shaded", setup=gradient_opacity)
        self.agreement("gradient opacity, Shade off", setup=gradient_opacity_unshaded)

        # Shade toggled between frames of one pass: a transfer update each time, and VTK's image each time
        volume = make_volume(lumpy_blob())
        win = vtkRenderWindow()
        win.SetOffScreenRendering(1)
        win.SetSize(SIZE, SIZE)
        ren = make_renderer(volume)
        win.AddRenderer(ren)
        p = plain_pass()
        for shade, expect in ((1, (1, 0)), (0, (0, 1)), (1, (0, 1))):
            volume.GetProperty().SetShade(shade)
            ren.SetPass(p)
            win.Render()
            counts = frame_counts(p)
            traced = grab(win)
            ren.SetPass(None)
            win.Render()
            mae, _ = covered_mae(traced, grab(win))
            print("Shade %d: %d converted, %d transfer updates; MAE %.3f/255" % (shade, counts[1], counts[2], mae))
            self.assertEqual((counts[1], counts[2]), expect)
            self.assertLessEqual(mae, 1.0)
        shaded_frame = traced
        volume.GetProperty().ShadeOff()
        ren.SetPass(p)
        win.Render()
        unshaded_frame = grab(win)
        changed = int((np.abs(shaded_frame - unshaded_frame).max(axis=2) > 8).sum())
        print("Shade on against off: %d pixels differ by more than 8/255" % changed)
        self.assertGreater(changed, 1000)
        ren.SetPass(None)
        win.Finalize()

        # A mirror floor shows the shaded volume: pixels off its direct footprint change when it is shown
        volume = make_volume(lumpy_blob())
        ren = make_renderer(volume, floor=True)
        ren.GetViewProps().RemoveAllItems()  # (the same view without the mirror)
        ren.AddVolume(volume)
        direct, _ = offscreen_render(ren, SIZE, plain_pass())
        ren = make_renderer(volume, floor=True)
        p = vtkWhittedPass()
        p.SetShadows(False)
        with_volume, _ = offscreen_render(ren, SIZE, p)
        volume.VisibilityOff()
        without, _ = offscreen_render(ren, SIZE, p)
        footprint = np.abs(direct - np.array(BACKGROUND) * 255.0).max(axis=2) > 3
        for _ in range(3):
            footprint = footprint | np.roll(footprint, 1, 0) | np.roll(footprint, -1, 0) | \
                np.roll(footprint, 1, 1) | np.roll(footprint, -1, 1)
        reflection = int(((np.abs(with_volume - without).max(axis=2) > 8) & ~footprint).sum())
        print("mirror: %d pixels off the footprint change when the shaded volume is shown" % reflection)
        self.assertGreater(reflection, 500)


if __name__ == "__main__":
    Testing.main([(TestWhittedPythonVolumeShade, "test")])
