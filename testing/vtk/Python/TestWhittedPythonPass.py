#!/usr/bin/env python3
"""vtkWhittedPass from Python: settings, Whitted keys (vtkWhittedMaterialKeys, and the same keys through
vtkWhittedPass's older spelling), the last frame's statistics and report, rebuild counts
(camera and light changes rebuild nothing), Start/Progress/End events, hardware picking, transparent misses
(layers, alpha), tiled screenshots, concave polygons."""
from vtkmodules.test import Testing
from vtkmodules.vtkCommonCore import vtkCommand
from vtkmodules.vtkCommonCore import vtkPoints
from vtkmodules.vtkCommonDataModel import vtkCellArray, vtkPolyData
from vtkmodules.vtkFiltersSources import vtkSphereSource
from vtkmodules.util.numpy_support import vtk_to_numpy
from vtkmodules.vtkRenderingCore import (vtkActor, vtkCoordinate, vtkPolyDataMapper, vtkPropPicker,
                                         vtkRenderer, vtkRenderWindow, vtkWindowToImageFilter)
import vtkmodules.vtkRenderingOpenGL2  # noqa: F401
from whitted import vtkWhittedMaterialKeys, vtkWhittedPass
from whitted.scenes import classic_scene, set_whitted


def make_window(w=160, h=120):
    renderer = vtkRenderer()
    window = vtkRenderWindow()
    window.SetMultiSamples(0)
    window.SetOffScreenRendering(True)
    window.SetSize(w, h)
    window.AddRenderer(renderer)
    return renderer, window


class TestWhittedPythonPass(Testing.vtkTest):
    def testSettings(self):
        p = vtkWhittedPass()
        self.assertEqual(p.GetMaxDepth(), 5)
        self.assertEqual(p.GetSamplesPerPixel(), 1)
        self.assertFalse(p.GetAdaptiveSampling())
        self.assertTrue(p.GetShadows() and p.GetReflections() and p.GetRefractions())
        self.assertAlmostEqual(p.GetContributionThreshold(), 1.0 / 255.0)
        self.assertEqual(p.GetNumberOfThreads(), 0)
        self.assertFalse(p.GetFresnel())
        p.SetSamplesPerPixel(0)  # clamped
        self.assertEqual(p.GetSamplesPerPixel(), 1)
        p.ShadowsOff()
        self.assertFalse(p.GetShadows())
        self.assertEqual(p.GetLastFrameReport(), "")

    def testKeys(self):
        actor = vtkActor()
        set_whitted(actor.GetProperty(), reflectance=(0.2, 0.4, 0.6), transmittance=0.5, ior=1.33)
        info = actor.GetProperty().GetInformation()
        self.assertEqual(info.Length(vtkWhittedMaterialKeys.REFLECTANCE()), 3)
        self.assertAlmostEqual(info.Get(vtkWhittedMaterialKeys.REFLECTANCE(), 1), 0.4)
        self.assertAlmostEqual(info.Get(vtkWhittedMaterialKeys.TRANSMITTANCE(), 0), 0.5)
        self.assertAlmostEqual(info.Get(vtkWhittedMaterialKeys.INDEX_OF_REFRACTION()), 1.33)

    def testKeysCompatibility(self):
        """The older spelling vtkWhittedPass.KEY() returns the very same key objects as vtkWhittedMaterialKeys:
        a key set through one is read through the other."""
        names = ("REFLECTANCE", "TRANSMITTANCE", "INDEX_OF_REFRACTION", "ATTENUATION_COLOR", "ATTENUATION_DISTANCE",
                 "RADIUS_ARRAY", "RADIUS_FUNCTION")
        for name in names:
            key, old = getattr(vtkWhittedMaterialKeys, name)(), getattr(vtkWhittedPass, name)()
            self.assertIs(old, key, name)
            self.assertEqual(old.GetAddressAsString("vtkObjectBase"), key.GetAddressAsString("vtkObjectBase"))
            self.assertEqual(key.GetName(), name)
        info = vtkActor().GetProperty().GetInformation()
        info.Set(vtkWhittedPass.REFLECTANCE(), [0.2, 0.4, 0.6], 3)
        info.Set(vtkWhittedPass.INDEX_OF_REFRACTION(), 1.33)
        info.Set(vtkWhittedMaterialKeys.RADIUS_ARRAY(), "r")
        self.assertAlmostEqual(info.Get(vtkWhittedMaterialKeys.REFLECTANCE(), 2), 0.6)
        self.assertAlmostEqual(info.Get(vtkWhittedMaterialKeys.INDEX_OF_REFRACTION()), 1.33)
        self.assertEqual(info.Get(vtkWhittedPass.RADIUS_ARRAY()), "r")

    def testStatisticsAndCaching(self):
        renderer, window = make_window()
        parts = classic_scene(renderer, 16)
        p = vtkWhittedPass()
        renderer.SetPass(p)
        stats = p.GetLastFrameStatistics()  # updated by every frame

        def rebuilt():
            return stats.GetNumberOfGeometriesConverted(), stats.GetNumberOfObjectsRebuilt(), stats.GetTopLevelRebuilt()
        events = []
        for e in (vtkCommand.StartEvent, vtkCommand.ProgressEvent, vtkCommand.EndEvent):
            p.AddObserver(e, lambda o, ev: events.append(ev))

        window.Render()
        self.assertEqual(events[0], "StartEvent")
        self.assertEqual(events[-1], "EndEvent")
        self.assertIn("ProgressEvent", events)
        self.assertEqual(stats.GetPrimaryRays(), 160 * 120)
        self.assertGreater(stats.GetShadowRays(), 0)
        self.assertGreater(stats.GetReflectionRays(), 0)
        self.assertGreater(stats.GetRefractionRays(), 0)
        self.assertGreater(stats.GetRaysSavedByThreshold() + stats.GetRaysSavedByDepth(), 0)
        self.assertGreater(stats.GetNumberOfTriangles(), 280)
        self.assertGreater(stats.GetBVHBytes(), 0)
        self.assertEqual(stats.GetSize(), (160, 120))
        for t in (stats.GetConversionTime(), stats.GetBuildTime(), stats.GetTraceTime(), stats.GetCompositeTime()):
            self.assertGreaterEqual(t, 0.0)
        self.assertGreater(stats.GetTraceTime(), 0.0)
        report = p.GetLastFrameReport()
        for word in ("Whitted frame report", "primary 19200", "conversion", "composite", "BVH"):
            self.assertIn(word, report)
        self.assertEqual(rebuilt(), (3, 3, True))

        # Camera-only and light-only changes rebuild nothing
        renderer.GetActiveCamera().Azimuth(15)
        window.Render()
        self.assertEqual(rebuilt(), (0, 0, False))
        parts["light"].SetPosition(-3, 6, 2)
        window.Render()
        self.assertEqual(rebuilt(), (0, 0, False))
        # Moving an actor rebuilds only the top level
        parts["mirror"].AddPosition(0.2, 0, 0)
        window.Render()
        self.assertEqual(rebuilt(), (0, 0, True))

    def testFastTreeIsUpgradedBetweenFrames(self):
        """Large new geometry is traced with the fast (Morton) tree in the frame that shows it; its SAH tree, built
        in the background after that frame, is swapped in by the first frame after it finished (the next one, or
        the one after WaitForBackgroundBuilds), and the image stays the same (the tree changes only speed)."""
        from whitted_imagetest import grab
        renderer, window = make_window()
        sphere = vtkSphereSource()
        sphere.SetThetaResolution(300)
        sphere.SetPhiResolution(200)
        mapper = vtkPolyDataMapper()
        mapper.SetInputConnection(sphere.GetOutputPort())
        actor = vtkActor()
        actor.SetMapper(mapper)
        renderer.AddActor(actor)
        p = vtkWhittedPass()
        renderer.SetPass(p)
        stats = p.GetLastFrameStatistics()
        window.Render()
        self.assertGreaterEqual(stats.GetNumberOfTriangles(), 50000)
        self.assertEqual((stats.GetNumberOfFastTrees(), stats.GetNumberOfObjectsUpgraded()), (1, 0))
        self.assertIn("1 objects traced with the fast tree", p.GetLastFrameReport())
        self.assertGreater(stats.GetBuildCPUTime(), 0.0)
        first = grab(window, rerender=False)
        window.Render()  # nothing changed; the build is either still running or just finished
        self.assertIn((stats.GetNumberOfFastTrees(), stats.GetNumberOfObjectsUpgraded()), [(1, 0), (0, 1)])
        # the second frame neither waits for the build nor restarts it (only the 4th/16th frame after it may)
        self.assertEqual((stats.GetWaitedForUpgrade(), stats.GetUpgradeRestarted()), (False, False))
        self.assertNotIn("waited for the background build", p.GetLastFrameReport())
        if stats.GetNumberOfFastTrees():
            p.WaitForBackgroundBuilds()
            window.Render()
        self.assertEqual(stats.GetNumberOfObjectsUpgraded(), 1)
        self.assertEqual(stats.GetNumberOfFastTrees(), 0)
        self.assertEqual(stats.GetNumberOfObjectsRebuilt(), 0)
        self.assertIn("1 upgraded to the SAH tree", p.GetLastFrameReport())
        self.assertTrue((grab(window, rerender=False) == first).all())
        window.Render()
        self.assertEqual((stats.GetNumberOfFastTrees(), stats.GetNumberOfObjectsUpgraded()), (0, 0))

    def testPicking(self):
        """Hardware picking (vtkPropPicker -> vtkHardwareSelector) still works: the pass lets OpenGL render the
        selection passes."""
        renderer, window = make_window(160, 120)
        parts = classic_scene(renderer, 16)
        renderer.SetPass(vtkWhittedPass())
        window.Render()
        picker = vtkPropPicker()
        # The mirror sphere's centre on screen
        coordinate = vtkCoordinate()
        coordinate.SetCoordinateSystemToWorld()
        coordinate.SetValue(0.9, 1.1, -3.6)
        x, y = coordinate.GetComputedDisplayValue(renderer)
        self.assertTrue(picker.PickProp(x, y, renderer))
        self.assertIs(picker.GetViewProp(), parts["mirror"])

    def testTransparentMisses(self):
        """Where the tracer misses, the framebuffer keeps what VTK put there: a lower layer shows through a
        pass on layer 1, and with a transparent background (as for parallel compositing) misses have alpha 0
        while hits are opaque."""
        window = vtkRenderWindow()
        window.SetMultiSamples(0)
        window.SetOffScreenRendering(True)
        window.SetAlphaBitPlanes(True)
        window.SetSize(80, 60)
        window.SetNumberOfLayers(2)
        bottom = vtkRenderer()
        bottom.SetBackground(1.0, 0.0, 0.0)
        bottom.SetBackgroundAlpha(0.0)
        window.AddRenderer(bottom)
        top = vtkRenderer()
        top.SetLayer(1)
        top.SetBackground(0.0, 0.0, 1.0)  # a layer-1 renderer does not clear colour: never seen
        sphere = vtkSphereSource()
        mapper = vtkPolyDataMapper()
        mapper.SetInputConnection(sphere.GetOutputPort())
        ball = vtkActor()
        ball.SetMapper(mapper)
        ball.GetProperty().SetColor(0.0, 1.0, 0.0)
        ball.GetProperty().SetAmbient(1.0)
        ball.GetProperty().SetDiffuse(0.0)
        top.AddActor(ball)
        window.AddRenderer(top)
        top.SetPass(vtkWhittedPass())
        window.Render()

        grab = vtkWindowToImageFilter()
        grab.SetInput(window)
        grab.SetInputBufferTypeToRGBA()
        grab.ReadFrontBufferOff()
        grab.ShouldRerenderOff()
        grab.Update()
        pixels = grab.GetOutput().GetPointData().GetScalars()
        corner = pixels.GetTuple4(0)
        centre = pixels.GetTuple4(30 * 80 + 40)
        self.assertEqual(corner, (255.0, 0.0, 0.0, 0.0))  # layer 0's clear: red, transparent
        self.assertEqual(centre, (0.0, 255.0, 0.0, 255.0))  # the traced sphere, opaque

    def testTiledScreenshot(self):
        """A 2x tiled screenshot of a 100x75 view equals a direct 200x150 rendering: rays come from the inverse
        of the camera's composite projection with the tiled aspect ratio."""
        def render(size, scale):
            renderer, window = make_window(*size)
            classic_scene(renderer, 16)
            renderer.SetPass(vtkWhittedPass())
            window.Render()
            grab = vtkWindowToImageFilter()
            grab.SetInput(window)
            grab.SetScale(scale)
            grab.ReadFrontBufferOff()
            grab.Update()
            return vtk_to_numpy(grab.GetOutput().GetPointData().GetScalars()).astype(int)

        tiled = render((100, 75), 2)
        direct = render((200, 150), 1)
        self.assertEqual(tiled.shape, direct.shape)
        differ = (abs(tiled - direct).max(axis=1) > 2).mean()
        print("tiled vs direct: %.3f%% of pixels differ" % (100 * differ))
        self.assertLess(differ, 0.002)

    def testConcavePolygon(self):
        """An L-shaped polygon listed from a vertex that does not see the whole outline: a fan from it (what
        VTK's OpenGL mapper draws) would fill the notch; the pass triangulates it correctly."""
        points = vtkPoints()
        for x, y in ((2, 1), (1, 1), (1, 2), (0, 2), (0, 0), (2, 0)):
            points.InsertNextPoint(x, y, 0)
        cells = vtkCellArray()
        cells.InsertNextCell(6, range(6))
        poly = vtkPolyData()
        poly.SetPoints(points)
        poly.SetPolys(cells)
        mapper = vtkPolyDataMapper()
        mapper.SetInputData(poly)
        actor = vtkActor()
        actor.SetMapper(mapper)
        actor.GetProperty().LightingOff()
        renderer, window = make_window(100, 100)
        renderer.AddActor(actor)
        camera = renderer.GetActiveCamera()
        camera.ParallelProjectionOn()
        camera.SetPosition(1, 1, 5)
        camera.SetFocalPoint(1, 1, 0)
        camera.SetParallelScale(1.25)
        renderer.ResetCameraClippingRange()
        p = vtkWhittedPass()
        renderer.SetPass(p)
        window.Render()
        self.assertEqual(p.GetLastFrameStatistics().GetNumberOfTriangles(), 4)
        grab = vtkWindowToImageFilter()
        grab.SetInput(window)
        grab.ShouldRerenderOff()
        grab.Update()
        image = grab.GetOutput()
        # World (x, y) -> pixel: 100 px span 2.5 units centred on (1, 1)
        def at(x, y):
            i, j = int(50 + (x - 1) * 40), int(50 + (y - 1) * 40)
            return image.GetScalarComponentAsDouble(i, j, 0, 0)
        self.assertEqual(at(0.5, 0.5), 255.0)  # inside the L
        self.assertEqual(at(1.5, 0.5), 255.0)
        self.assertEqual(at(0.5, 1.5), 255.0)
        self.assertEqual(at(1.25, 1.25), 0.0)  # the notch stays background (a fan would fill it)

    def testSettingsChangeTheFrame(self):
        renderer, window = make_window(80, 60)
        classic_scene(renderer, 12)
        p = vtkWhittedPass()
        renderer.SetPass(p)
        p.SetShadows(False)
        p.SetReflections(False)
        p.SetRefractions(False)
        p.SetMaxDepth(0)
        window.Render()
        stats = p.GetLastFrameStatistics()
        self.assertEqual(stats.GetShadowRays() + stats.GetReflectionRays() + stats.GetRefractionRays(), 0)
        p.SetMaxDepth(5)
        p.SetShadows(True)
        p.SetReflections(True)
        p.SetRefractions(True)
        p.SetSamplesPerPixel(4)
        p.SetNumberOfThreads(1)
        window.Render()
        self.assertEqual(stats.GetPrimaryRays(), 80 * 60 * 4)
        p.SetAdaptiveSampling(True)
        window.Render()
        self.assertLess(stats.GetPrimaryRays(), 80 * 60 * 4)
        self.assertGreater(stats.GetPrimaryRays(), 80 * 60)

    def testKeptTexturesGiveTheNewImage(self):
        """The compositor keeps its textures between frames of one size (updated in place) and makes new ones on a
        size change: each frame of a window that rendered other views and sizes before equals, colour and depth,
        the frame of a new window and pass (new textures) for the same view."""
        from vtkmodules.vtkRenderingCore import vtkCamera
        from whitted_imagetest import grab_with_depth

        def new_view(size, camera):
            """The first frame of a new window and pass (new textures) through a copy of camera."""
            renderer, window = make_window(*size)
            classic_scene(renderer, 12)
            renderer.SetPass(vtkWhittedPass())
            renderer.GetActiveCamera().DeepCopy(camera)
            return grab_with_depth(window)

        renderer, window = make_window(80, 60)
        classic_scene(renderer, 12)
        renderer.SetPass(vtkWhittedPass())
        window.Render()
        camera = renderer.GetActiveCamera()
        start = vtkCamera()
        start.DeepCopy(camera)
        kept, views = [], []

        def keep():
            kept.append(grab_with_depth(window))
            views.append((window.GetSize(), vtkCamera()))
            views[-1][1].DeepCopy(camera)

        keep()
        camera.Azimuth(20)
        keep()
        window.SetSize(64, 48)
        keep()
        window.SetSize(80, 60)
        camera.DeepCopy(start)
        keep()
        for k, (size, view) in enumerate(views):
            color, depth = new_view(size, view)
            self.assertEqual(kept[k][0].shape, color.shape)
            self.assertTrue((kept[k][0] == color).all(), "colour of frame %d" % k)
            self.assertTrue((kept[k][1] == depth).all(), "depth of frame %d" % k)
        self.assertFalse((kept[0][0] == kept[1][0]).all())  # the second frame changed the kept textures
        self.assertLess(kept[1][1].min(), 1.0)  # (grab_with_depth renders a new frame)

    def testInteractiveQuality(self):
        """Interactive frames: 1 sample, at most InteractiveMaxDepth bounces, shadows only with InteractiveShadows,
        at 1/InteractiveImageReduction of the size; the full-quality settings are never changed, so turning
        Interactive off gives the full-quality frame back."""
        renderer, window = make_window(80, 60)
        classic_scene(renderer, 12)
        p = vtkWhittedPass()
        renderer.SetPass(p)
        p.SetSamplesPerPixel(4)
        stats = p.GetLastFrameStatistics()
        window.Render()
        full = (stats.GetSize(), stats.GetPrimaryRays(), stats.GetShadowRays(), stats.GetReflectionRays())
        self.assertEqual(full[:2], ((80, 60), 80 * 60 * 4))
        self.assertGreater(min(full[2:]), 0)

        p.InteractiveOn()
        p.SetInteractiveImageReduction(4)
        p.SetInteractiveMaxDepth(0)
        p.InteractiveShadowsOff()
        window.Render()
        self.assertEqual(stats.GetSize(), (20, 15))
        self.assertEqual(stats.GetPrimaryRays(), 20 * 15)
        self.assertEqual(stats.GetShadowRays() + stats.GetReflectionRays() + stats.GetRefractionRays(), 0)
        self.assertEqual((p.GetSamplesPerPixel(), p.GetMaxDepth(), p.GetShadows()), (4, 5, True))
        p.InteractiveShadowsOn()
        p.SetInteractiveMaxDepth(9)  # capped by MaxDepth
        window.Render()
        self.assertGreater(stats.GetShadowRays() * stats.GetReflectionRays(), 0)

        p.InteractiveOff()
        window.Render()
        self.assertEqual((stats.GetSize(), stats.GetPrimaryRays(), stats.GetShadowRays(), stats.GetReflectionRays()),
                         full)


if __name__ == "__main__":
    Testing.main([(TestWhittedPythonPass, "test")])
