#!/usr/bin/env python3
"""3D glyphs (vtkGlyph3DMapper) traced as instances of their source.

- Agreement: with shadows, reflections and refractions off, the traced glyphs reproduce VTK's own OpenGL image
  (colour and depth) of the same mapper, in two set-ups: (a) orientation by a vector array (DIRECTION), scale by
  a scalar's magnitude, colour by that scalar through a lookup table, two sources picked by an index array and a
  mask array; (b) ROTATION and QUATERNION orientation, scale by components with Range and Clamping, inside an
  actor with its own position and orientation.
- Instancing: the glyphs cost instances, not geometry: the scene holds the sources' triangles once, and one
  traced instance per drawn glyph.
- Bad input: NaN points, orientations, scales and source indices, zero scales and an orientation array of the
  wrong size render without a crash or a non-finite pixel (the NaN glyphs are left out, the wrong array draws no
  glyph, as in VTK).
- Caching: a camera move converts and places nothing (no top-level rebuild); a lookup-table edit recolours the
  glyphs in place (no object BVH rebuilt); fewer points hide the surplus instances.
- Effects: glyphs cast shadows on the floor (floor pixels darker with shadows than without) and show in a mirror
  (mirror pixels change when the glyphs are hidden); that image is the regression baseline
  (TestWhittedPythonGlyphs.png), whose glyphs are checked against OpenGL by the agreement above.
"""
import math

import numpy as np
from vtkmodules.test import Testing
from vtkmodules.vtkCommonCore import vtkBitArray, vtkDoubleArray, vtkLookupTable, vtkPoints
from vtkmodules.vtkCommonDataModel import vtkPolyData
from vtkmodules.vtkFiltersSources import vtkConeSource, vtkCubeSource, vtkSphereSource
from vtkmodules.vtkRenderingCore import vtkActor, vtkGlyph3DMapper, vtkRenderer, vtkRenderWindow
import vtkmodules.vtkRenderingOpenGL2  # noqa: F401
from whitted import vtkWhittedPass
from whitted_imagetest import (apply_test_switches, check_against_raster, check_baseline, grab_with_depth,
                               light_and_camera, quad_actor)



def array(name, components, values):
    a = vtkDoubleArray()
    a.SetName(name)
    a.SetNumberOfComponents(components)
    for v in values:
        a.InsertNextTuple(v if components > 1 else (v,))
    return a


def points_grid(nx, ny, spacing, height):
    points = vtkPoints()
    for j in range(ny):
        for i in range(nx):
            points.InsertNextPoint((i - (nx - 1) / 2) * spacing, height, (j - (ny - 1) / 2) * spacing)
    poly = vtkPolyData()
    poly.SetPoints(points)
    return poly


def sources():
    cone = vtkConeSource()
    cone.SetResolution(24)
    cone.SetHeight(1.0)
    cone.SetRadius(0.3)
    ball = vtkSphereSource()
    ball.SetThetaResolution(24)
    ball.SetPhiResolution(12)
    ball.SetRadius(0.3)
    return cone, ball


def directed_glyphs():
    """(a): DIRECTION orientation, magnitude scaling by a scalar, colour by that scalar, two sources by index,
    a mask."""
    poly = points_grid(5, 4, 0.9, 0.6)
    n = poly.GetNumberOfPoints()
    speed = [0.6 + 0.5 * ((7 * i) % 5) / 4 for i in range(n)]
    poly.GetPointData().AddArray(array("speed", 1, speed))
    poly.GetPointData().AddArray(array("velocity", 3, [(math.cos(i), 0.6 * math.sin(2 * i), math.sin(i))
                                                       for i in range(n)]))
    poly.GetPointData().AddArray(array("shape", 1, [i % 3 for i in range(n)]))  # 2 clamps to the last source
    mask = vtkBitArray()
    mask.SetName("mask")
    for i in range(n):
        mask.InsertNextValue(0 if i in (3, 11) else 1)
    poly.GetPointData().AddArray(mask)
    poly.GetPointData().SetActiveScalars("speed")

    cone, ball = sources()
    mapper = vtkGlyph3DMapper()
    mapper.SetInputData(poly)
    mapper.SetSourceConnection(0, cone.GetOutputPort())
    mapper.SetSourceConnection(1, ball.GetOutputPort())
    mapper.SetScaleArray("speed")
    mapper.SetScaleModeToScaleByMagnitude()
    mapper.SetScaleFactor(0.9)
    mapper.SetOrientationArray("velocity")
    mapper.SetOrientationModeToDirection()
    mapper.SourceIndexingOn()
    mapper.SetSourceIndexArray("shape")
    mapper.MaskingOn()
    mapper.SetMaskArray("mask")
    lut = vtkLookupTable()
    lut.SetHueRange(0.65, 0.0)
    lut.Build()
    mapper.SetLookupTable(lut)
    mapper.SetScalarRange(0.6, 1.1)
    actor = vtkActor()
    actor.SetMapper(mapper)
    actor.GetProperty().SetSpecular(0.4)
    actor.GetProperty().SetSpecularPower(30)
    drawn = n - 2
    return actor, drawn


def rotated_glyphs():
    """(b): ROTATION (degrees) and QUATERNION orientation, scale by components with Range and Clamping, in a
    moved and turned actor; no scalars (property colour)."""
    actors = []
    for mode in ("rotation", "quaternion"):
        poly = points_grid(4, 3, 1.0, 0.7 if mode == "rotation" else 1.9)
        n = poly.GetNumberOfPoints()
        if mode == "rotation":
            poly.GetPointData().AddArray(array("orient", 3, [(20 * i, 35 * i, 50 * i) for i in range(n)]))
        else:
            quats = []
            for i in range(n):
                a, axis = 0.4 * i, (math.sin(i), 1.0, math.cos(i))
                norm = math.sqrt(sum(c * c for c in axis))
                quats.append((math.cos(a / 2),) + tuple(math.sin(a / 2) * c / norm for c in axis))
            poly.GetPointData().AddArray(array("orient", 4, quats))
        poly.GetPointData().AddArray(array("sizes", 3, [(1 + i % 3, 2 + (i * 5) % 4, 1.5 + i % 2) for i in range(n)]))
        cube = vtkCubeSource()
        cube.SetXLength(0.8)
        cube.SetYLength(0.5)
        cube.SetZLength(0.3)
        mapper = vtkGlyph3DMapper()
        mapper.SetInputData(poly)
        mapper.SetSourceConnection(cube.GetOutputPort())
        mapper.SetScaleArray("sizes")
        mapper.SetScaleModeToScaleByVectorComponents()
        mapper.SetRange(0.5, 4.0)
        mapper.ClampingOn()
        mapper.SetScaleFactor(0.8)
        mapper.SetOrientationArray("orient")
        if mode == "rotation":
            mapper.SetOrientationModeToRotation()
        else:
            mapper.SetOrientationModeToQuaternion()
        actor = vtkActor()
        actor.SetMapper(mapper)
        actor.SetPosition(0.3, 0.0, -0.2)
        actor.SetOrientation(0, 25, 0)
        actor.GetProperty().SetColor(0.9, 0.6, 0.3)
        actor.GetProperty().SetSpecular(0.3)
        actors.append(actor)
    return actors


def floor_actor(size=4.0):
    return quad_actor((-size, 0, size), (size, 0, size), (-size, 0, -size), (0.85, 0.85, 0.8))


def mirror_actor():
    return quad_actor((-4, 0, -2.4), (4, 0, -2.4), (-4, 3, -2.4), (0.1, 0.1, 0.12), reflectance=0.85)


def scene(actors, with_mirror=False):
    ren = vtkRenderer()
    for a in actors:
        ren.AddActor(a)
    ren.AddActor(floor_actor())
    if with_mirror:
        ren.AddActor(mirror_actor())
    light_and_camera(ren, (1.5, 6, 3), (0.5, 3.8, 6.5), (0, 0.6, 0))
    return ren


def window_of(ren, size=(300, 220)):
    win = vtkRenderWindow()
    win.SetMultiSamples(0)
    win.SetOffScreenRendering(True)
    win.SetSize(*size)
    win.AddRenderer(ren)
    return win


def traced(win, ren, shadows=True, reflections=True):
    p = apply_test_switches(vtkWhittedPass())
    p.SetShadows(shadows)
    p.SetReflections(reflections)
    p.SetRefractions(False)
    ren.SetPass(p)
    win.Render()
    return p, grab_with_depth(win)


class TestWhittedPythonGlyphs(Testing.vtkTest):
    def agree(self, actors, name):
        ren = scene(actors)
        win = window_of(ren)
        win.Render()
        gl_rgb, gl_z = grab_with_depth(win)
        _, (rt_rgb, rt_z) = traced(win, ren, shadows=False, reflections=False)
        d = np.abs(gl_rgb - rt_rgb).max(axis=2)
        hit = (gl_z < 1) & (rt_z < 1)
        coverage = ((gl_z < 1) != (rt_z < 1)).mean()
        depth_off = (np.abs(gl_z - rt_z)[hit] > 1e-3).mean()
        glyph_pixels = (np.abs(gl_rgb - grab_floor_only()[0]).max(axis=2) > 0).mean()
        print("%s: glyph pixels %.1f%%, mean |d| %.4f, >1: %.3f%%, >3: %.3f%%, coverage mismatch %.3f%%, "
              "depth > 1e-3: %.3f%%" % (name, 100 * glyph_pixels, d.mean(), 100 * (d > 1).mean(),
                                        100 * (d > 3).mean(), 100 * coverage, 100 * depth_off))
        self.assertGreater(glyph_pixels, 0.05)  # the glyphs fill a good part of the image
        self.assertLess((d > 1).mean(), 0.005)
        self.assertLess((d > 3).mean(), 0.002)
        self.assertLess(coverage, 0.002)
        self.assertLess(depth_off, 0.001)

    def testAgreementDirected(self):
        actor, _ = directed_glyphs()
        self.agree([actor], "direction/magnitude/colours/index/mask")

    def testAgreementRotated(self):
        self.agree(rotated_glyphs(), "rotation/quaternion/components/clamping/actor matrix")

    def testInstancingShadowsMirror(self):
        actor, drawn = directed_glyphs()
        ren = scene([actor], with_mirror=True)
        win = window_of(ren)
        p, (with_shadows, z) = traced(win, ren)
        stats = p.GetLastFrameStatistics()
        cone, ball = sources()
        cone.Update()
        ball.Update()
        source_triangles = cone.GetOutput().GetNumberOfPolys() - 1 + cone.GetResolution() - 2 + \
            ball.GetOutput().GetNumberOfPolys()
        print("instances %d, triangles %d (sources %d + floor 2 + mirror 2)"
              % (stats.GetNumberOfInstances(), stats.GetNumberOfTriangles(), source_triangles))
        self.assertEqual(stats.GetNumberOfInstances(), drawn + 2)
        self.assertEqual(stats.GetNumberOfTriangles(), source_triangles + 4)

        # The regression image (shadows and mirror)
        check_baseline(self, win, "TestWhittedPythonGlyphs.png")
        # Independent: VTK's raster of the same scene (its own glyphs) without the mirror
        mirror_quad = ren.GetActors().GetLastActor()
        check_against_raster(self, "PythonGlyphs", win, p, [mirror_quad], min_shadow_share=0.01,
                             min_umbra_share=0.05)

        # Shadows: floor pixels darker with shadows on (the floor alone casts none)
        _, (no_shadows, _) = traced(win, ren, shadows=False)
        darker = (no_shadows - with_shadows).max(axis=2) > 25
        print("shadow pixels: %d" % darker.sum())
        self.assertGreater(darker.sum(), 300)

        # Mirror: where the camera sees the mirror (same depth with and without glyphs), its colour changes when
        # the glyphs are hidden
        actor.VisibilityOff()
        _, (no_glyphs, z_no_glyphs) = traced(win, ren)
        mirror = (np.abs(z - z_no_glyphs) < 1e-7) & (z < 1)
        mirror_rows = np.zeros_like(mirror)
        mirror_rows[int(0.55 * mirror.shape[0]):, :] = True  # upper part of the image: the mirror wall
        reflected = mirror & mirror_rows & (np.abs(with_shadows - no_glyphs).max(axis=2) > 25)
        print("reflected glyph pixels: %d" % reflected.sum())
        self.assertGreater(reflected.sum(), 300)


class TestWhittedPythonGlyphCaching(Testing.vtkTest):
    def testCaching(self):
        actor, drawn = directed_glyphs()
        ren = scene([actor])
        win = window_of(ren)
        p, (first, _) = traced(win, ren)
        stats = p.GetLastFrameStatistics()
        ren.GetActiveCamera().Azimuth(2)
        win.Render()
        print("camera move: converted %d, objects rebuilt %d, top level rebuilt %d"
              % (stats.GetNumberOfGeometriesConverted(), stats.GetNumberOfObjectsRebuilt(), stats.GetTopLevelRebuilt()))
        self.assertEqual(stats.GetNumberOfGeometriesConverted(), 0)
        self.assertEqual(stats.GetNumberOfObjectsRebuilt(), 0)
        self.assertFalse(stats.GetTopLevelRebuilt())
        ren.GetActiveCamera().Azimuth(-2)
        win.Render()
        same, _ = grab_with_depth(win)
        self.assertEqual(np.abs(same - first).max(), 0)

        lut = actor.GetMapper().GetLookupTable()
        lut.SetHueRange(0.3, 0.9)
        lut.Build()
        win.Render()
        recoloured, _ = grab_with_depth(win)
        changed = (np.abs(recoloured - first).max(axis=2) > 25).mean()
        print("lookup-table edit: %.1f%% of pixels changed, objects rebuilt %d"
              % (100 * changed, stats.GetNumberOfObjectsRebuilt()))
        self.assertGreater(changed, 0.05)
        self.assertEqual(stats.GetNumberOfObjectsRebuilt(), 0)

        # Fewer points: the surplus instances are hidden
        poly = actor.GetMapper().GetInput()
        poly.GetPointData().GetArray("mask").SetValue(0, 0)
        poly.GetPointData().GetArray("mask").Modified()
        poly.Modified()
        win.Render()
        print("one more glyph masked: %d instances" % stats.GetNumberOfInstances())
        self.assertEqual(stats.GetNumberOfInstances(), drawn - 1 + 1)  # + the floor


class TestWhittedPythonGlyphBadInput(Testing.vtkTest):
    def testBadInput(self):
        nan = float("nan")
        actor, _ = directed_glyphs()
        poly = actor.GetMapper().GetInput()
        poly.GetPoints().SetPoint(1, nan, 0, 0)
        poly.GetPointData().GetArray("velocity").SetTuple3(2, nan, 1, 0)
        poly.GetPointData().GetArray("speed").SetValue(4, nan)
        poly.GetPointData().GetArray("speed").SetValue(5, 0.0)
        poly.GetPointData().GetArray("shape").SetValue(6, nan)
        poly.GetPointData().GetArray("shape").SetValue(7, 1e30)
        ren = scene([actor])
        win = window_of(ren)
        p, (rgb, _) = traced(win, ren)
        stats = p.GetLastFrameStatistics()
        print("bad input: %d instances, %d safety-net catches" % (stats.GetNumberOfInstances(),
                                                                  stats.GetNumberOfSafetyNetCatches()))
        self.assertEqual(stats.GetNumberOfSafetyNetCatches(), 0)
        self.assertGreater(stats.GetNumberOfInstances(), 10)
        self.assertTrue(np.isfinite(rgb).all())

        # An orientation array of the wrong size: VTK draws no glyph, nor does the pass
        actor.GetMapper().SetOrientationModeToQuaternion()
        win.Render()
        print("3-component array as quaternions: %d instances" % stats.GetNumberOfInstances())
        self.assertEqual(stats.GetNumberOfInstances(), 1)  # the floor


def grab_floor_only():
    ren = scene([])
    win = window_of(ren)
    win.Render()
    return grab_with_depth(win)


if __name__ == "__main__":
    Testing.main([(TestWhittedPythonGlyphs, "test"), (TestWhittedPythonGlyphCaching, "test"),
                  (TestWhittedPythonGlyphBadInput, "test")])
