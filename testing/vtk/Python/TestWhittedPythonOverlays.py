#!/usr/bin/env python3
"""Overlays from Python: a vtkTextActor, a vtkCornerAnnotation and an orientation-axes widget stay on top of the
traced classic scene; a plain OpenGL wireframe actor is depth-composited with it."""
from vtkmodules.test import Testing
from vtkmodules.vtkFiltersSources import vtkSphereSource
from vtkmodules.vtkInteractionWidgets import vtkOrientationMarkerWidget
from vtkmodules.vtkRenderingAnnotation import vtkAxesActor, vtkCornerAnnotation
from vtkmodules.vtkRenderingCore import (vtkActor, vtkPolyDataMapper, vtkRenderer, vtkRenderWindow,
                                         vtkRenderWindowInteractor, vtkTextActor)
import vtkmodules.vtkInteractionStyle  # noqa: F401
import vtkmodules.vtkRenderingFreeType  # noqa: F401
import vtkmodules.vtkRenderingOpenGL2  # noqa: F401
from whitted import vtkWhittedPass
from whitted.scenes import classic_scene
from whitted_imagetest import apply_test_switches, check_against_raster, check_baseline


class TestWhittedPythonOverlays(Testing.vtkTest):
    def testOverlays(self):
        renderer = vtkRenderer()
        window = vtkRenderWindow()
        window.SetMultiSamples(0)
        window.SetOffScreenRendering(True)
        window.SetSize(280, 210)
        window.AddRenderer(renderer)
        interactor = vtkRenderWindowInteractor()
        interactor.SetRenderWindow(window)
        actors = classic_scene(renderer, 24)

        text = vtkTextActor()
        text.SetInput("vtkWhittedPass")
        text.GetTextProperty().SetFontSize(22)
        text.GetTextProperty().SetColor(1, 1, 1)
        text.SetDisplayPosition(8, 180)
        renderer.AddActor2D(text)
        corner = vtkCornerAnnotation()
        corner.SetText(3, "ray traced")
        corner.GetTextProperty().SetColor(0.1, 0.1, 0.1)
        renderer.AddViewProp(corner)

        # Wireframe cage around the glass sphere: drawn by OpenGL, hidden by the traced spheres where behind
        cage_source = vtkSphereSource()
        cage_source.SetCenter(-0.7, 0.8, -1.4)
        cage_source.SetRadius(1.0)
        cage_source.SetThetaResolution(10)
        cage_source.SetPhiResolution(6)
        cage_mapper = vtkPolyDataMapper()
        cage_mapper.SetInputConnection(cage_source.GetOutputPort())
        cage = vtkActor()
        cage.SetMapper(cage_mapper)
        cage.GetProperty().SetRepresentationToWireframe()
        cage.GetProperty().SetColor(0.1, 1.0, 0.3)
        renderer.AddActor(cage)

        axes = vtkAxesActor()
        widget = vtkOrientationMarkerWidget()
        widget.SetOrientationMarker(axes)
        widget.SetInteractor(interactor)
        widget.SetViewport(0.75, 0.0, 1.0, 0.3)
        widget.SetEnabled(1)
        widget.InteractiveOff()

        whitted_pass = apply_test_switches(vtkWhittedPass())
        renderer.SetPass(whitted_pass)
        window.Render()
        stats = whitted_pass.GetLastFrameStatistics()
        self.assertEqual(stats.GetNumberOfTracedActors(), 3)
        self.assertEqual(stats.GetNumberOfOpenGLProps(), 3)
        check_baseline(self, window, "TestWhittedPythonOverlays.png")
        # Independent: VTK's raster of the same scene without the spheres (text, annotation, cage and axes are
        # OpenGL in both); the mirror sphere's shadow is an umbra
        check_against_raster(self, "PythonOverlays", window, whitted_pass, [actors["mirror"], actors["glass"]],
                             min_shadow_share=0.02, min_umbra_share=0.05)


if __name__ == "__main__":
    Testing.main([(TestWhittedPythonOverlays, "test")])
