#!/usr/bin/env python3
"""ShadowsFromBrightestLightOnly: shadow rays toward the brightest light only.

A sphere over a floor, lit by two directional lights from either side, so each casts its own shadow on the floor
(a key light of intensity 1 and a fill light of 0.4, both white). The independent reference is VTK's own per-light
control, vtkLight ShadowAttenuation 0 (a light that casts no shadow, already tested against VTK's raster):
- setting on: the image equals, pixel for pixel, the image with the setting off and the fill light's
  ShadowAttenuation 0; the fill light's shadow is gone, the key light's is there;
- setting off (vtkWhittedPass's default): both shadows are there (the image differs from the reference above);
- with the two intensities exchanged, the other light is the brightest: the setting keeps the other shadow;
- equal intensities: the brighter colour channel decides (a red key of 1 against a white fill of 0.9), and for
  exact equals the first light wins.
"""
import numpy as np
from vtkmodules.test import Testing
from vtkmodules.vtkFiltersSources import vtkPlaneSource, vtkSphereSource
from vtkmodules.vtkRenderingCore import vtkActor, vtkLight, vtkPolyDataMapper, vtkRenderer
import vtkmodules.vtkRenderingOpenGL2  # noqa: F401
from whitted import vtkWhittedPass
from whitted_imagetest import offscreen_render

SIZE = 160


def scene(intensities, attenuations=(1.0, 1.0), colors=((1, 1, 1), (1, 1, 1))):
    ren = vtkRenderer()
    ren.SetBackground(0.2, 0.3, 0.4)
    sphere = vtkSphereSource()
    sphere.SetCenter(0, 0, 0.8)
    sphere.SetRadius(0.5)
    sphere.SetThetaResolution(48)
    sphere.SetPhiResolution(24)
    floor = vtkPlaneSource()
    floor.SetOrigin(-3, -3, 0)
    floor.SetPoint1(3, -3, 0)
    floor.SetPoint2(-3, 3, 0)
    for source in (sphere, floor):
        mapper = vtkPolyDataMapper()
        mapper.SetInputConnection(source.GetOutputPort())
        actor = vtkActor()
        actor.SetMapper(mapper)
        ren.AddActor(actor)
    # Two directional lights from the left and from the right, 45 degrees up: shadows to either side
    for x, intensity, attenuation, color in zip((-1.0, 1.0), intensities, attenuations, colors):
        light = vtkLight()
        light.SetLightTypeToSceneLight()
        light.SetPositional(False)
        light.SetPosition(x, 0, 1)
        light.SetFocalPoint(0, 0, 0)
        light.SetIntensity(intensity)
        light.SetColor(*color)
        light.SetShadowAttenuation(attenuation)
        ren.AddLight(light)
    cam = ren.GetActiveCamera()
    cam.SetPosition(0, -0.01, 6)
    cam.SetFocalPoint(0, 0, 0)
    cam.SetViewUp(0, 1, 0)
    cam.SetViewAngle(40)
    ren.ResetCameraClippingRange()
    return ren


def traced(brightest_only, **kw):
    p = vtkWhittedPass()
    p.SetShadowsFromBrightestLightOnly(brightest_only)
    image, nan = offscreen_render(scene(**kw), SIZE, p,
                                  lambda q: q.GetLastFrameStatistics().GetNumberOfSafetyNetCatches())
    assert nan == 0, "safety-net catches %d on valid input" % nan
    return image


def floor_spot(x):
    """Mean grey of a floor spot at world x (y = 0) -- the shadows fall at x = +-0.8 (a light from -x throws the
    sphere's shadow toward +x)."""
    # camera at z = 6, 40 degrees: the image spans 2 x 6 x tan(20) = 4.37 world units at z = 0
    px = int(round(SIZE / 2 + x / (2 * 6 * np.tan(np.radians(20))) * SIZE))
    return px


class TestWhittedPythonShadowLights(Testing.vtkTest):
    def test(self):
        left_shadow = floor_spot(-0.8)  # the shadow the light from +x throws
        right_shadow = floor_spot(0.8)  # the shadow the light from -x throws
        row = SIZE // 2

        def grey(img, px):
            return img[row - 2:row + 3, px - 2:px + 3].mean()

        # Key (1.0) from -x, fill (0.4) from +x
        on = traced(True, intensities=(1.0, 0.4))
        off = traced(False, intensities=(1.0, 0.4))
        reference = traced(False, intensities=(1.0, 0.4), attenuations=(1.0, 0.0))
        both = traced(False, intensities=(1.0, 0.4), attenuations=(0.0, 0.0))
        print("key shadow (x=+0.8): on %.1f off %.1f unshadowed %.1f" % (
            grey(on, right_shadow), grey(off, right_shadow), grey(both, right_shadow)))
        print("fill shadow (x=-0.8): on %.1f off %.1f unshadowed %.1f" % (
            grey(on, left_shadow), grey(off, left_shadow), grey(both, left_shadow)))
        self.assertEqual(np.abs(on - reference).max(), 0, "setting on = the fill light's ShadowAttenuation 0")
        self.assertGreater(np.abs(off - reference).max(), 20, "setting off: the fill light's shadow is drawn")
        # The key light's shadow stays, the fill light's is gone (its spot as bright as with no shadows at all)
        self.assertLess(grey(on, right_shadow), grey(both, right_shadow) - 40)
        self.assertEqual(grey(on, left_shadow), grey(both, left_shadow))
        self.assertLess(grey(off, left_shadow), grey(both, left_shadow) - 10)

        # Exchanged intensities: the light from +x is now the brightest
        swapped = traced(True, intensities=(0.4, 1.0))
        swapped_ref = traced(False, intensities=(0.4, 1.0), attenuations=(0.0, 1.0))
        self.assertEqual(np.abs(swapped - swapped_ref).max(), 0, "the brighter light keeps its shadow")

        # Colour decides: a red key of 1 (largest channel 1) beats a white fill of 0.9
        colored = traced(True, intensities=(1.0, 0.9), colors=((1, 0, 0), (1, 1, 1)))
        colored_ref = traced(False, intensities=(1.0, 0.9), colors=((1, 0, 0), (1, 1, 1)), attenuations=(1.0, 0.0))
        self.assertEqual(np.abs(colored - colored_ref).max(), 0, "largest channel x intensity decides")
        # Equals: the first light
        equal = traced(True, intensities=(0.7, 0.7))
        equal_ref = traced(False, intensities=(0.7, 0.7), attenuations=(1.0, 0.0))
        self.assertEqual(np.abs(equal - equal_ref).max(), 0, "first of equals")
        # A light that casts no shadow of its own is never chosen: the fill's shadow when the key's is off
        fill_only = traced(True, intensities=(1.0, 0.4), attenuations=(0.0, 1.0))
        fill_only_ref = traced(False, intensities=(1.0, 0.4), attenuations=(0.0, 1.0))
        self.assertEqual(np.abs(fill_only - fill_only_ref).max(), 0, "only lights that cast shadows compete")


if __name__ == "__main__":
    Testing.main([(TestWhittedPythonShadowLights, "test")])
