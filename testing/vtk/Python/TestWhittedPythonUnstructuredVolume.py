#!/usr/bin/env python3
"""Unstructured grids volume-rendered by an unstructured-grid mapper are traced after resampling to image data.

A ball of tetrahedra cut from a wavelet (vtkClipDataSet by a sphere, then vtkDataSetTriangleFilter) drawn by a
vtkProjectedTetrahedraMapper, opacity 0 below 100 and rising to 0.3 at the top of the range. Checks:
- the pass traces it: the frame report counts 1 volume traced and no prop left to OpenGL (vtkWhittedPass warns
  once that it was resampled);
- independent references, MAE within 3/255 over the pixels either image covers: VTK's own image (the projected
  tetrahedra without the pass; measured 2.26/255, the resampling's smoothing), and vtkGPUVolumeRayCastMapper drawing
  the same grid resampled by vtkResampleToImage at the same 128^3 (2.51/255: the resampler's hidden points outside
  the ball have scalar 0 there, a shell the transfer function shows where the traced grid is transparent);
- a mirror floor under it shows it (pixels outside its direct footprint change when it is shown);
- a second frame converts nothing (the resampled grid is kept), a modified input is converted again, and so is
  another selected array (the image changes).
"""
import re

import numpy as np
from vtkmodules.test import Testing
from vtkmodules.vtkCommonDataModel import vtkPiecewiseFunction, vtkSphere
from vtkmodules.vtkFiltersCore import vtkArrayCalculator, vtkResampleToImage
from vtkmodules.vtkFiltersGeneral import vtkClipDataSet, vtkDataSetTriangleFilter
from vtkmodules.vtkImagingCore import vtkRTAnalyticSource
from vtkmodules.vtkRenderingCore import vtkColorTransferFunction, vtkRenderer, vtkRenderWindow, vtkVolume, vtkVolumeProperty
import vtkmodules.vtkRenderingOpenGL2  # noqa: F401
import vtkmodules.vtkRenderingVolumeOpenGL2  # noqa: F401
from vtkmodules.vtkRenderingVolume import vtkGPUVolumeRayCastMapper, vtkProjectedTetrahedraMapper
from whitted import vtkWhittedPass
from whitted_imagetest import grab, offscreen_render, quad_actor

SIZE = 200
BACKGROUND = (0.32, 0.34, 0.43)


def ball():
    src = vtkRTAnalyticSource()
    src.SetWholeExtent(-10, 10, -10, 10, -10, 10)
    sphere = vtkSphere()
    sphere.SetRadius(9.0)
    clip = vtkClipDataSet()
    clip.SetInputConnection(src.GetOutputPort())
    clip.SetClipFunction(sphere)
    clip.InsideOutOn()
    tets = vtkDataSetTriangleFilter()
    tets.SetInputConnection(clip.GetOutputPort())
    # A second point array, for switching the selected scalars: 314 - RTData (the range flipped)
    other = vtkArrayCalculator()
    other.SetInputConnection(tets.GetOutputPort())
    other.AddScalarArrayName("RTData")
    other.SetFunction("314 - RTData")
    other.SetResultArrayName("other")
    other.Update()
    return other


def volume_property():
    color = vtkColorTransferFunction()
    color.AddRGBPoint(37.0, 0.23, 0.30, 0.75)
    color.AddRGBPoint(157.0, 0.87, 0.87, 0.87)
    color.AddRGBPoint(277.0, 0.71, 0.02, 0.15)
    opacity = vtkPiecewiseFunction()
    opacity.AddPoint(0.0, 0.0)
    opacity.AddPoint(100.0, 0.0)
    opacity.AddPoint(277.0, 0.3)
    prop = vtkVolumeProperty()
    prop.SetColor(color)
    prop.SetScalarOpacity(opacity)
    prop.SetScalarOpacityUnitDistance(1.0)
    prop.SetInterpolationTypeToLinear()
    return prop


def renderer(mapper, floor=False):
    ren = vtkRenderer()
    ren.SetBackground(*BACKGROUND)
    volume = vtkVolume()
    volume.SetMapper(mapper)
    volume.SetProperty(volume_property())
    ren.AddVolume(volume)
    if floor:  # a black mirror
        actor = quad_actor((-40.0, -12.0, 40.0), (40.0, -12.0, 40.0), (-40.0, -12.0, -40.0), (0.0, 0.0, 0.0), 1.0)
        actor.GetProperty().SetAmbient(0.0)
        actor.GetProperty().SetDiffuse(0.0)
        ren.AddActor(actor)
    cam = ren.GetActiveCamera()
    cam.SetPosition(0.0, 14.0, 60.0)
    cam.SetFocalPoint(0.0, -4.0, 0.0)
    cam.SetViewUp(0.0, 1.0, 0.0)
    ren.ResetCameraClippingRange()
    return ren, volume


class TestWhittedPythonUnstructuredVolume(Testing.vtkTest):
    def test(self):
        grid = ball()
        tetra = vtkProjectedTetrahedraMapper()
        tetra.SetInputConnection(grid.GetOutputPort())
        tetra.SetScalarModeToUsePointFieldData()
        tetra.SelectScalarArray("RTData")
        ren, volume = renderer(tetra)
        p = vtkWhittedPass()
        p.SetSamplesPerPixel(1)
        p.SetShadows(False)

        def report(rp):
            text = rp.GetLastFrameReport()
            m = re.search(r"(\d+) volumes traced \((\d+) converted, (\d+) transfer updates\), (\d+) props drawn by "
                          r"OpenGL", text)
            self.assertIsNotNone(m, text)
            return tuple(int(g) for g in m.groups())

        traced, frame = offscreen_render(ren, SIZE, p, report)
        print("unstructured: %d traced, %d converted, %d transfer updates, %d OpenGL props" % frame)
        self.assertEqual(frame[0], 1)
        self.assertEqual(frame[3], 0)

        # References: VTK's own image of the grid (the projected tetrahedra without the pass), and VTK's GPU mapper
        # on the same grid resampled at the same resolution
        background = np.array(BACKGROUND) * 255.0
        own, _ = offscreen_render(renderer(tetra)[0], SIZE)
        covered = (np.abs(traced - background).max(axis=2) > 1) | (np.abs(own - background).max(axis=2) > 1)
        mae = float(np.abs(traced - own)[covered].mean())
        print("against vtkProjectedTetrahedraMapper: MAE %.3f/255 over %d covered pixels" % (mae, int(covered.sum())))
        self.assertGreater(covered.sum(), 3000)
        self.assertLessEqual(mae, 3.0)
        resample = vtkResampleToImage()
        resample.SetInputConnection(grid.GetOutputPort())
        resample.UseInputBoundsOn()
        resample.SetSamplingDimensions(128, 128, 128)
        gpu = vtkGPUVolumeRayCastMapper()
        gpu.SetInputConnection(resample.GetOutputPort())
        gpu.SetAutoAdjustSampleDistances(0)
        gpu.SetLockSampleDistanceToInputSpacing(1)
        gpu.SelectScalarArray("RTData")
        gpu.SetScalarModeToUsePointFieldData()
        ref_ren, _ = renderer(gpu)
        raster, _ = offscreen_render(ref_ren, SIZE)
        covered = (np.abs(traced - background).max(axis=2) > 1) | (np.abs(raster - background).max(axis=2) > 1)
        mae = float(np.abs(traced - raster)[covered].mean())
        print("against vtkGPUVolumeRayCastMapper of the resampled grid: MAE %.3f/255 over %d covered pixels" % (
            mae, int(covered.sum())))
        self.assertGreater(covered.sum(), 3000)
        self.assertLessEqual(mae, 3.0)

        # Seen in a mirror floor: pixels outside the direct footprint change when it is shown
        ren2, volume2 = renderer(tetra, floor=True)
        p2 = vtkWhittedPass()
        p2.SetSamplesPerPixel(1)
        p2.SetShadows(False)
        with_volume, _ = offscreen_render(ren2, SIZE, p2)
        volume2.VisibilityOff()
        without, _ = offscreen_render(ren2, SIZE, p2)
        footprint = np.abs(traced - background).max(axis=2) > 3
        for _ in range(3):  # dilated by 3 pixels
            footprint = footprint | np.roll(footprint, 1, 0) | np.roll(footprint, -1, 0) | \
                np.roll(footprint, 1, 1) | np.roll(footprint, -1, 1)
        reflection = int(((np.abs(with_volume - without).max(axis=2) > 8) & ~footprint).sum())
        print("mirror: %d pixels outside the footprint change when the volume is shown" % reflection)
        self.assertGreater(reflection, 500)

        # A second frame of the same window and pass converts nothing (the resampled grid is kept); a changed
        # input is resampled and converted again
        win = vtkRenderWindow()
        win.SetOffScreenRendering(1)
        win.SetSize(SIZE, SIZE)
        ren3, _ = renderer(tetra)
        win.AddRenderer(ren3)
        p3 = vtkWhittedPass()
        ren3.SetPass(p3)
        win.Render()
        first = report(p3)
        win.Render()
        second = report(p3)
        grid.Modified()
        win.Render()
        third = report(p3)
        print("frames of one pass: converted %d, %d, then %d after the input changed" % (first[1], second[1], third[1]))
        self.assertEqual((first[1], second[1], third[1]), (1, 0, 1))
        # Selecting another array resamples that one: a new grid, another image
        before = grab(win)
        tetra.SelectScalarArray("other")
        win.Render()
        fourth = report(p3)
        after = grab(win)
        changed = int((np.abs(after - before).max(axis=2) > 8).sum())
        print("another array selected: converted %d, %d pixels change" % (fourth[1], changed))
        self.assertEqual(fourth[1], 1)
        self.assertGreater(changed, 1000)
        tetra.SelectScalarArray("RTData")
        ren3.SetPass(None)
        win.Finalize()


if __name__ == "__main__":
    Testing.main([(TestWhittedPythonUnstructuredVolume, "test")])
