"""Materials a user understands, in ParaView: a Transmittance-only sphere is glass, presets set every field.

    pvbatch test_materials.py --plugin P --tmp DIR

A white sphere (Opacity 1, lit) shown as "Whitted Surface" with Transmittance 0.9 (index 1) in front of a wall
whose colour W does not depend on light (Ambient 1, Diffuse 0). The energy rule gives the sphere's own colour the
0.1 that transmission leaves at each of the two surfaces a centre ray crosses (front, then back from inside), so
every pixel of the sphere's centre lies between 0.81 W and 0.81 W + 0.19 x 255 (own colours at most 1), with W
measured in a render without the sphere: not the white, over-exposed ball (1 x its colour + 0.9 x (1 x its colour
+ 0.9 W)) that the old rule gave. Then the Material Preset list: Gold puts its coloured reflectance on the actor's property and
no other key, Glass its transmittance and index, None gives the fields back (Transmittance 0.9 again), a material
of an OSPRay material library file (Material Library, Library Material) its keys, and a Mirror sphere's centre
reflects the wall behind the camera exactly. The materials of a library file are listed (LibraryMaterialNames, in
name order) once the file is set, and none without one.
"""
import argparse
import json
import os
import sys

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import whitted_pvtest as wt  # noqa: E402

ap = argparse.ArgumentParser()
ap.add_argument("--plugin", required=True)
ap.add_argument("--tmp", required=True)
args = ap.parse_args()

import paraview.simple  # noqa: E402
from paraview.simple import Plane, Render, Show, Sphere  # noqa: E402

os.makedirs(args.tmp, exist_ok=True)
failures = []
SIZE = 160


def check(ok, msg):
    print(("ok    " if ok else "FAIL  ") + msg)
    if not ok:
        failures.append(msg)


def centre_pixels(view, name):
    pixels = wt.screenshot(view, os.path.join(args.tmp, "materials_%s.png" % name), [SIZE, SIZE]).astype(float)
    h, w, _ = pixels.shape
    return pixels[h // 2 - 12:h // 2 + 12, w // 2 - 12:w // 2 + 12].reshape(-1, 3)


material_keys = wt.material_keys


def library_choices(display):
    """The names a script reads from the representation: LibraryMaterialNames (information property)"""
    display.UpdatePropertyInformation()
    prop = display.GetProperty("LibraryMaterialNames").SMProperty
    return [prop.GetElement(i) for i in range(prop.GetNumberOfElements())]


wt.load_plugin(args.plugin)
view = wt.make_view([SIZE, SIZE])
view.UseLight = 1
view.Shadows = 0  # the wall behind the camera would shade the sphere from every light
paraview.simple._DisableFirstRenderCameraReset()
view.CameraPosition = [0.0, 0.0, 6.0]
view.CameraFocalPoint = [0.0, 0.0, 0.0]
view.CameraViewUp = [0.0, 1.0, 0.0]
view.CameraViewAngle = 30.0


def wall(origin, p1, p2, colour):
    d = Show(Plane(Origin=origin, Point1=p1, Point2=p2), view)
    d.AmbientColor = colour
    d.DiffuseColor = colour
    d.Ambient = 1.0
    d.Diffuse = 0.0
    return d


wall([-20, -20, -3], [20, -20, -3], [-20, 20, -3], [0.2, 0.6, 0.9])
behind = wall([-20, -20, 8], [-20, 20, 8], [20, -20, 8], [0.7, 0.4, 0.3])  # behind the camera: what mirrors show
background = centre_pixels(view, "wall").mean(axis=0)
check(np.abs(background - np.array([0.2, 0.6, 0.9]) * 255).max() <= 2, "the camera sees the wall: %s" % background)

sphere = Show(Sphere(Radius=1.0, ThetaResolution=96, PhiResolution=48), view)
sphere.Representation = "Whitted Surface"
# The sphere must be well lit for the test to tell the rules apart: the old rule adds at least its opaque colour
# on top of 0.81 W, so an opaque centre above 50 puts it beyond the upper bound below
opaque = centre_pixels(view, "opaque").mean()
check(opaque > 50, "the opaque white sphere is lit (centre mean %.1f > 50)" % opaque)
sphere.Transmittance = 0.9
glass = centre_pixels(view, "transmittance")
low, high = 0.81 * background - 1.5, 0.81 * background + 0.19 * 255 + 1.5
check(bool(np.all(glass >= low) and np.all(glass <= high)),
      "Transmittance 0.9 sphere: centre %s within 0.81 x wall %s .. + 48.5 (min %s, max %s)"
      % (np.round(glass.mean(axis=0), 1), np.round(background, 1), glass.min(axis=0), glass.max(axis=0)))
check(glass.mean() < 0.9 * 255, "Transmittance 0.9 sphere is not over-exposed (mean %.1f)" % glass.mean())

sphere.MaterialPreset = "Gold"
Render(view)
check(material_keys(sphere) == {"REFLECTANCE": [1.0, 0.71, 0.29]}, "Gold preset keys %s" % material_keys(sphere))
sphere.MaterialPreset = "Glass"
Render(view)
check(material_keys(sphere) == {"TRANSMITTANCE": [1.0, 1.0, 1.0], "INDEX_OF_REFRACTION": [1.5]},
      "Glass preset keys %s" % material_keys(sphere))
sphere.MaterialPreset = "None"
Render(view)
keys = material_keys(sphere)
check(keys.get("TRANSMITTANCE") == [0.9], "None gives the fields back: %s" % keys)

# An OSPRay material library file, as ParaView's "Load Ray Tracing Materials" reads
library = os.path.join(args.tmp, "materials.json")
with open(library, "w") as f:
    json.dump({"family": "OSPRay", "version": "0.0", "materials": {
        "bronze": {"type": "alloy", "doubles": {"color": [0.9, 0.5, 0.2], "roughness": [0.2]}},
        "window": {"type": "glass", "doubles": {"eta": [1.52]}}}}, f)
choices = library_choices(sphere)
check(choices == [], "before a library, no Library Material Names: %s" % choices)
sphere.MaterialLibrary = library
choices = library_choices(sphere)
check(choices == ["bronze", "window"], "the library's materials are its Library Material Names: %s" % choices)
Render(view)
check(material_keys(sphere).get("TRANSMITTANCE") == [0.9], "library loaded, no material chosen: the fields apply")
sphere.LibraryMaterial = "bronze"
Render(view)
check(material_keys(sphere) == {"REFLECTANCE": [0.9, 0.5, 0.2]}, "library alloy keys %s" % material_keys(sphere))
sphere.LibraryMaterial = "None"
Render(view)
check(material_keys(sphere).get("TRANSMITTANCE") == [0.9], "None: no library material, the fields again")
sphere.LibraryMaterial = "bronze"
Render(view)
sphere.LibraryMaterial = ""
Render(view)
check(material_keys(sphere).get("TRANSMITTANCE") == [0.9], "an empty name: the fields again")
sphere.MaterialLibrary = ""
choices = library_choices(sphere)
check(choices == [], "library removed: no names: %s" % choices)

sphere.MaterialPreset = "Mirror"
view.UseLight = 0  # the preset's highlight of the light kit's headlight would sit exactly on the centre
mirror = centre_pixels(view, "mirror")
seen = np.array([0.7, 0.4, 0.3]) * 255
check(np.abs(mirror.mean(axis=0) - seen).max() <= 2.0,
      "Mirror preset: the sphere's centre shows the wall behind the camera, %s vs %s"
      % (np.round(mirror.mean(axis=0), 1), np.round(seen, 1)))

print("%d failed" % len(failures))
sys.stdout.flush()
os._exit(1 if failures else 0)
