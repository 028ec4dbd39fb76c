#!/usr/bin/env python3
"""What a mirror shows: the environment in the reflected direction (issue: correct pixels at every setting).

A flat mirror quad (kr 1, no local shading) turned 25 degrees about y is rendered through the pass; for every
pixel well inside the mirror the reflected direction is computed here independently (camera matrix inverse,
plane intersection, reflection: numpy), mapped to the environment with VTK's own conventions, and compared:
- a vtkSkybox (Sphere projection) with an equirectangular image of 8 x 4 coloured cells: the mirror shows the
  cell of the reflected direction (vtkSkybox's shader: u = atan2(d.right, d.front)/2pi + 0.5,
  v = atan2(d.up, |d.(right, front)|)/pi + 0.5, front = up x right); the skybox is never traced as a square;
- the renderer's environment texture (image-based lighting, equirectangular: u = atan2(d.z, d.x)/2pi + 0.5);
- a gradient background: the mix of bottom and top colours by elevation 0.5 (1 + r.up);
- a translucent IOR-1 quad in front of the skybox blends over the skybox exactly as VTK's own image does.
"""
import sys

import numpy as np
from vtkmodules.vtkCommonDataModel import vtkImageData
from vtkmodules.vtkFiltersSources import vtkPlaneSource
from vtkmodules.vtkRenderingCore import vtkActor, vtkPolyDataMapper, vtkRenderer, vtkSkybox, vtkTexture
from vtkmodules.util.numpy_support import numpy_to_vtk
from whitted import vtkWhittedMaterialKeys, vtkWhittedPass
from whitted_imagetest import offscreen_render

SIZE = 200
ANGLE = 25.0
failures = []


def check(condition, message):
    print(("ok    " if condition else "FAIL  ") + message)
    if not condition:
        failures.append(message)


def cell_image():
    """64 x 32 equirectangular image, 8 x 4 cells of distinct colours; rows bottom (v = 0) to top."""
    u = np.arange(64) // 8
    v = np.arange(32) // 8
    uu, vv = np.meshgrid(u, v)
    rgb = np.stack([uu * 32 + 16, vv * 64 + 32, 60 + ((uu + vv) % 2) * 150], axis=-1).astype(np.uint8)
    image = vtkImageData()
    image.SetDimensions(64, 32, 1)
    image.GetPointData().SetScalars(numpy_to_vtk(rgb.reshape(-1, 3).copy()))
    texture = vtkTexture()
    texture.SetInputData(image)
    texture.InterpolateOff()
    return texture, rgb


def cell_colour(rgb, u, v):
    return rgb[np.clip((v * 32).astype(int), 0, 31), np.clip((u * 64).astype(int), 0, 63)]


def mirror_scene(ren):
    plane = vtkPlaneSource()
    plane.SetOrigin(-1, -1, 0)
    plane.SetPoint1(1, -1, 0)
    plane.SetPoint2(-1, 1, 0)
    mapper = vtkPolyDataMapper()
    mapper.SetInputConnection(plane.GetOutputPort())
    mirror = vtkActor()
    mirror.SetMapper(mapper)
    mirror.SetOrientation(0, ANGLE, 0)
    p = mirror.GetProperty()
    p.SetAmbient(0)
    p.SetDiffuse(0)
    p.SetSpecular(0)
    p.GetInformation().Set(vtkWhittedMaterialKeys.REFLECTANCE(), [1.0], 1)
    ren.AddActor(mirror)
    camera = ren.GetActiveCamera()
    camera.SetPosition(0, 0.3, 4)
    camera.SetFocalPoint(0, 0, 0)
    camera.SetViewUp(0, 1, 0)
    camera.SetViewAngle(40)
    ren.ResetCameraClippingRange()


def reflected_directions(ren):
    """Per pixel: inside-mirror mask and reflected unit direction, from the camera matrix alone."""
    m = ren.GetActiveCamera().GetCompositeProjectionTransformMatrix(1.0, -1, 1)
    M = np.array([[m.GetElement(r, c) for c in range(4)] for r in range(4)])
    inv = np.linalg.inv(M)
    j, i = np.mgrid[0:SIZE, 0:SIZE]
    x, y = 2 * (i + 0.5) / SIZE - 1, 2 * (j + 0.5) / SIZE - 1

    def unproject(z):
        p = inv @ np.stack([x.ravel(), y.ravel(), np.full(x.size, z), np.ones(x.size)])
        return (p[:3] / p[3]).T

    near, far = unproject(-1.0), unproject(1.0)
    d = far - near
    d /= np.linalg.norm(d, axis=1, keepdims=True)
    a = np.radians(ANGLE)
    n = np.array([np.sin(a), 0.0, np.cos(a)])
    t = -(near @ n) / (d @ n)
    hit = near + t[:, None] * d
    # Quad coordinates: x along (cos a, 0, -sin a), y along (0, 1, 0)
    qx, qy = hit @ np.array([np.cos(a), 0.0, -np.sin(a)]), hit[:, 1]
    inside = (np.abs(qx) < 0.85) & (np.abs(qy) < 0.85) & (t > 0)
    r = d - 2 * (d @ n)[:, None] * n
    return inside.reshape(SIZE, SIZE), r.reshape(SIZE, SIZE, 3)


def render(ren, with_pass=True):
    pass_ = None
    if with_pass:
        pass_ = vtkWhittedPass()
        pass_.SetShadows(False)

    def stats(p):
        if p is None:
            return None
        stats = p.GetLastFrameStatistics()
        return (stats.GetNumberOfTriangles(), stats.GetNumberOfTracedActors(), stats.GetNumberOfSafetyNetCatches())

    return offscreen_render(ren, SIZE, pass_, stats)


def away_from_cell_borders(u, v):
    fu, fv = (u * 8) % 1.0, (v * 4) % 1.0
    return (np.abs(fu - 0.5) < 0.4) & (np.abs(fv - 0.5) < 0.4) & (np.abs(u - 0.5) < 0.49)


def compare_cells(label, image, inside, u, v, rgb):
    ok = inside & away_from_cell_borders(u, v)
    expected = cell_colour(rgb, u, v).astype(float)
    match = (np.abs(image - expected).max(axis=2) <= 1)[ok].mean()
    check(ok.sum() > 2000 and match >= 0.995,
          f"{label}: {match * 100:.2f}% of {ok.sum()} mirror pixels show the environment cell of the reflected "
          "direction")


def skybox():
    texture, rgb = cell_image()
    ren = vtkRenderer()
    mirror_scene(ren)
    sky = vtkSkybox()
    sky.SetProjection(vtkSkybox.Sphere)
    sky.SetTexture(texture)
    ren.AddActor(sky)
    image, (triangles, traced, catches) = render(ren)
    check(triangles == 2 and traced == 1, f"skybox not traced: {triangles} triangles, {traced} traced actors")
    check(catches == 0, f"skybox: safety nets caught nothing ({catches})")
    inside, r = reflected_directions(ren)
    right, up = np.array([1.0, 0, 0]), np.array([0, 1.0, 0])
    front = np.cross(up, right)
    x, y, z = r @ right, r @ up, r @ front
    u = 0.5 * np.arctan2(x, z) / np.pi + 0.5
    v = np.arctan2(y, np.hypot(x, z)) / np.pi + 0.5
    compare_cells("vtkSkybox (sphere)", image, inside, u, v, rgb)


def environment_texture():
    texture, rgb = cell_image()
    ren = vtkRenderer()
    mirror_scene(ren)
    ren.SetEnvironmentTexture(texture)
    image, (_, _, catches) = render(ren)
    check(catches == 0, f"environment texture: safety nets caught nothing ({catches})")
    inside, r = reflected_directions(ren)
    u = np.arctan2(r[..., 2], r[..., 0]) / (2 * np.pi) + 0.5
    v = np.arcsin(np.clip(r[..., 1], -1, 1)) / np.pi + 0.5
    compare_cells("renderer environment texture", image, inside, u, v, rgb)


def gradient():
    bottom, top = np.array([0.1, 0.2, 0.5]), np.array([0.9, 0.8, 0.3])
    ren = vtkRenderer()
    mirror_scene(ren)
    ren.SetBackground(*bottom)
    ren.SetBackground2(*top)
    ren.GradientBackgroundOn()
    image, _ = render(ren)
    inside, r = reflected_directions(ren)
    up = np.array(ren.GetActiveCamera().GetViewUp())
    up = up - (up @ np.array(ren.GetActiveCamera().GetDirectionOfProjection())) * np.array(
        ren.GetActiveCamera().GetDirectionOfProjection())
    up /= np.linalg.norm(up)
    s = np.clip(0.5 * (1 + r @ up), 0, 1)[..., None]
    expected = ((1 - s) * bottom + s * top) * 255
    err = np.abs(image - expected).max(axis=2)[inside]
    check(inside.sum() > 2000 and np.percentile(err, 99) <= 2.0,
          f"gradient background by elevation: 99th percentile error {np.percentile(err, 99):.2f}/255 over "
          f"{inside.sum()} mirror pixels")


def translucent_over_skybox():
    def scene():
        texture, _ = cell_image()
        ren = vtkRenderer()
        plane = vtkPlaneSource()
        mapper = vtkPolyDataMapper()
        mapper.SetInputConnection(plane.GetOutputPort())
        quad = vtkActor()
        quad.SetMapper(mapper)
        quad.GetProperty().SetColor(0.9, 0.3, 0.2)
        quad.GetProperty().SetOpacity(0.35)
        ren.AddActor(quad)
        sky = vtkSkybox()
        sky.SetProjection(vtkSkybox.Sphere)
        sky.SetTexture(texture)
        ren.AddActor(sky)
        camera = ren.GetActiveCamera()
        camera.SetPosition(0.2, 0.1, 1.5)
        camera.SetFocalPoint(0, 0, 0)
        ren.ResetCameraClippingRange()
        return ren

    vtk_image, _ = render(scene(), with_pass=False)
    image, _ = render(scene())
    diff = np.abs(image - vtk_image).max(axis=2)
    share = (diff > 2).mean()
    check(vtk_image.std() > 10 and share <= 0.02,
          f"translucent quad over a skybox: {share * 100:.2f}% of pixels differ from VTK's image by > 2/255")


def main():
    skybox()
    environment_texture()
    gradient()
    translucent_over_skybox()
    print(f"{len(failures)} failed")
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
