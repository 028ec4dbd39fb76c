"""3D Glyphs, Point Gaussian and per-point sphere radii in the Whitted view: traced (nothing left to OpenGL), one
instance per glyph, one sphere per splat, shadows on the ground, radii from an array, and a regression image.

    pvbatch test_glyphs.py --plugin P --tmp DIR --baseline B.png

Arrows glyph a sphere's points (3D Glyphs: oriented by Normals, coloured by a point array), Point Gaussian
splats (shader preset Sphere) stand beside them on a Whitted Surface ground; behind them vertices drawn as
spheres (Whitted Surface, Render Points As Spheres) take their radii from a point array through ParaView's
Scaling Mode / Scale Array properties.
"""
import argparse
import os
import re
import sys

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import whitted_pvtest as wt  # noqa: E402

ap = argparse.ArgumentParser()
ap.add_argument("--plugin", required=True)
ap.add_argument("--tmp", required=True)
ap.add_argument("--baseline", required=True)
args = ap.parse_args()

import paraview.simple  # noqa: E402
from paraview.simple import Calculator, ColorBy, Elevation, MaskPoints, Plane, Render, Show, Sphere  # noqa: E402

os.makedirs(args.tmp, exist_ok=True)
wt.load_plugin(args.plugin)
failures = []


def check(ok, msg):
    print(("ok    " if ok else "FAIL  ") + msg)
    if not ok:
        failures.append(msg)


def build(view):
    """The glyph scene in view (a Whitted or a Render View); returns the displays and point counts."""
    ground = Show(Plane(Origin=[-3.0, -1.0, 3.0], Point1=[3.0, -1.0, 3.0], Point2=[-3.0, -1.0, -3.0]), view)
    ground.Representation = "Whitted Surface"
    ground.DiffuseColor = [0.85, 0.85, 0.8]

    ball = Sphere(Center=[-0.9, 0.0, 0.0], Radius=0.8, ThetaResolution=10, PhiResolution=6)
    glyphs = Show(Elevation(Input=ball, LowPoint=[0, -1, 0], HighPoint=[0, 1, 0]), view)
    glyphs.Representation = "3D Glyphs"
    glyphs.GlyphType = "Arrow"
    glyphs.Orient = 1
    glyphs.OrientationMode = "Direction"
    glyphs.SelectOrientationVectors = "Normals"
    glyphs.ScaleFactor = 0.5
    ColorBy(glyphs, ("POINTS", "Elevation"))
    glyph_points = ball.GetDataInformation().GetNumberOfPoints()

    cloud = Sphere(Center=[1.2, -0.2, 0.3], Radius=0.7, ThetaResolution=8, PhiResolution=5)
    splats = Show(Elevation(Input=cloud, LowPoint=[0, -1, 0], HighPoint=[0, 1, 0]), view)
    splats.Representation = "Point Gaussian"
    splats.ShaderPreset = "Sphere"
    splats.GaussianRadius = 0.12
    ColorBy(splats, ("POINTS", "Elevation"))
    splat_points = cloud.GetDataInformation().GetNumberOfPoints()

    dots = MaskPoints(Input=Sphere(Center=[0.2, 0.2, -1.6], Radius=0.6, ThetaResolution=12, PhiResolution=6),
                      OnRatio=1, GenerateVertices=1, SingleVertexPerCell=1, MaximumNumberofPoints=1000)
    radii = Calculator(Input=dots, ResultArrayName="radius", Function="0.03 + 0.1 * (coordsY - 0.2 + 0.6)")
    balls = Show(radii, view)
    balls.Representation = "Whitted Surface"
    balls.RenderPointsAsSpheres = 1
    balls.DiffuseColor = [0.3, 0.6, 0.9]
    dot_points = dots.GetDataInformation().GetNumberOfPoints()
    return ground, glyphs, splats, balls, glyph_points, splat_points, dot_points


view = wt.make_view([300, 225])
ground, glyphs, splats, balls, glyph_points, splat_points, dot_points = build(view)
wt.set_camera(view)
Render(view)
uniform = wt.screenshot(view, os.path.join(args.tmp, "glyphs_uniform_radii.png"), [300, 225])
balls.OSPRayUseScaleArray = "Each Exact"
balls.OSPRayScaleArray = "radius"
Render(view)
view.UpdatePropertyInformation()
report = view.GetProperty("LastFrameReport").GetData()
print(report)
opengl = int(re.search(r"(\d+) props drawn by OpenGL", report).group(1))
scene = re.search(r"(\d+) triangles, (\d+) spheres, \d+ tubes, \d+ objects, (\d+) instances", report)
triangles, spheres, instances = (int(g) for g in scene.groups())
check(opengl == 0, "nothing drawn by OpenGL (%d props)" % opengl)
check(instances >= glyph_points + 2, "one instance per glyph: %d instances for %d glyphs" % (instances, glyph_points))
check(spheres == splat_points + dot_points, "one sphere per splat and per vertex: %d for %d + %d points" % (
    spheres, splat_points, dot_points))
check(triangles < 1000, "glyph geometry held once: %d triangles" % triangles)

image = wt.screenshot(view, os.path.join(args.tmp, "glyphs.png"), [300, 225])
ok, _ = wt.compare_image(os.path.join(args.tmp, "glyphs.png"), args.baseline, args.tmp, **wt.CHANGE_GUARD)
check(ok, "regression image")
changed = int((np.abs(image - uniform).max(axis=2) > 25).sum())
check(changed > 200, "Scale Array sets the sphere radii: %d pixels changed from uniform radii" % changed)
view.Shadows = 0
unshadowed = wt.screenshot(view, os.path.join(args.tmp, "glyphs_noshadow.png"), [300, 225])
darker = int(((unshadowed - image).max(axis=2) > 25).sum())
check(darker > 300, "glyphs and splats cast shadows: %d ground pixels darker with shadows" % darker)

# Independent check: effects off (and the radii as the Render View draws them: uniform), the Whitted image equals
# ParaView's own Render View raster of the same scene away from silhouettes (whitted_pvtest.RENDER_VIEW; measured:
# see there). The Render View draws the splats and point spheres as impostors, the tracer as spheres: the same
# pixels, up to edges.
balls.OSPRayUseScaleArray = "All Approximate"
view.Shadows = 0
view.Reflections = 0
view.Refractions = 0
off_png = os.path.join(args.tmp, "glyphs_effects_off.png")
wt.screenshot(view, off_png, [300, 225])
rv = wt.make_view([300, 225], proxy="RenderView")
build(rv)
wt.set_camera(rv)
rv_png = os.path.join(args.tmp, "glyphs_renderview.png")
raster = wt.screenshot(rv, rv_png, [300, 225])
compared = ~wt.silhouette_mask(raster)
print("render-view oracle: %.1f%% of the pixels compared" % (100 * compared.mean()))
ok, _ = wt.compare_image(off_png, rv_png, args.tmp, mask=compared, **wt.RENDER_VIEW)
check(ok, "effects off, the Whitted view equals the Render View away from edges")

if failures:
    wt.fail("; ".join(failures))
print("OK")
