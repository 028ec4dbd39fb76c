#!/usr/bin/env python3
"""Materials a user understands: the energy rule, coloured reflectance, absorption, presets, OSPRay libraries.

Every check compares traced pixels with a value computed here from the material alone (analytic), in a scene where
the answer is exact: a camera looking down -z at a quad (or slab) in front of an UNLIT wall, whose colour is
therefore its exact pixel value.
- Energy rule: a lit, white, opaque quad with Transmittance 1 (IOR 1) shows exactly the wall (it used to add its
  own lit colour on top: a white, over-exposed quad); Transmittance 0.9 over an unlit colour C shows
  0.9 wall + 0.1 C; a default translucent quad (Opacity 0.4, no keys) shows 0.4 C + 0.6 wall and equals VTK's own
  raster image; a lit white mirror (Reflectance 1, turned 45 degrees) shows exactly the wall it faces.
- RGB reflectance: a gold mirror (Reflectance (1, 0.71, 0.29)) in front of a white wall shows that colour.
- Absorption: a 2-unit slab (Transmittance 1, IOR 1) with ATTENUATION_COLOR c over ATTENUATION_DISTANCE 1 shows
  c^2 of the white wall behind it (Beer-Lambert).
- Presets (vtkWhittedMaterialLibrary.ApplyPreset) set every key, None removes them all; the Gold preset renders
  the gold mirror's pixels.
- An OSPRay material library (JSON): glass, metal (eta, k -> normal-incidence reflectance computed here), alloy,
  principled (the PBR interpolation's metallic rule) and an unmapped type; unused fields are warned about; an alloy mirror renders its colour plus the
  share of its own (lit white) colour the energy rule leaves.
"""
import json
import math
import sys

import numpy as np
from vtkmodules.vtkCommonCore import vtkCommand
from vtkmodules.vtkFiltersSources import vtkCubeSource, vtkPlaneSource
from vtkmodules.vtkRenderingCore import vtkActor, vtkPolyDataMapper, vtkRenderer
from whitted import vtkWhittedMaterialKeys, vtkWhittedMaterialLibrary, vtkWhittedPass
from whitted_imagetest import offscreen_render

SIZE = 120
WALL = (0.2, 0.6, 0.9)
failures = []


def check(condition, message):
    print(("ok    " if condition else "FAIL  ") + message)
    if not condition:
        failures.append(message)


def actor(source, color=(1, 1, 1), lit=True):
    mapper = vtkPolyDataMapper()
    mapper.SetInputConnection(source.GetOutputPort())
    a = vtkActor()
    a.SetMapper(mapper)
    p = a.GetProperty()
    p.SetColor(*color)
    p.SetLighting(lit)
    return a


def quad(origin, p1, p2, color=(1, 1, 1), lit=True):
    plane = vtkPlaneSource()
    plane.SetOrigin(*origin)
    plane.SetPoint1(*p1)
    plane.SetPoint2(*p2)
    return actor(plane, color, lit)


def set_keys(prop, **keys):
    info = prop.GetInformation()
    for name, value in keys.items():
        key = getattr(vtkWhittedMaterialKeys, name)()
        if isinstance(value, (int, float)):
            info.Set(key, float(value))
        else:
            info.Set(key, [float(v) for v in value], len(value))


def scene(front, wall=None):
    """Camera on +z looking at the origin; an unlit wall (colour WALL unless given) at z = -3 behind front."""
    ren = vtkRenderer()
    ren.SetBackground(0, 0, 0)
    ren.AddActor(wall or quad((-20, -20, -3), (20, -20, -3), (-20, 20, -3), WALL, lit=False))
    if front is not None:
        ren.AddActor(front)
    cam = ren.GetActiveCamera()
    cam.SetPosition(0, 0, 6)
    cam.SetFocalPoint(0, 0, 0)
    cam.SetViewUp(0, 1, 0)
    cam.SetViewAngle(30)
    ren.ResetCameraClippingRange()
    return ren


def centre(ren, traced=True):
    """Mean and spread (max - min) of the central 20 x 20 pixels, in 0..255."""
    image, _ = offscreen_render(ren, SIZE, vtkWhittedPass() if traced else None)
    block = image[SIZE // 2 - 10:SIZE // 2 + 10, SIZE // 2 - 10:SIZE // 2 + 10].reshape(-1, 3)
    return block.mean(axis=0), (block.max(axis=0) - block.min(axis=0)).max()


def expect(ren, rgb, message, tol=1.0):
    got, spread = centre(ren)
    want = 255.0 * np.asarray(rgb)
    check(np.abs(got - want).max() <= tol and spread <= 1,
          "%s: %s, expected %s" % (message, np.round(got, 1), np.round(want, 1)))


def front_quad(color=(1, 1, 1), lit=True):
    return quad((-1, -1, 0), (1, -1, 0), (-1, 1, 0), color, lit)


def mirror(**keys):
    """A lit, white, opaque quad turned 45 degrees about y: camera rays reflect along +x, into a wall at x = 4."""
    m = front_quad()
    m.SetOrientation(0, 45, 0)
    set_keys(m.GetProperty(), **keys)
    return m


def mirror_scene(m, wall_color):
    wall = quad((4, -20, -20), (4, -20, 20), (4, 20, -20), wall_color, lit=False)
    ren = scene(m)
    ren.AddActor(wall)
    return ren


# Energy rule ------------------------------------------------------------------------------------------------------
expect(scene(None), WALL, "wall alone")
glass = front_quad()
set_keys(glass.GetProperty(), TRANSMITTANCE=[1.0])
expect(scene(glass), WALL, "lit white quad, Transmittance 1 alone: exactly the wall behind")
C = (0.9, 0.3, 0.1)
tinted = front_quad(C, lit=False)
set_keys(tinted.GetProperty(), TRANSMITTANCE=[0.9])
expect(scene(tinted), [0.9 * w + 0.1 * c for w, c in zip(WALL, C)], "Transmittance 0.9 over colour C")
translucent = front_quad(C, lit=False)
translucent.GetProperty().SetOpacity(0.4)
expect(scene(translucent), [0.4 * c + 0.6 * w for w, c in zip(WALL, C)], "default translucency (Opacity 0.4)")
raster, _ = centre(scene(translucent), traced=False)
traced, _ = centre(scene(translucent))
check(np.abs(raster - traced).max() <= 1.0,
      "default translucency equals VTK's raster: %s vs %s" % (np.round(traced, 1), np.round(raster, 1)))
MIRRORED = (0.7, 0.4, 0.3)
expect(mirror_scene(mirror(REFLECTANCE=[1.0]), MIRRORED), MIRRORED,
       "lit white quad, Reflectance 1 alone: exactly the wall it mirrors")

# RGB reflectance ------------------------------------------------------------------------------------------------
GOLD = (1.0, 0.71, 0.29)
expect(mirror_scene(mirror(REFLECTANCE=GOLD), (1, 1, 1)), GOLD, "gold mirror over a white wall")

# Beer-Lambert absorption ------------------------------------------------------------------------------------------
cube = vtkCubeSource()
cube.SetXLength(2)
cube.SetYLength(2)
cube.SetZLength(2)
slab = actor(cube)
ATT = (0.5, 0.8, 1.0)
set_keys(slab.GetProperty(), TRANSMITTANCE=[1.0], ATTENUATION_COLOR=ATT, ATTENUATION_DISTANCE=1.0)
white_wall = quad((-20, -20, -3), (20, -20, -3), (-20, 20, -3), (1, 1, 1), lit=False)
expect(scene(slab, white_wall), [a ** 2 for a in ATT], "2 units of glass keeping ATTENUATION_COLOR per unit")

# Presets -----------------------------------------------------------------------------------------------------------
Lib = vtkWhittedMaterialLibrary
names = [Lib.GetPresetName(i) for i in range(Lib.GetNumberOfPresets())]
check(names == ["None", "Glass", "Water", "Mirror", "Chrome", "Gold", "Copper", "Plastic"], "preset names %s" % names)


def keys_of(prop):
    info = prop.GetInformation()
    out = {}
    for name in ("REFLECTANCE", "TRANSMITTANCE", "ATTENUATION_COLOR"):
        key = getattr(vtkWhittedMaterialKeys, name)()
        if info.Has(key):
            out[name] = [round(info.Get(key, i), 6) for i in range(info.Length(key))]
    for name in ("INDEX_OF_REFRACTION", "ATTENUATION_DISTANCE"):
        key = getattr(vtkWhittedMaterialKeys, name)()
        if info.Has(key):
            out[name] = round(info.Get(key), 6)
    return out


gold = mirror()
check(Lib.ApplyPreset("Water", gold.GetProperty()), "Water applied")
water = keys_of(gold.GetProperty())
check(water.get("TRANSMITTANCE") == [1, 1, 1] and water.get("INDEX_OF_REFRACTION") == 1.33
      and "ATTENUATION_COLOR" in water and "REFLECTANCE" not in water, "Water keys %s" % water)
check(Lib.ApplyPreset("Gold", gold.GetProperty()), "Gold applied")
check(keys_of(gold.GetProperty()) == {"REFLECTANCE": list(GOLD)},
      "Gold replaces every key of Water: %s" % keys_of(gold.GetProperty()))
expect(mirror_scene(gold, (1, 1, 1)), GOLD, "Gold preset mirror over a white wall")
check(not Lib.ApplyPreset("Unobtainium", gold.GetProperty()), "unknown preset refused")
check(Lib.ApplyPreset("None", gold.GetProperty()) and keys_of(gold.GetProperty()) == {}, "None removes every key")

# OSPRay material library ---------------------------------------------------------------------------------------
library = {
    "family": "OSPRay", "version": "0.0",
    "materials": {
        "bottle": {"type": "glass", "doubles": {"eta": [1.45], "attenuationColor": [0.2, 0.7, 0.3],
                                                 "attenuationDistance": [4.0]}},
        "silver": {"type": "metal", "doubles": {"eta": [0.15, 0.14, 0.13], "k": [3.7, 3.1, 2.3],
                                                "roughness": [0.1]}},
        "bronze": {"type": "alloy", "doubles": {"color": [0.9, 0.5, 0.2]}},
        "paint": {"type": "principled", "doubles": {"baseColor": [0.2, 0.4, 0.6], "metallic": [0.5],
                                                    "sheen": [0.3]}},
        "lamp": {"type": "luminous", "doubles": {"color": [1, 1, 1]}},
    }}
lib = Lib()
warnings = []
lib.AddObserver(vtkCommand.WarningEvent, lambda obj, ev: warnings.append(ev))
check(lib.ReadBuffer(json.dumps(library)), "library read")
check([lib.GetMaterialName(i) for i in range(lib.GetNumberOfMaterials())] ==
      ["bottle", "bronze", "lamp", "paint", "silver"], "library names")
check(lib.GetMaterialType("silver") == "metal", "type of silver")
p = front_quad().GetProperty()
check(lib.ApplyMaterial("bottle", p), "glass applied")
check(keys_of(p) == {"TRANSMITTANCE": [1, 1, 1], "INDEX_OF_REFRACTION": 1.45, "ATTENUATION_COLOR": [0.2, 0.7, 0.3],
                     "ATTENUATION_DISTANCE": 4.0}, "glass keys %s" % keys_of(p))
n_warn = len(warnings)
check(lib.ApplyMaterial("silver", p), "metal applied")
f0 = [round(((n - 1) ** 2 + k ** 2) / ((n + 1) ** 2 + k ** 2), 6) for n, k in zip((0.15, 0.14, 0.13), (3.7, 3.1, 2.3))]
check(keys_of(p) == {"REFLECTANCE": f0}, "metal: normal-incidence reflectance %s == %s" % (keys_of(p), f0))
check(len(warnings) == n_warn + 1, "metal: roughness warned about")
# principled takes VTK's PBR rule: metallic x baseColor + (1 - metallic) x F0(ior 1.5 = 0.04), x (1 - roughness 0)
paint = [round(0.5 * b + 0.5 * 0.04, 6) for b in (0.2, 0.4, 0.6)]
check(lib.ApplyMaterial("paint", p) and keys_of(p) == {"REFLECTANCE": paint}
      and [round(c, 6) for c in p.GetDiffuseColor()] == [0.2, 0.4, 0.6],
      "principled: metallic x baseColor + (1 - metallic) x F0: %s == %s" % (keys_of(p), paint))
check(len(warnings) == n_warn + 2, "principled: sheen warned about")
check(not lib.ApplyMaterial("lamp", p) and keys_of(p) == {"REFLECTANCE": paint},
      "luminous: not applied, property unchanged")
check(not lib.ReadBuffer('{"family": "other", "materials": {}}'), "not an OSPRay library: refused")
bronze = mirror()
check(lib.ApplyMaterial("bronze", bronze.GetProperty()), "alloy applied")
# kr = (0.9, 0.5, 0.2) leaves the lit white body 1 - 0.9 = 0.1; the headlight meets the quad at 45 degrees
body = 0.1 * math.cos(math.radians(45))
expect(mirror_scene(bronze, (1, 1, 1)), [c + body for c in (0.9, 0.5, 0.2)],
       "alloy mirror over a white wall: kr x wall + (1 - max kr) x lit body")

if failures:
    print("%d check(s) failed" % len(failures))
    sys.exit(1)
print("all material checks passed")
