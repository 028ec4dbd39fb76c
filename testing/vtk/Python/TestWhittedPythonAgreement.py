#!/usr/bin/env python3
"""Agreement with VTK's OpenGL image from Python: with shadows, reflections and refractions off, the pass must
reproduce VTK's own rendering (colour and depth) of scenes exercising actor transforms (position, orientation,
scale with origin, user matrix with shear, a mirroring user transform, an assembly), scalar colouring
(InterpolateScalarsBeforeMapping through a banded table, cell scalars with a clamped range) and textures
(nearest and interpolated), and vtkDataSetMapper over an unstructured grid and image data."""
import numpy as np
from vtkmodules.test import Testing
from vtkmodules.vtkCommonCore import vtkFloatArray, vtkLookupTable
from vtkmodules.vtkCommonDataModel import vtkImageData, vtkPolyData
from vtkmodules.vtkCommonMath import vtkMatrix4x4
from vtkmodules.vtkCommonTransforms import vtkTransform
from vtkmodules.vtkFiltersCore import vtkElevationFilter, vtkThreshold
from vtkmodules.vtkFiltersSources import (vtkConeSource, vtkPlaneSource, vtkSphereSource,
                                          vtkTexturedSphereSource)
from vtkmodules.vtkImagingCore import vtkRTAnalyticSource
from vtkmodules.vtkRenderingCore import (vtkActor, vtkAssembly, vtkDataSetMapper, vtkLight, vtkLightKit,
                                         vtkPolyDataMapper, vtkRenderer, vtkRenderWindow, vtkTexture,
                                         vtkWindowToImageFilter)
import vtkmodules.vtkRenderingOpenGL2  # noqa: F401
from vtkmodules.util.numpy_support import vtk_to_numpy
from whitted import vtkWhittedPass


def grab(window):
    f = vtkWindowToImageFilter()
    f.SetInput(window)
    f.ReadFrontBufferOff()
    f.Update()
    image = f.GetOutput()
    w, h, _ = image.GetDimensions()
    rgb = vtk_to_numpy(image.GetPointData().GetScalars()).reshape(h, w, -1)[:, :, :3].astype(int)
    z = vtkFloatArray()
    window.GetZbufferData(0, 0, w - 1, h - 1, z)
    return rgb, vtk_to_numpy(z).reshape(h, w).copy()


def look(ren, position, focal):
    camera = ren.GetActiveCamera()
    camera.SetPosition(*position)
    camera.SetFocalPoint(*focal)
    ren.ResetCameraClippingRange()


def actor_of(mapper, color=None, specular=0.0):
    actor = vtkActor()
    actor.SetMapper(mapper)
    if color:
        actor.GetProperty().SetColor(*color)
    actor.GetProperty().SetSpecular(specular)
    actor.GetProperty().SetSpecularPower(30)
    return actor


def transforms(ren):
    """One cone mapper placed seven ways; a positional light (VTK light complexity 3)."""
    cone = vtkConeSource()
    cone.SetResolution(32)
    mapper = vtkPolyDataMapper()
    mapper.SetInputConnection(cone.GetOutputPort())

    a = actor_of(mapper, (1, 0, 0), 0.4)
    a.SetPosition(-2, 0.5, 0.5)
    ren.AddActor(a)
    a = actor_of(mapper, (0, 1, 0), 0.4)
    a.SetPosition(-0.8, 0.6, 0.8)
    a.SetOrientation(0, 30, 90)
    ren.AddActor(a)
    a = actor_of(mapper, (0, 0, 1), 0.4)
    a.SetOrigin(0.5, 0, 0)
    a.SetScale(1.6, 0.6, 0.6)
    a.SetPosition(0.2, 0.3, 1.2)
    ren.AddActor(a)
    shear = vtkMatrix4x4()
    shear.SetElement(0, 3, 1.5)
    shear.SetElement(0, 1, 0.5)
    a = actor_of(mapper, (1, 1, 0), 0.4)
    a.SetUserMatrix(shear)
    ren.AddActor(a)
    mirrored = vtkTransform()  # negative determinant
    mirrored.Translate(0.6, 0.35, -0.6)
    mirrored.RotateY(60)
    mirrored.Scale(1, -1, 1)
    a = actor_of(mapper, (1, 0, 1), 0.4)
    a.SetUserTransform(mirrored)
    ren.AddActor(a)
    assembly = vtkAssembly()
    part_a = actor_of(mapper, (0, 1, 1), 0.4)
    part_b = actor_of(mapper, (1, 0.5, 0), 0.4)
    part_b.SetPosition(0, 0, 0.7)
    part_b.SetOrientation(0, 180, 0)
    assembly.AddPart(part_a)
    assembly.AddPart(part_b)
    assembly.SetPosition(-1.6, 0.4, -1.2)
    assembly.RotateY(35)
    ren.AddActor(assembly)

    light = vtkLight()
    light.SetPositional(True)
    light.SetPosition(-1, 5, 4)
    light.SetConeAngle(180)
    ren.AddLight(light)
    look(ren, (0, 3.5, 5.5), (-0.2, 0.4, 0))


def scalars(ren):
    """Scalars interpolated before mapping (banded table) and cell scalars with a clamped range; VTK's
    automatic headlight (light complexity 1)."""
    sphere = vtkSphereSource()
    sphere.SetThetaResolution(48)
    sphere.SetPhiResolution(24)
    sphere.SetRadius(0.9)
    elevation = vtkElevationFilter()
    elevation.SetInputConnection(sphere.GetOutputPort())
    elevation.SetLowPoint(0, -0.9, 0)
    elevation.SetHighPoint(0, 0.9, 0)
    bands = vtkLookupTable()
    bands.SetNumberOfTableValues(6)
    bands.SetHueRange(0.8, 0.1)
    bands.Build()
    banded = vtkPolyDataMapper()
    banded.SetInputConnection(elevation.GetOutputPort())
    banded.SetLookupTable(bands)
    banded.InterpolateScalarsBeforeMappingOn()
    # Specular on: the colour map must be looked up before lighting, so the highlight is not tinted
    a = actor_of(banded, specular=0.6)
    a.GetProperty().SetAmbient(0.1)
    ren.AddActor(a)

    sphere.Update()
    cells = vtkPolyData()
    cells.DeepCopy(sphere.GetOutput())
    values = vtkFloatArray()
    for i in range(cells.GetNumberOfCells()):
        values.InsertNextValue((i * 7) % 50)
    cells.GetCellData().SetScalars(values)
    by_cell = vtkPolyDataMapper()
    by_cell.SetInputData(cells)
    by_cell.SetScalarModeToUseCellData()
    by_cell.SetScalarRange(10, 40)
    a = actor_of(by_cell)
    a.SetPosition(2, 0, 0)
    ren.AddActor(a)
    look(ren, (1, 1.2, 6.5), (1, 0, 0))


def texture(ren):
    """A nearest-filtered texture on a plane (with specular, applied after lighting as VTK does) and an
    interpolated one on a textured sphere."""
    image = vtkImageData()
    image.SetDimensions(8, 8, 1)
    image.AllocateScalars(3, 3)  # VTK_UNSIGNED_CHAR, RGB
    texels = image.GetPointData().GetScalars()
    for j in range(8):
        for i in range(8):
            dark = (i + j) % 2 == 0
            texels.SetTuple3(j * 8 + i, 30 if dark else 200 + 7 * i, 60 + 20 * j if dark else 200, 120)
    plane = vtkPlaneSource()
    plane.SetOrigin(-3, 0, 3)
    plane.SetPoint1(3, 0, 3)
    plane.SetPoint2(-3, 0, -3)
    mapper = vtkPolyDataMapper()
    mapper.SetInputConnection(plane.GetOutputPort())
    nearest = vtkTexture()
    nearest.SetInputData(image)
    nearest.InterpolateOff()
    a = actor_of(mapper, None, 0.3)
    a.SetTexture(nearest)
    ren.AddActor(a)

    ball = vtkTexturedSphereSource()
    ball.SetThetaResolution(48)
    ball.SetPhiResolution(24)
    mapper = vtkPolyDataMapper()
    mapper.SetInputConnection(ball.GetOutputPort())
    smooth = vtkTexture()
    smooth.SetInputData(image)
    smooth.InterpolateOn()
    a = actor_of(mapper)
    a.SetTexture(smooth)
    a.SetPosition(0, 1, 0)
    ren.AddActor(a)
    look(ren, (0.5, 3, 5.5), (0, 0.5, 0))


def datasets(ren):
    """vtkDataSetMapper over non-polydata inputs (an unstructured grid from vtkThreshold, image data): the pass
    extracts the outer surface as the mapper does; point scalars through the default table; a light kit
    (light complexity 2)."""
    source = vtkRTAnalyticSource()
    source.SetWholeExtent(-8, 8, -8, 8, -8, 8)
    threshold = vtkThreshold()
    threshold.SetInputConnection(source.GetOutputPort())
    threshold.SetLowerThreshold(150.0)
    threshold.SetUpperThreshold(300.0)
    threshold.SetThresholdFunction(vtkThreshold.THRESHOLD_BETWEEN)
    grid_mapper = vtkDataSetMapper()
    grid_mapper.SetInputConnection(threshold.GetOutputPort())
    grid_mapper.SetScalarRange(150, 280)
    a = actor_of(grid_mapper, None, 0.3)
    ren.AddActor(a)

    box = vtkImageData()
    box.SetDimensions(4, 3, 2)
    box.SetOrigin(10, -4, -2)
    box.SetSpacing(2, 2, 2)
    box_mapper = vtkDataSetMapper()
    box_mapper.SetInputData(box)
    a = actor_of(box_mapper, (0.4, 0.6, 0.9), 0.5)
    ren.AddActor(a)
    kit = vtkLightKit()
    kit.AddLightsToRenderer(ren)
    look(ren, (30, 25, 40), (4, 0, 0))


class TestWhittedPythonAgreement(Testing.vtkTest):
    def compare(self, build):
        ren = vtkRenderer()
        win = vtkRenderWindow()
        win.SetMultiSamples(0)
        win.SetOffScreenRendering(True)
        win.SetSize(240, 180)
        win.AddRenderer(ren)
        build(ren)
        win.Render()
        gl_rgb, gl_z = grab(win)
        p = vtkWhittedPass()
        p.SetShadows(False)
        p.SetReflections(False)
        p.SetRefractions(False)
        ren.SetPass(p)
        win.Render()
        rt_rgb, rt_z = grab(win)
        d = np.abs(gl_rgb - rt_rgb).max(axis=2)
        hit = (gl_z < 1) & (rt_z < 1)
        coverage = ((gl_z < 1) != (rt_z < 1)).mean()
        depth_off = (np.abs(gl_z - rt_z)[hit] > 1e-3).mean()
        print("%s: mean |d| %.4f, >1: %.3f%%, >3: %.3f%%, coverage mismatch %.3f%%, depth > 1e-3: %.3f%%"
              % (build.__name__, d.mean(), 100 * (d > 1).mean(), 100 * (d > 3).mean(), 100 * coverage,
                 100 * depth_off))
        self.assertLess((d > 1).mean(), 0.005)
        self.assertLess((d > 3).mean(), 0.002)
        self.assertLess(coverage, 0.002)
        self.assertLess(depth_off, 0.001)

    def testTransforms(self):
        self.compare(transforms)

    def testScalars(self):
        self.compare(scalars)

    def testTexture(self):
        self.compare(texture)

    def testDataSets(self):
        self.compare(datasets)


if __name__ == "__main__":
    Testing.main([(TestWhittedPythonAgreement, "test")])
