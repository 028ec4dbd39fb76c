"""Scenes built from VTK sources, shared by the demo (whitted_demo.py) and the tests.

Every function takes a vtkRenderer, adds actors and lights, sets the background and the camera, and
returns a dict of the actors it created (by name) so callers can tweak them.
"""
from vtkmodules.vtkCommonCore import vtkUnsignedCharArray
from vtkmodules.vtkFiltersSources import vtkPlaneSource, vtkSphereSource
from vtkmodules.vtkRenderingCore import vtkActor, vtkLight, vtkPolyDataMapper

from .vtkWhitted import vtkWhittedPass


def set_whitted(prop, reflectance=None, transmittance=None, ior=None):
    """Sets the Whitted material keys on a vtkProperty (scalars or RGB triples)."""
    info = prop.GetInformation()
    for key, value in ((vtkWhittedPass.REFLECTANCE(), reflectance),
                       (vtkWhittedPass.TRANSMITTANCE(), transmittance)):
        if value is None:
            continue
        values = [float(value)] if isinstance(value, (int, float)) else [float(v) for v in value]
        info.Set(key, values, len(values))
    if ior is not None:
        info.Set(vtkWhittedPass.INDEX_OF_REFRACTION(), float(ior))


def checkerboard(origin, point1, point2, nx, ny, color0, color1):
    """A vtkPlaneSource whose cells carry alternating RGB colours (direct unsigned-char scalars)."""
    plane = vtkPlaneSource()
    plane.SetOrigin(*origin)
    plane.SetPoint1(*point1)
    plane.SetPoint2(*point2)
    plane.SetResolution(nx, ny)
    plane.Update()
    poly = plane.GetOutput()
    colors = vtkUnsignedCharArray()
    colors.SetName("checker")
    colors.SetNumberOfComponents(3)
    for j in range(ny):
        for i in range(nx):
            c = color0 if (i + j) % 2 == 0 else color1
            colors.InsertNextTuple3(*[round(255 * v) for v in c])
    poly.GetCellData().SetScalars(colors)
    return poly


def sphere_actor(center, radius, resolution=48):
    source = vtkSphereSource()
    source.SetCenter(*center)
    source.SetRadius(radius)
    source.SetThetaResolution(2 * resolution)
    source.SetPhiResolution(resolution)
    mapper = vtkPolyDataMapper()
    mapper.SetInputConnection(source.GetOutputPort())
    actor = vtkActor()
    actor.SetMapper(mapper)
    return actor


def classic_scene(renderer, resolution=48):
    """Whitted's 1980 scene: red/yellow checkerboard floor, mirror sphere, glass sphere, one point
    light; the same layout as the core's built-in "classic" scene."""
    floor_poly = checkerboard((-5.0, 0.0, 3.0), (5.0, 0.0, 3.0), (-5.0, 0.0, -11.0), 10, 14,
                              (0.85, 0.1, 0.1), (0.95, 0.85, 0.1))
    floor_mapper = vtkPolyDataMapper()
    floor_mapper.SetInputData(floor_poly)
    floor_mapper.SetScalarModeToUseCellData()
    floor = vtkActor()
    floor.SetMapper(floor_mapper)
    floor.GetProperty().SetAmbient(0.15)
    floor.GetProperty().SetDiffuse(0.85)

    mirror = sphere_actor((0.9, 1.1, -3.6), 1.1, resolution)
    p = mirror.GetProperty()
    p.SetColor(0.7, 0.7, 0.7)
    p.SetAmbient(0.05)
    p.SetDiffuse(0.15)
    p.SetSpecular(0.6)
    p.SetSpecularPower(60)
    set_whitted(p, reflectance=0.8)

    glass = sphere_actor((-0.7, 0.8, -1.4), 0.8, resolution)
    p = glass.GetProperty()
    p.SetColor(0.9, 0.9, 0.9)
    p.SetAmbient(0.0)
    p.SetDiffuse(0.0)
    p.SetSpecular(0.8)
    p.SetSpecularPower(100)
    set_whitted(p, reflectance=0.1, transmittance=0.9, ior=1.5)

    for a in (floor, mirror, glass):
        renderer.AddActor(a)

    light = vtkLight()
    light.SetLightTypeToSceneLight()
    light.SetPositional(True)
    light.SetPosition(4.0, 7.0, 3.0)
    light.SetFocalPoint(0.0, 0.0, 0.0)
    light.SetConeAngle(180.0)
    renderer.AddLight(light)
    renderer.SetBackground(0.3, 0.5, 0.85)

    camera = renderer.GetActiveCamera()
    camera.SetPosition(0.0, 1.8, 4.0)
    camera.SetFocalPoint(0.0, 0.9, -2.5)
    camera.SetViewUp(0.0, 1.0, 0.0)
    camera.SetViewAngle(40.0)
    renderer.ResetCameraClippingRange()
    return {"floor": floor, "mirror": mirror, "glass": glass, "light": light}
