"""Material presets look like their names on ParaView's default scene set-up: a new Whitted view as ParaView makes
it (default background (0.32, 0.34, 0.43) from the colour palette, default light kit, no scene light), a Sphere
with its defaults shown as "Whitted Surface" above a light-grey floor, and the Material Preset set, nothing else.

    pvbatch test_presets.py --plugin P --tmp DIR

What a user must see, per preset (numbers are 0-255; "sphere" = the sphere's pixels, found as the pixels that change
when the sphere is hidden; "upper"/"lower" = its upper and lower thirds; "bg" = the background next to it):
  every preset but None: the key light's highlight, a sphere pixel at least 60 above the brightest background or
      floor pixel seen through / in the sphere without the highlight (the same preset rendered with the view's
      light kit dimmed to 0: no light, no highlight) -- Glass and Mirror would otherwise not show at all
  Glass: the highlight; the refracted floor shows upside down (the sphere's upper third brighter than its lower third);
      a rim brighter than the centre over the floor (Fresnel: at grazing incidence the ball mirrors the floor; measured
      1.155); alone and without lights on the uniform background the ball vanishes (kr + kt = 1: reflection and
      refraction see the same colour, an analytic value: 2 of 18155 pixels more than 2/255 off), which is why no
      rim shows there
  Water: a blue-green tint: the sphere's upper third has a lower red/blue ratio than the background it refracts
  Gold, Copper: a warm tint: red/blue of the sphere's upper third (reflecting the bluish background) above 1.5
  Mirror, Chrome: the floor mirrored: the lower third (reflecting the floor) brighter than the upper third
      (reflecting the background), by at least 20
The Representation panel: choosing a preset writes its values into the Whitted fields, and None gives back the
user's own values (vtkSMWhittedSurfaceRepresentationProxy; tested in test_preset_panel.py).
"""
import os
import sys

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import whitted_pvtest as wt  # noqa: E402

args = wt.parse_args(tmp=True)

import paraview.simple  # noqa: E402
from paraview.simple import CreateView, Hide, Plane, Show, Sphere  # noqa: E402

wt.load_plugin(args.plugin)
check = wt.Checks()
SIZE = [240, 240]

view = CreateView("WhittedRayTraceView")  # ParaView's defaults: palette background, light kit
view.ViewSize = SIZE
view.OrientationAxesVisibility = 0
floor = Show(Plane(Origin=[-4, -0.6, 4], Point1=[4, -0.6, 4], Point2=[-4, -0.6, -4]), view)
floor.DiffuseColor = [0.9, 0.9, 0.9]
source = Sphere(ThetaResolution=96, PhiResolution=48)
sphere = Show(source, view)
sphere.Representation = "Whitted Surface"
paraview.simple._DisableFirstRenderCameraReset()
view.CameraPosition = [0.0, 0.6, 3.2]
view.CameraFocalPoint = [0.0, -0.05, 0.0]
view.CameraViewUp = [0.0, 1.0, 0.0]
print("background %s, light kit %d, key light intensity %.2f" % (view.Background, view.UseLight,
                                                                  view.KeyLightIntensity))
check(np.allclose(view.Background, [0.32, 0.34, 0.43], atol=0.011) and view.UseLight == 1,
      "ParaView's default background and light kit")

Hide(source, view)
empty = wt.screenshot(view, os.path.join(args.tmp, "presets_empty.png"), SIZE)
Show(source, view)
plain = wt.screenshot(view, os.path.join(args.tmp, "presets_none.png"), SIZE)
mask = np.abs(plain - empty).max(axis=2) > 0
ys, xs = np.nonzero(mask)
top, bottom = ys.max(), ys.min()  # rows bottom first
third = (top - bottom) / 3.0
inner = mask & (np.abs(xs.mean() - np.arange(SIZE[0]))[None, :] < 0.6 * (xs.max() - xs.min()) / 2)
rows = np.arange(SIZE[1])[:, None]
upper = inner & (rows > top - third)
lower = inner & (rows < bottom + third)
bg = empty[upper].mean(axis=0)
print("sphere: %d pixels; background behind its upper third %s" % (mask.sum(), np.round(bg, 1)))


def render(preset, name):
    sphere.MaterialPreset = preset
    return wt.screenshot(view, os.path.join(args.tmp, "presets_%s_%s.png" % (preset.lower(), name)), SIZE).astype(
        float)


# The sphere alone (floor hidden), as a new user tries it: a preset without a body colour (kr or kt 1 in some
# channel) shows only what it reflects or refracts, the plain background, plus its highlight
Hide(floor.Input, view)
Hide(source, view)
background = wt.screenshot(view, os.path.join(args.tmp, "presets_background.png"), SIZE)
Show(source, view)
alone = {}
for preset in ("Glass", "Water", "Mirror", "Chrome", "Gold", "Copper"):
    alone[preset] = render(preset, "alone")
    highlight = float(alone[preset][mask].max() - background.max())
    print("%-8s alone: brightest sphere pixel %.0f above the background" % (preset, highlight))
    check(highlight >= 60, "%s: the light kit's highlight (%.0f >= 60 above the background)" % (preset, highlight))
# Why a glass ball shows no brighter rim there: with kr + kt = 1 and no absorption, Fresnel only moves weight between
# the reflected and the refracted ray, and on a uniform background both see the same colour, so without the light
# kit (no highlight) the ball must vanish: every sphere pixel equals the background (an analytic value)
view.UseLight = 0
unlit = render("Glass", "unlit")
view.UseLight = 1
off_bg = np.abs(unlit[mask] - background[mask]).max(axis=1)
print("Glass alone without lights: sphere pixels off the background: max %.0f, %d of %d by more than 2" % (
    off_bg.max(), int((off_bg > 2).sum()), int(mask.sum())))
check(float((off_bg > 2).mean()) <= 0.001, "Glass alone without lights: the ball vanishes into the uniform "
      "background (%d of %d pixels more than 2/255 off)" % (int((off_bg > 2).sum()), int(mask.sum())))
Show(floor.Input, view)

# Over the floor; each tint against the untinted preset of the same optics at the same pixels
over = {}
for preset in ("Glass", "Water", "Mirror", "Chrome", "Gold", "Copper"):
    over[preset] = render(preset, "floor")
    up, low = over[preset][upper].mean(axis=0), over[preset][lower].mean(axis=0)
    print("%-8s over the floor: upper third %s, lower third %s" % (preset, np.round(up, 1), np.round(low, 1)))


def red_blue(img, region):
    c = img[region].mean(axis=0)
    return c[0] / c[2]


check(over["Glass"][upper].mean() > over["Glass"][lower].mean(),
      "Glass: the refracted floor upside down (upper third %.1f > lower third %.1f)" % (
          over["Glass"][upper].mean(), over["Glass"][lower].mean()))
# Over the floor the rim is brighter than the centre: at grazing incidence Fresnel reflects most of the light, and
# there the ball mirrors the bright floor and its surroundings (rim: 0.85-0.97 of the radius; centre: within 0.5)
yy, xx = np.mgrid[0:SIZE[1], 0:SIZE[0]]
radial = np.hypot(yy - ys.mean(), xx - xs.mean()) / ((xs.max() - xs.min()) / 2.0)
rim, centre = mask & (radial > 0.85) & (radial < 0.97), mask & (radial < 0.5)
rim_ratio = over["Glass"][rim].mean() / over["Glass"][centre].mean()
check(rim_ratio >= 1.08, "Glass over the floor: a brighter rim, rim/centre %.3f (>= 1.08; 1.000 without lights on a "
      "uniform background, above)" % rim_ratio)
tint = red_blue(over["Water"], inner) / red_blue(over["Glass"], inner)
check(tint < 0.95, "Water: blue-green tint, red/blue %.3f x that of Glass (< 0.95)" % tint)
for metal in ("Gold", "Copper"):
    tint = red_blue(over[metal], inner) / red_blue(over["Mirror"], inner)
    check(tint > 1.5, "%s: warm tint, red/blue %.2f x that of Mirror (> 1.5)" % (metal, tint))
for mirror in ("Mirror", "Chrome"):
    seen = float(np.abs(over[mirror][lower] - alone[mirror][lower]).max(axis=1).mean())
    check(seen > 20, "%s: the floor mirrored (its lower third changes by %.1f > 20 with the floor shown)" % (
        mirror, seen))
check.finish("test_presets")
sys.stdout.flush()
os._exit(0)
