#!/usr/bin/env python3
"""Surface With Edges, BackfaceProperty and PBR interpolation through vtkWhittedPass.

- Edges agree with VTK's own OpenGL image of the same actors (a sphere of triangles, a plane of quads whose
  triangulation diagonals VTK does not draw) at line widths 1 and 3: nearly every edge pixel of one image is
  within a pixel of an edge pixel of the other (at least 90% and 95%: VTK's own lines z-fight with the surface in
  places; no diagonals, no missing edges), and the traced
  edges have the width VTK draws (edge pixel counts within 25%; 3 px edges about 3x the 1 px ones).
- Regression image (TestWhittedPythonEdges.png): edged sphere and floor with shadows, seen directly and in a
  mirror, with a translucent edged cube (edges keep their pixel width in the mirror), a PBR copper sphere (a
  coloured mirror) and a bowl whose inside shows its BackfaceProperty.
- BackfaceProperty: an open hemisphere whose inside is green agrees with VTK's image of it; so do the same bowl
  with BackfaceCulling and with FrontfaceCulling in front of a plane (culled faces pass rays).
- PBR: a metallic, smooth quad in front of an unlit white wall shows its base colour as a mirror, exactly as
  REFLECTANCE = base colour does; a rough one has no reflection; the approximation is warned about once.
"""
import numpy as np
from vtkmodules.test import Testing
from vtkmodules.vtkCommonCore import vtkCommand, VTK_STRING
from vtkmodules.vtkCommonDataModel import vtkPlane
from vtkmodules.vtkFiltersCore import vtkClipPolyData
from vtkmodules.vtkFiltersSources import vtkCubeSource, vtkPlaneSource, vtkSphereSource
from vtkmodules.vtkRenderingCore import (vtkActor, vtkLight, vtkPolyDataMapper, vtkProperty, vtkRenderer,
                                         vtkRenderWindow)
import vtkmodules.vtkRenderingOpenGL2  # noqa: F401
from vtkmodules.util.misc import calldata_type
from whitted import vtkWhittedMaterialKeys, vtkWhittedPass
from whitted_imagetest import (apply_test_switches, check_against_raster, check_baseline, edge_mask, grab, near,
                               offscreen_render, plain_pass)

SIZE = 200


def actor_of(source, color=(0.2, 0.3, 1.0)):
    mapper = vtkPolyDataMapper()
    mapper.SetInputConnection(source.GetOutputPort())
    a = vtkActor()
    a.SetMapper(mapper)
    a.GetProperty().SetColor(*color)
    return a


def edged(a, width, color=(1, 0, 0)):
    p = a.GetProperty()
    p.EdgeVisibilityOn()
    p.SetEdgeColor(*color)
    p.SetLineWidth(width)
    return a


def sphere_source(center, radius, theta, phi):
    sphere = vtkSphereSource()
    sphere.SetThetaResolution(theta)
    sphere.SetPhiResolution(phi)
    sphere.SetCenter(*center)
    sphere.SetRadius(radius)
    return sphere


def plane_source(origin, point1, point2, resolution=1):
    plane = vtkPlaneSource()
    plane.SetOrigin(*origin)
    plane.SetPoint1(*point1)
    plane.SetPoint2(*point2)
    plane.SetResolution(resolution, resolution)
    return plane


def bowl(center, radius, normal, inside):
    """A sphere cut open by the plane through its centre with the given normal; inside: the back faces' colour
    (BackfaceProperty, with a highlight)."""
    plane = vtkPlane()
    plane.SetOrigin(*center)
    plane.SetNormal(*normal)
    sphere = sphere_source(center, radius, 48, 24)
    clip = vtkClipPolyData()
    clip.SetInputConnection(sphere.GetOutputPort())
    clip.SetClipFunction(plane)
    a = actor_of(clip, (1.0, 0.4, 0.2))
    a.pipeline = (sphere, clip, plane)  # an output port does not keep its producer alive
    back = vtkProperty()
    back.SetColor(*inside)
    back.SetSpecular(0.5)
    back.SetSpecularPower(20)
    a.SetBackfaceProperty(back)
    return a


def window(ren, width, height, render_pass):
    win = vtkRenderWindow()
    win.SetOffScreenRendering(1)
    win.SetMultiSamples(0)
    win.SetSize(width, height)
    win.AddRenderer(ren)
    ren.SetPass(render_pass)
    return win


def edge_scene(width):
    ren = vtkRenderer()
    ren.AddActor(edged(actor_of(sphere_source((-0.6, 0, 0), 0.5, 16, 10)), width))
    ren.AddActor(edged(actor_of(plane_source((0.2, -0.5, 0), (1.2, -0.5, 0.3), (0.2, 0.5, 0), 4)), width))
    camera = ren.GetActiveCamera()
    camera.SetPosition(0.1, 0.4, 4)
    camera.SetFocalPoint(0.1, 0, 0)
    ren.ResetCameraClippingRange()
    return ren


def render_both(ren):
    gl, _ = offscreen_render(ren, SIZE)
    rt, _ = offscreen_render(ren, SIZE, plain_pass())
    return gl, rt


class TestWhittedPythonEdges(Testing.vtkTest):
    def testEdgesAgreeWithVTK(self):
        counts = {}
        for width in (1, 3):
            gl, rt = render_both(edge_scene(width))
            g, r = edge_mask(gl), edge_mask(rt)
            recall, precision = near(g, r), near(r, g)
            counts[width] = r.sum()
            print("width %d: VTK %d edge pixels, traced %d; VTK's near traced %.3f, traced near VTK's %.3f"
                  % (width, g.sum(), r.sum(), recall, precision))
            self.assertGreater(g.sum(), 200)  # the scene shows edges at all
            self.assertGreater(recall, 0.9)
            self.assertGreater(precision, 0.95)  # VTK's own edge lines z-fight with their surface in places
            self.assertLess(abs(r.sum() / g.sum() - 1.0), 0.25)
            # Away from edges (in both images; also VTK's pixels where an edge line blends with the surface, red
            # above the surfaces' 0.2) the surfaces agree as without edges
            reddish = (gl[:, :, 0] > 90) | (rt[:, :, 0] > 90)
            grown_g = ~np.logical_or.reduce([np.roll(np.roll(reddish, dy, 0), dx, 1)
                                             for dy in (-2, 0, 2) for dx in (-2, 0, 2)])
            d = np.abs(gl - rt).max(axis=2)[grown_g]
            self.assertLess((d > 3).mean(), 0.01)
        self.assertGreater(counts[3], 2.2 * counts[1])

    def testEdgesInMirror(self):
        ren = vtkRenderer()
        sphere = sphere_source((-0.5, 0, 0.5), 0.5, 12, 8)
        ren.AddActor(edged(actor_of(sphere, (0.9, 0.9, 0.3)), 2, (0.1, 0.1, 0.6)))
        cube = vtkCubeSource()
        cube.SetCenter(0.7, 0.2, 0.4)
        cube.SetXLength(0.6)
        cube.SetYLength(0.6)
        cube.SetZLength(0.8)
        glassy = edged(actor_of(cube, (0.3, 0.9, 0.5)), 3, (1, 1, 1))
        glassy.GetProperty().SetOpacity(0.4)
        ren.AddActor(glassy)
        floor = plane_source((-2, -2, 0), (2, -2, 0), (-2, 2, 0), 6)
        ren.AddActor(edged(actor_of(floor, (0.8, 0.8, 0.8)), 1, (0.6, 0, 0)))
        m = actor_of(plane_source((-2, 1.5, 0), (2, 1.5, 0), (-2, 1.5, 2)), (0.1, 0.1, 0.1))
        m.GetProperty().GetInformation().Set(vtkWhittedMaterialKeys.REFLECTANCE(), [0.85], 1)
        ren.AddActor(m)
        # A PBR copper sphere (smooth metal: a coloured mirror) and a bowl whose inside has its own colour
        copper = actor_of(sphere_source((-1.25, -0.35, 0.35), 0.35, 32, 16), (0.95, 0.64, 0.54))
        copper.GetProperty().SetInterpolationToPBR()
        copper.GetProperty().SetMetallic(1.0)
        copper.GetProperty().SetRoughness(0.1)
        ren.AddActor(copper)
        ren.AddActor(bowl((1.45, -0.3, 0.4), 0.4, (0.2, 1, -0.5), (0.1, 0.8, 0.3)))
        ren.SetBackground(0.32, 0.34, 0.43)
        # A headlight, and a light between the objects and the mirror: the mirror shows their lit backs
        head = vtkLight()
        head.SetLightTypeToHeadlight()
        head.SetIntensity(0.6)
        ren.AddLight(head)
        back = vtkLight()
        back.SetLightTypeToSceneLight()
        back.SetPosition(0.3, 1.2, 2.5)
        back.SetFocalPoint(0, 0, 0)
        back.SetIntensity(0.7)
        ren.AddLight(back)
        camera = ren.GetActiveCamera()
        camera.SetPosition(0.5, -4.5, 2.6)
        camera.SetFocalPoint(0, 0.3, 0.4)
        camera.SetViewUp(0, 0, 1)
        ren.ResetCameraClippingRange()
        whitted_pass = apply_test_switches(vtkWhittedPass())
        win = window(ren, 300, 225, whitted_pass)
        win.Render()
        check_baseline(self, win, "TestWhittedPythonEdges.png")
        # Independent: VTK's raster of the same scene without the translucent cube, the mirror and the copper
        # sphere, away from the edges (VTK's edge lines z-fight with their surface and sit a pixel off the traced
        # ones: testEdgesAgreeWithVTK checks them): pixels where VTK's image changes with the edges off, grown by 2
        ren.SetPass(None)
        win.Render()
        with_edges = grab(win)
        edged_props = [ren.GetActors().GetItemAsObject(i) for i in range(ren.GetActors().GetNumberOfItems())]
        edged_props = [a for a in edged_props if a.GetProperty().GetEdgeVisibility()]
        for a in edged_props:
            a.GetProperty().EdgeVisibilityOff()
        win.Render()
        edges = np.abs(grab(win) - with_edges).max(axis=2) > 0
        for a in edged_props:
            a.GetProperty().EdgeVisibilityOn()
        edges = np.logical_or.reduce([np.roll(np.roll(edges, dy, 0), dx, 1) for dy in (-2, 0, 2) for dx in (-2, 0, 2)])
        ren.SetPass(whitted_pass)
        win.Render()
        check_against_raster(self, "PythonEdges", win, whitted_pass, [glassy, m, copper], min_shadow_share=0.01,
                             min_umbra_share=0.02, ignore=edges)

    def bowl_against_vtk(self, name, cull=None):
        """The bowl (green inside) in front of a plane, culling nothing or one face side: VTK's image and the
        traced one; returns the traced image."""
        ren = vtkRenderer()
        a = bowl((0, 0, 0), 0.5, (0.3, -0.2, -1), (0.1, 0.9, 0.2))
        if cull:
            getattr(a.GetProperty(), "%sCullingOn" % cull)()
        ren.AddActor(a)
        ren.AddActor(actor_of(plane_source((-2, -2, -1), (2, -2, -1), (-2, 2, -1)), (0.9, 0.9, 0.9)))
        camera = ren.GetActiveCamera()
        camera.SetPosition(0.4, -0.6, 2.5)
        camera.SetFocalPoint(0, 0, 0)
        ren.ResetCameraClippingRange()
        gl, rt = render_both(ren)
        d = np.abs(gl - rt).max(axis=2)
        print("%s: mean |d| %.4f, >3: %.3f%%" % (name, d.mean(), 100 * (d > 3).mean()))
        self.assertLess((d > 3).mean(), 0.005)
        return rt

    def testBackfaceProperty(self):
        rt = self.bowl_against_vtk("backface")
        green = (rt[:, :, 1] > 1.5 * rt[:, :, 0]) & (rt[:, :, 1] > 60)
        print("backface: green pixels %d" % green.sum())
        self.assertGreater(green.sum(), 2000)  # the inside shows the back colour

    def testFaceCulling(self):
        """Culled faces pass rays: the bowl culling its back faces shows its outside only, the one culling its
        front faces its (back-face coloured) inside only, as in VTK's image; the plane behind shows through."""
        for cull in ("Backface", "Frontface"):
            self.bowl_against_vtk("%s culling" % cull, cull)

    def testPBR(self):
        def scene(material):
            ren = vtkRenderer()
            # normal (1, 0, 1)/sqrt(2): reflects the view ray -z to +x
            quad = plane_source((-0.5, -0.5, 0.5), (0.5, -0.5, -0.5), (-0.5, 0.5, 0.5))
            q = actor_of(quad, (1.0, 0.71, 0.29))
            material(q.GetProperty())
            ren.AddActor(q)
            w = actor_of(plane_source((3, -20, -20), (3, 20, -20), (3, -20, 20)), (1, 1, 1))
            w.GetProperty().LightingOff()
            ren.AddActor(w)
            camera = ren.GetActiveCamera()
            camera.SetPosition(0, 0, 5)
            camera.SetFocalPoint(0, 0, 0)
            ren.ResetCameraClippingRange()
            return ren

        def pbr(metallic, roughness):
            def set_pbr(p):
                p.SetInterpolationToPBR()
                p.SetMetallic(metallic)
                p.SetRoughness(roughness)
            return set_pbr

        warnings = []

        @calldata_type(VTK_STRING)
        def on_warning(obj, event, text):
            warnings.append(text)

        def traced(material, frames=1):
            p = vtkWhittedPass()
            p.AddObserver(vtkCommand.WarningEvent, on_warning)
            ren = scene(material)
            images = []
            win = window(ren, 120, 120, p)
            for _ in range(frames):
                win.Render()
                images.append(grab(win))
            return images[-1]

        gold_pbr = traced(pbr(1.0, 0.0), frames=2)
        pbr_warnings = [w for w in warnings if "PBR" in w]
        print("PBR warnings:", pbr_warnings)
        self.assertEqual(len(pbr_warnings), 1)
        gold_keys = traced(lambda p: p.GetInformation().Set(vtkWhittedMaterialKeys.REFLECTANCE(), [1.0, 0.71, 0.29], 3))
        self.assertEqual(np.abs(gold_pbr - gold_keys).max(), 0)
        centre = gold_pbr[60, 60]
        print("metallic 1, roughness 0: centre pixel", centre)
        self.assertTrue(np.allclose(centre, [255, 181, 74], atol=1.5))
        # Rough: no mirror image of the white wall, the base colour lit instead (as Gouraud)
        rough = traced(pbr(1.0, 1.0))
        gouraud = traced(lambda p: None)
        self.assertEqual(np.abs(rough - gouraud).max(), 0)


if __name__ == "__main__":
    Testing.main([(TestWhittedPythonEdges, "test")])
