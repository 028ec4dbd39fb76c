#!/usr/bin/env python3
"""The classic Whitted scene from Python (whitted.scenes.classic_scene, i.e. the wrapped vtkWhittedClassicScene)
through vtkWhittedPass: must match the C++ test's baseline (TestWhittedClassic.png), so the scene and the pass
behave through the Python wrapping as in C++."""
from vtkmodules.test import Testing
from vtkmodules.vtkRenderingCore import vtkRenderer, vtkRenderWindow
import vtkmodules.vtkRenderingOpenGL2  # noqa: F401
from whitted import vtkWhittedPass
from whitted.scenes import classic_scene
from whitted_imagetest import apply_test_switches, check_against_raster, check_baseline


class TestWhittedPythonClassic(Testing.vtkTest):
    def testClassic(self):
        renderer = vtkRenderer()
        window = vtkRenderWindow()
        window.SetMultiSamples(0)
        window.SetOffScreenRendering(True)
        window.SetSize(320, 240)
        window.AddRenderer(renderer)
        actors = classic_scene(renderer, 48)
        whitted_pass = apply_test_switches(vtkWhittedPass())
        renderer.SetPass(whitted_pass)
        window.Render()
        print(whitted_pass.GetLastFrameReport())
        stats = whitted_pass.GetLastFrameStatistics()
        self.assertEqual(stats.GetNumberOfTracedActors(), 3)
        self.assertGreater(stats.GetReflectionRays(), 0)
        self.assertGreater(stats.GetRefractionRays(), 0)
        self.assertGreater(stats.GetShadowRays(), 0)
        # The baseline, and independent of it VTK's raster of the floor (the spheres left out; the mirror sphere's
        # shadow is an umbra): both run (the negative control requires both to fail), the first failure is raised
        failures = []
        for check in (lambda: check_baseline(self, window, "TestWhittedClassic.png"),
                      lambda: check_against_raster(self, "Classic", window, whitted_pass,
                                                   [actors["mirror"], actors["glass"]], min_shadow_share=0.03,
                                                   min_umbra_share=0.1)):
            try:
                check()
            except AssertionError as e:
                print("[check failed] %s" % e, flush=True)
                failures.append(e)
        if failures:
            raise failures[0]


if __name__ == "__main__":
    Testing.main([(TestWhittedPythonClassic, "test")])
