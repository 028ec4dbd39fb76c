#!/usr/bin/env python3
"""A volume whose traced copy does not fit in memory is left to OpenGL with a clear message; the rest of the scene is
traced, nothing crashes, and once memory allows it the next frame traces the volume.

The tracer keeps its own copy of a volume's scalars as float: four times the bytes of an 8-bit grid, where VTK's GPU
mapper uploads the 8-bit values. A 700^3 8-bit grid (343 MB; 1308 MiB as float) is rendered with the process's
address space limited (RLIMIT_AS) to what it uses plus 900 MiB: too little for the float copy, enough for the OpenGL
mapper's 8-bit texture. Checked:
- vtkWhittedPass warns, naming the reason and the size ("not enough memory for the traced copy of its scalars");
- the frame report counts the sphere traced, no volume traced or converted, and one prop drawn by OpenGL;
- the image shows the sphere (traced) and the volume (VTK's OpenGL mapper), against the background;
- with the limit lifted, the next frame traces the volume (1 volume traced, no OpenGL prop).
Not run under AddressSanitizer (its shadow memory needs terabytes of address space): labelled 'large'.
"""
import re
import resource

import numpy as np
from vtkmodules.test import Testing
from vtkmodules.util.numpy_support import numpy_to_vtk
from vtkmodules.vtkCommonCore import vtkOutputWindow, vtkStringOutputWindow
from vtkmodules.vtkCommonDataModel import vtkImageData
from vtkmodules.vtkRenderingCore import vtkRenderer, vtkRenderWindow
import vtkmodules.vtkRenderingOpenGL2  # noqa: F401
from whitted import vtkWhittedPass
from whitted_imagetest import grab, ramp_volume, sphere_actor

N = 700
HEADROOM_MIB = 900
BACKGROUND = (0.32, 0.34, 0.43)  # ParaView's default background


def counts(render_pass):
    text = render_pass.GetLastFrameReport()
    actors = re.search(r"(\d+) actors traced", text)
    m = re.search(r"(\d+) volumes traced \((\d+) converted, (\d+) transfer updates\), (\d+) props drawn by OpenGL",
                  text)
    assert actors and m, text
    return int(actors.group(1)), int(m.group(1)), int(m.group(2)), int(m.group(4))


class TestWhittedPythonVolumeMemory(Testing.vtkTest):
    def test(self):
        # A ramp along x, 0..199 (8-bit), in the unit cube
        scalars = np.empty((N, N, N), dtype=np.uint8)
        scalars[:] = (np.arange(N) * (200.0 / N)).astype(np.uint8)[None, None, :]
        image = vtkImageData()
        image.SetDimensions(N, N, N)
        image.SetSpacing(1.0 / (N - 1), 1.0 / (N - 1), 1.0 / (N - 1))
        image.GetPointData().SetScalars(numpy_to_vtk(scalars.ravel(), deep=0))
        volume = ramp_volume(image, 0.5)
        actor = sphere_actor((1.6, 0.5, 0.5), 0.3)
        ren = vtkRenderer()
        ren.AddActor(actor)
        ren.SetBackground(*BACKGROUND)
        win = vtkRenderWindow()
        win.SetOffScreenRendering(1)
        win.SetMultiSamples(0)
        win.AddRenderer(ren)
        win.SetSize(240, 160)
        p = vtkWhittedPass()
        p.SetShadows(False)
        ren.SetPass(p)
        ren.AddVolume(volume)
        ren.ResetCamera()
        ren.RemoveVolume(volume)
        win.Render()  # OpenGL and the tracer set up, without the volume
        ren.AddVolume(volume)

        log = vtkStringOutputWindow()
        previous = vtkOutputWindow.GetInstance()
        vtkOutputWindow.SetInstance(log)
        soft, hard = resource.getrlimit(resource.RLIMIT_AS)
        with open("/proc/self/statm") as f:
            used = int(f.read().split()[0]) * resource.getpagesize()
        resource.setrlimit(resource.RLIMIT_AS, (used + HEADROOM_MIB * 2**20, hard))
        try:
            win.Render()
            frame = counts(p)
            rgb = grab(win, rerender=False)
        finally:
            resource.setrlimit(resource.RLIMIT_AS, (soft, hard))
            vtkOutputWindow.SetInstance(previous)
        text = log.GetOutput()
        print("limited: %d actors traced, %d volumes traced (%d converted), %d OpenGL props" % frame)
        print(text.strip()[:400])
        self.assertIn("not enough memory for the traced copy of its scalars (1308 MiB as float)", text)
        self.assertEqual(frame, (1, 0, 0, 1))  # the failed conversion is not counted
        # The sphere (traced) and the volume (OpenGL) are both in the image
        background = np.array(BACKGROUND) * 255.0
        drawn = np.abs(rgb - background).max(axis=2) > 8
        h, w = drawn.shape
        left, right = drawn[:, : w // 2].sum(), drawn[:, w // 2:].sum()
        print("pixels off the background: left (volume) %d, right (sphere) %d" % (left, right))
        self.assertGreater(left, 1000)
        self.assertGreater(right, 800)

        # Memory back: the next frame traces the volume
        win.Render()
        frame = counts(p)
        print("unlimited: %d actors traced, %d volumes traced (%d converted), %d OpenGL props" % frame)
        self.assertEqual(frame, (1, 1, 1, 0))
        ren.SetPass(None)
        win.Finalize()


if __name__ == "__main__":
    Testing.main([(TestWhittedPythonVolumeMemory, "test")])
