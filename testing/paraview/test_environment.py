"""ParaView's Skybox background mode in the Whitted Ray Trace view: mirrors reflect the skybox by direction.

    pvbatch test_environment.py --plugin P --tmp DIR

An equirectangular image of 8 x 4 coloured cells is set as the view's Skybox background (BackgroundColorMode
'Skybox', BackgroundTexture from CreateTexture). A mirror sphere (Reflectance 1, no local shading) sits at the
origin and the camera looks at its centre, so the centre pixel reflects the direction back to the camera. The
test computes that direction's cell with ParaView's skybox convention (u = atan2(d.z, d.x) / 2pi + 0.5,
v = asin(d.y) / pi + 0.5 for the default environment vectors) and checks the pixel shows it; a corner pixel
(a miss) must show the skybox, not the single background colour.
"""
import argparse
import math
import os
import sys

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import whitted_pvtest as wt  # noqa: E402

ap = argparse.ArgumentParser()
ap.add_argument("--plugin", required=True)
ap.add_argument("--tmp", required=True)
args = ap.parse_args()

from paraview.simple import CreateTexture, Show, Sphere  # noqa: E402
from vtkmodules.util.numpy_support import numpy_to_vtk  # noqa: E402
from vtkmodules.vtkCommonDataModel import vtkImageData  # noqa: E402
from vtkmodules.vtkIOImage import vtkPNGWriter  # noqa: E402

os.makedirs(args.tmp, exist_ok=True)
failures = []


def check(ok, msg):
    print(("ok    " if ok else "FAIL  ") + msg)
    if not ok:
        failures.append(msg)


# The environment image: 256 x 128, 8 x 4 cells of distinct colours, rows bottom (v = 0) to top
u_cell, v_cell = np.meshgrid(np.arange(256) // 32, np.arange(128) // 32)
cells = np.stack([u_cell * 32 + 16, v_cell * 64 + 32, 60 + ((u_cell + v_cell) % 2) * 150], axis=-1).astype(np.uint8)
image = vtkImageData()
image.SetDimensions(256, 128, 1)
image.GetPointData().SetScalars(numpy_to_vtk(cells.reshape(-1, 3).copy()))
sky_png = os.path.join(args.tmp, "environment_cells.png")
writer = vtkPNGWriter()
writer.SetFileName(sky_png)
writer.SetInputData(image)
writer.Write()

wt.load_plugin(args.plugin)
view = wt.make_view([200, 200])
view.UseLight = 1
view.BackgroundColorMode = "Skybox"
view.BackgroundTexture = CreateTexture(sky_png)
mirror = Show(Sphere(Radius=1.0, ThetaResolution=128, PhiResolution=64), view)
mirror.Representation = "Whitted Surface"
mirror.Ambient = 0.0
mirror.Diffuse = 0.0
mirror.Specular = 0.0
mirror.Reflectance = 1.0
eye = [0.8, 0.5, 4.0]
view.CameraPosition = eye
view.CameraFocalPoint = [0.0, 0.0, 0.0]
view.CameraViewUp = [0.0, 1.0, 0.0]
view.CameraViewAngle = 30.0
pixels = wt.screenshot(view, os.path.join(args.tmp, "environment.png"), [200, 200])
h, w, _ = pixels.shape

d = np.array(eye) / np.linalg.norm(eye)  # reflected straight back to the camera at the sphere's centre pixel
u = math.atan2(d[2], d[0]) / (2 * math.pi) + 0.5
v = math.asin(d[1]) / math.pi + 0.5
expected = cells[int(v * 128), int(u * 256)].astype(int)
centre = pixels[h // 2 - 1:h // 2 + 1, w // 2 - 1:w // 2 + 1].reshape(-1, 3)
err = np.abs(centre - expected).max()
check(err <= 3, "mirror centre shows the skybox cell of the reflected direction (u %.3f, v %.3f): expected %s, got "
      "%s" % (u, v, expected.tolist(), centre.tolist()))
background = np.round(np.array(view.Background) * 255).astype(int)
corner = pixels[2, 2]
check(np.abs(corner - background).max() > 10, "a miss shows the skybox (%s), not the background colour (%s)" %
      (corner.tolist(), background.tolist()))
print("%d failed" % len(failures))
sys.stdout.flush()
os._exit(1 if failures else 0)
