#!/usr/bin/env python3
"""A volume of more than 2^31 points (1300^3 8-bit scalars, 2.2 GB; 8.8 GB as the tracer's float copy) is traced
whole, with a surface beside it, on a 24 GB machine.

The field depends on z alone (a ramp, brightest at the top), so a grid of 2 x 2 x 1300 points over the same box holds
the same field: trilinear interpolation of equal values is exact, and the z positions and the step are the same. That
small grid's image is the reference; its indices are small, so it does not share an index overflow with the large
grid (points beyond index 2^31 are the top 2% of the slices: an overflow would read other slices there, or crash).
Both are traced in one pass (camera looking along x, parallel projection, shadows off); checked: both frames trace
the volume and the sphere, and the images agree within 1/255 everywhere (the sample points' rounding differs).
Peak memory about 11 GB: labelled 'large' (not run under the sanitizers); skipped (exit code 77, ctest's
SKIP_RETURN_CODE) when the machine has less than 13 GiB available, rather than risk the out-of-memory killer.
"""
import re
import sys
import time

import numpy as np
from vtkmodules.test import Testing
from vtkmodules.util.numpy_support import numpy_to_vtk
from vtkmodules.vtkCommonDataModel import vtkImageData
from vtkmodules.vtkRenderingCore import vtkRenderer, vtkRenderWindow
import vtkmodules.vtkRenderingOpenGL2  # noqa: F401
from whitted import vtkWhittedPass
from whitted_imagetest import grab, ramp_volume, sphere_actor

N = 1300
BACKGROUND = (0.32, 0.34, 0.43)  # ParaView's default background


def grid(nx, ny, nz):
    """nx x ny x nz points over the unit cube, 8-bit scalars 0..200 rising with z."""
    ramp = np.round(np.arange(nz) * (200.0 / (nz - 1))).astype(np.uint8)
    scalars = np.empty((nz, ny, nx), dtype=np.uint8)
    scalars[:] = ramp[:, None, None]
    image = vtkImageData()
    image.SetDimensions(nx, ny, nz)
    image.SetSpacing(1.0 / (nx - 1), 1.0 / (ny - 1), 1.0 / (nz - 1))
    image.GetPointData().SetScalars(numpy_to_vtk(scalars.ravel(), deep=0))
    return image, scalars


def render(image):
    volume = ramp_volume(image, 0.8, sample_distance=1.0 / 256.0, unit_distance=0.5)
    actor = sphere_actor((0.5, 1.5, 0.5), 0.3)
    ren = vtkRenderer()
    ren.AddVolume(volume)
    ren.AddActor(actor)
    ren.SetBackground(*BACKGROUND)
    cam = ren.GetActiveCamera()
    cam.ParallelProjectionOn()
    cam.SetFocalPoint(0.5, 0.9, 0.5)
    cam.SetPosition(5.0, 0.9, 0.5)
    cam.SetViewUp(0.0, 0.0, 1.0)
    cam.SetParallelScale(0.6)
    ren.ResetCameraClippingRange()
    win = vtkRenderWindow()
    win.SetOffScreenRendering(1)
    win.SetMultiSamples(0)
    win.AddRenderer(ren)
    win.SetSize(240, 160)
    p = vtkWhittedPass()
    p.SetShadows(False)
    ren.SetPass(p)
    start = time.time()
    win.Render()
    seconds = time.time() - start
    rgb = grab(win, rerender=False)
    text = p.GetLastFrameReport()
    ren.SetPass(None)
    win.Finalize()
    m = re.search(r"(\d+) actors traced .*?(\d+) volumes traced \((\d+) converted.*?(\d+) props drawn by OpenGL", text)
    assert m, text
    return rgb, tuple(int(g) for g in m.groups()), seconds


class TestWhittedPythonHugeVolume(Testing.vtkTest):
    def test(self):
        image, scalars = grid(N, N, N)
        self.assertGreater(scalars.size, 2**31)
        huge, frame, seconds = render(image)
        print("%d^3 = %d points: %d actors traced, %d volumes traced (%d converted), %d OpenGL props; first frame "
              "%.1f s" % ((N, scalars.size) + frame + (seconds,)))
        del image, scalars
        small, small_frame, _ = render(grid(2, 2, N)[0])
        self.assertEqual(frame, (1, 1, 1, 0))
        self.assertEqual(small_frame, (1, 1, 1, 0))
        diff = np.abs(huge - small).max(axis=2)
        background = np.array(BACKGROUND) * 255.0
        covered = np.abs(small - background).max(axis=2) > 1
        # Rows bottom to top: the top rows show the slices beyond index 2^31
        top = covered[-int(0.2 * covered.shape[0]):].sum()
        print("max difference %.1f/255, MAE %.4f over %d covered pixels (%d in the top fifth)"
              % (diff.max(), float(diff[covered].mean()), int(covered.sum()), int(top)))
        self.assertGreater(covered.sum(), 8000)
        self.assertGreater(top, 1000)
        self.assertLessEqual(diff.max(), 1.0)


def available_gib():
    with open("/proc/meminfo") as f:
        for line in f:
            if line.startswith("MemAvailable:"):
                return int(line.split()[1]) / 2.0**20
    return 0.0


if __name__ == "__main__":
    if available_gib() < 13.0:
        print("SKIPPED: %.1f GiB available, the test needs 13" % available_gib())
        sys.exit(77)
    Testing.main([(TestWhittedPythonHugeVolume, "test")])
