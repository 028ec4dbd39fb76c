#!/usr/bin/env python3
"""Per-point radii: Point Gaussian splats, points as spheres and lines as tubes with a radius array.

- Point Gaussian (vtkPointGaussianMapper): each splat a sphere of radius ScaleFunction(ScaleArray) x ScaleFactor,
  coloured by the mapper's scalars. Checked against an independent reference: the same spheres built here as
  finely tessellated vtkSphereSource actors (radius and colour computed in this script from the function and
  the lookup table) drawn by VTK's OpenGL: silhouettes, depth and colours agree.
- vtkWhittedMaterialKeys.RADIUS_ARRAY / RADIUS_FUNCTION on a points-as-spheres actor: the same reference.
- Lines as tubes with RADIUS_ARRAY: looking straight at a polyline, each segment's width in pixels is twice the
  mean of its end points' radii.
- Effects: splats and tubes cast shadows (floor darker than without shadows) and the image with shadows and a
  mirror is the regression baseline (TestWhittedPythonRadii.png).
"""
import numpy as np
from vtkmodules.test import Testing
from vtkmodules.vtkCommonCore import vtkDoubleArray, vtkLookupTable, vtkPoints
from vtkmodules.vtkCommonDataModel import vtkCellArray, vtkPiecewiseFunction, vtkPolyData, vtkPolyLine
from vtkmodules.vtkFiltersSources import vtkSphereSource
from vtkmodules.vtkRenderingCore import (vtkActor, vtkPointGaussianMapper, vtkPolyDataMapper,
                                         vtkRenderer, vtkRenderWindow)
import vtkmodules.vtkRenderingOpenGL2  # noqa: F401
from whitted import vtkWhittedMaterialKeys, vtkWhittedPass
from whitted_imagetest import (apply_test_switches, check_against_raster, check_baseline, grab_with_depth,
                               light_and_camera, quad_actor)

SIZE = (300, 220)
SIZES = [0.5, 2.0, 3.5, 5.0, 6.5, 8.0, 9.5, 12.0, -1.0]   # the last two clamp to the function's ends
TEMPS = [float(i) for i in range(len(SIZES))]
FACTOR = 1.5



def scale_function():
    f = vtkPiecewiseFunction()
    f.AddPoint(0.0, 0.08)
    f.AddPoint(4.0, 0.2)
    f.AddPoint(10.0, 0.3)
    return f


def lookup_table():
    lut = vtkLookupTable()
    lut.SetHueRange(0.0, 0.7)
    lut.SetRange(0, len(TEMPS) - 1)
    lut.Build()
    return lut


def centres():
    return [((i % 3) * 1.0 - 1.0, 0.45 + 0.5 * (i // 3), (i // 3) * 0.3 - 0.3) for i in range(len(SIZES))]


def cloud(verts=True):
    points = vtkPoints()
    cells = vtkCellArray()
    for c in centres():
        cells.InsertNextCell(1, [points.InsertNextPoint(c)])
    poly = vtkPolyData()
    poly.SetPoints(points)
    if verts:
        poly.SetVerts(cells)
    for name, values in (("size", SIZES), ("temp", TEMPS)):
        a = vtkDoubleArray()
        a.SetName(name)
        for v in values:
            a.InsertNextValue(v)
        poly.GetPointData().AddArray(a)
    poly.GetPointData().SetActiveScalars("temp")
    return poly


def expected_radius(size, factor):
    f = scale_function()
    lo, hi = f.GetRange()
    return f.GetValue(min(max(size, lo), hi)) * factor


def gaussian_actor():
    mapper = vtkPointGaussianMapper()
    mapper.SetInputData(cloud(verts=False))  # no vertex cells: a splat per point
    mapper.SetScaleArray("size")
    mapper.SetScaleFunction(scale_function())
    mapper.SetScaleFactor(FACTOR)
    mapper.EmissiveOff()
    mapper.SetLookupTable(lookup_table())
    mapper.SetScalarRange(0, len(TEMPS) - 1)
    actor = vtkActor()
    actor.SetMapper(mapper)
    return actor


def radius_key_actor():
    mapper = vtkPolyDataMapper()
    mapper.SetInputData(cloud())
    mapper.SetLookupTable(lookup_table())
    mapper.SetScalarRange(0, len(TEMPS) - 1)
    actor = vtkActor()
    actor.SetMapper(mapper)
    actor.GetProperty().SetRenderPointsAsSpheres(True)
    actor.GetProperty().SetPointSize(4)  # ignored: the radius array decides
    info = actor.GetProperty().GetInformation()
    info.Set(vtkWhittedMaterialKeys.RADIUS_ARRAY(), "size")
    info.Set(vtkWhittedMaterialKeys.RADIUS_FUNCTION(), scale_function())
    actor.SetScale(FACTOR)  # the radius key gives data units: the actor scale applies
    return actor


def reference_actors(factor_in_radius, actor_scale=1.0):
    lut = lookup_table()
    actors = []
    for c, size, temp in zip(centres(), SIZES, TEMPS):
        s = vtkSphereSource()
        s.SetCenter(*c)
        s.SetRadius(expected_radius(size, factor_in_radius))
        s.SetThetaResolution(120)
        s.SetPhiResolution(60)
        mapper = vtkPolyDataMapper()
        mapper.SetInputConnection(s.GetOutputPort())
        a = vtkActor()
        a.SetMapper(mapper)
        rgb = [0.0, 0.0, 0.0]
        lut.GetColor(temp, rgb)
        a.GetProperty().SetColor(*rgb)
        a.SetScale(actor_scale)
        actors.append(a)
    return actors


def renderer(actors, floor=False, mirror=False):
    ren = vtkRenderer()
    for a in actors:
        ren.AddActor(a)
    if floor:
        ren.AddActor(quad_actor((-4, 0, 4), (4, 0, 4), (-4, 0, -4), (0.85, 0.85, 0.8)))
    if mirror:
        ren.AddActor(quad_actor((-4, 0, -1.5), (4, 0, -1.5), (-4, 3, -1.5), (0.1, 0.1, 0.12), reflectance=0.85))
    light_and_camera(ren, (1, 6, 4), (0.4, 2.6, 5.0), (0, 0.9, 0))
    ren.GetActiveCamera().SetClippingRange(1, 20)  # the same depth mapping for the traced and reference scene
    return ren


def render(ren, traced=True, shadows=False, reflections=False):
    win = vtkRenderWindow()
    win.SetMultiSamples(0)
    win.SetOffScreenRendering(True)
    win.SetSize(*SIZE)
    win.AddRenderer(ren)
    p = None
    if traced:
        p = apply_test_switches(vtkWhittedPass())
        p.SetShadows(shadows)
        p.SetReflections(reflections)
        p.SetRefractions(False)
        ren.SetPass(p)
    win.Render()
    return win, p, grab_with_depth(win)


class TestWhittedPythonRadii(Testing.vtkTest):
    def agree(self, traced_actor, reference, name):
        _, p, (rt_rgb, rt_z) = render(renderer([traced_actor]))
        self.assertEqual(p.GetLastFrameStatistics().GetNumberOfSpheres(), len(SIZES))
        _, _, (gl_rgb, gl_z) = render(renderer(reference), traced=False)
        d = np.abs(gl_rgb - rt_rgb).max(axis=2)
        covered = (gl_z < 1).mean()
        coverage = ((gl_z < 1) != (rt_z < 1)).mean()
        hit = (gl_z < 1) & (rt_z < 1)
        depth_off = (np.abs(gl_z - rt_z)[hit] > 1e-3).mean()
        print("%s: spheres cover %.1f%%, coverage mismatch %.3f%%, depth > 1e-3: %.3f%%, mean |d| %.3f, "
              ">8: %.3f%%" % (name, 100 * covered, 100 * coverage, 100 * depth_off, d.mean(),
                              100 * (d > 8).mean()))
        self.assertGreater(covered, 0.03)
        self.assertLess(coverage, 0.003)    # silhouettes of tessellated spheres: a pixel here and there
        self.assertLess(depth_off, 0.01)
        self.assertLess((d > 8).mean(), 0.005)

    def testPointGaussianRadiiAndColors(self):
        self.agree(gaussian_actor(), reference_actors(FACTOR), "Point Gaussian")

    def testRadiusArrayKeys(self):
        self.agree(radius_key_actor(), reference_actors(1.0, FACTOR), "RADIUS_ARRAY on points as spheres")

    def testTubeRadiusPerSegment(self):
        # A polyline along x at y = 0 seen head-on with a parallel camera: segment k is a tube of radius
        # mean(r_k, r_k+1)
        xs, radii = [-1.4, -0.5, 0.4, 1.3], [0.1, 0.3, 0.5, 0.2]
        points = vtkPoints()
        line = vtkPolyLine()
        for x in xs:
            line.GetPointIds().InsertNextId(points.InsertNextPoint(x, 0, 0))
        lines = vtkCellArray()
        lines.InsertNextCell(line)
        poly = vtkPolyData()
        poly.SetPoints(points)
        poly.SetLines(lines)
        r = vtkDoubleArray()
        r.SetName("r")
        for v in radii:
            r.InsertNextValue(v)
        poly.GetPointData().AddArray(r)
        mapper = vtkPolyDataMapper()
        mapper.SetInputData(poly)
        actor = vtkActor()
        actor.SetMapper(mapper)
        actor.GetProperty().SetRenderLinesAsTubes(True)
        actor.GetProperty().GetInformation().Set(vtkWhittedMaterialKeys.RADIUS_ARRAY(), "r")
        ren = vtkRenderer()
        ren.AddActor(actor)
        cam = ren.GetActiveCamera()
        cam.ParallelProjectionOn()
        cam.SetPosition(0, 0, 10)
        cam.SetFocalPoint(0, 0, 0)
        cam.SetParallelScale(1.1)  # half the view height in world units
        cam.SetClippingRange(5, 15)  # the data's bounds are flat: the tubes stand out of them
        _, _, (_, z) = render(ren)
        h, w = z.shape
        per_unit = h / 2.2
        for k in range(3):
            xm = 0.5 * (xs[k] + xs[k + 1])
            col = int(round(w / 2 + xm * per_unit))
            width = (z[:, col] < 1).sum() / per_unit
            expected = radii[k] + radii[k + 1]
            print("segment %d: width %.3f, expected %.3f" % (k, width, expected))
            self.assertLess(abs(width - expected), 1.5 / per_unit)

    def testShadowsAndBaseline(self):
        ren = renderer([gaussian_actor(), radius_key_actor()], floor=True, mirror=True)
        keyed = ren.GetActors().GetItemAsObject(1)
        keyed.SetScale(1.0)
        keyed.SetPosition(0.3, 0, 1.2)
        ren.GetActiveCamera().SetPosition(0.8, 3.8, 7.5)
        win, p, (lit, _) = render(ren, shadows=True, reflections=True)
        check_baseline(self, win, "TestWhittedPythonRadii.png")
        # Independent: VTK's raster of the floor (the splats, spheres and mirror left out: VTK draws the first two
        # as impostors of other sizes)
        actors = ren.GetActors()
        check_against_raster(self, "PythonRadii", win, p, [actors.GetItemAsObject(i) for i in (0, 1, 3)],
                             min_shadow_share=0.01, min_umbra_share=0.05)
        p.SetShadows(False)
        win.Render()
        unshadowed, _ = grab_with_depth(win)
        darker = (unshadowed - lit).max(axis=2) > 25
        print("shadow pixels: %d" % darker.sum())
        self.assertGreater(darker.sum(), 200)


if __name__ == "__main__":
    Testing.main([(TestWhittedPythonRadii, "test")])
