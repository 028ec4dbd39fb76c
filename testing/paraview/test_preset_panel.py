"""The Representation panel shows what a Material Preset sets: choosing a preset writes its values into the Whitted
fields (Reflectance, Reflectance Color, Transmittance, Index Of Refraction, Attenuation Color and Distance), which is
what the panel, Python and a saved state show.

    pvbatch test_preset_panel.py --plugin P --tmp DIR

Checks (the oracle for "what a preset sets" is the renderer, not the proxy: the material keys the representation puts
on the actor's vtkProperty with the preset chosen must equal the keys a second sphere gets from the fields alone,
preset None, set to the values shown):
  - for every preset, the fields shown render exactly as the preset (equal keys), and differ from the defaults for
    every preset but None (Glass shows Transmittance 1 and Index Of Refraction 1.5, not 0 and 1);
  - presets tried and dropped: None gives back the user's own fields (Transmittance 0.9);
  - a field edited away from the preset switches the preset to None and keeps the other preset values (Glass, then
    Index Of Refraction 1.4: Transmittance 1, index 1.4, rendered so);
  - a saved state loads with its preset and its fields, and a state whose fields were saved at their defaults with a
    preset chosen (as before the fields followed presets) shows the preset's fields after loading.
"""
import os
import re
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import whitted_pvtest as wt  # noqa: E402

args = wt.parse_args(tmp=True)

import paraview.simple as pvs  # noqa: E402

wt.load_plugin(args.plugin)
check = wt.Checks()
FIELDS = ["Reflectance", "ReflectanceColor", "Transmittance", "IndexOfRefraction", "AttenuationColor",
          "AttenuationDistance"]
DEFAULTS = {"Reflectance": [0.0], "ReflectanceColor": [1.0, 1.0, 1.0], "Transmittance": [0.0],
            "IndexOfRefraction": [1.0], "AttenuationColor": [1.0, 1.0, 1.0], "AttenuationDistance": [1.0]}
PRESETS = ["Glass", "Water", "Mirror", "Chrome", "Gold", "Copper", "Plastic"]


def rendered(display):
    """The keys as the pass reads them: a missing key is its default (no reflectance, index 1, no absorption; a
    missing TRANSMITTANCE means 1 - Opacity and stays missing), a scalar colour is grey."""
    keys = {"REFLECTANCE": [0.0] * 3, "INDEX_OF_REFRACTION": [1.0], "ATTENUATION_COLOR": [1.0] * 3,
            "ATTENUATION_DISTANCE": [1.0]}
    for name, v in wt.material_keys(display).items():
        keys[name] = v * 3 if len(v) == 1 and name in ("REFLECTANCE", "TRANSMITTANCE", "ATTENUATION_COLOR") else v
    return keys


def fields(display):
    out = {}
    for name in FIELDS:
        v = getattr(display, name)
        out[name] = [round(float(x), 9) for x in (v if hasattr(v, "__len__") else [v])]
    return out


def set_fields(display, values):
    for name, v in values.items():
        display.SetPropertyWithName(name, v if len(v) > 1 else v[0])


view = wt.make_view([64, 64])
sphere = pvs.Show(pvs.Sphere(), view)
sphere.Representation = "Whitted Surface"
twin = pvs.Show(pvs.Sphere(Center=[3, 0, 0]), view)  # the fields alone, preset None
twin.Representation = "Whitted Surface"
sphere.Transmittance = 0.9  # the user's own material
pvs.Render(view)
user_keys = rendered(sphere)

for name in PRESETS:
    sphere.MaterialPreset = name
    shown = fields(sphere)
    set_fields(twin, shown)
    pvs.Render(view)
    check(twin.MaterialPreset == "None", "%s: the twin keeps preset None" % name)
    check(rendered(sphere) == rendered(twin), "%s: the fields shown %s render as the preset (keys %s vs %s)"
          % (name, shown, rendered(sphere), rendered(twin)))
    check(shown != DEFAULTS, "%s: the panel shows the preset's values, not the defaults (%s)" % (name, shown))

sphere.MaterialPreset = "Glass"
check(sphere.Transmittance == 1.0 and abs(sphere.IndexOfRefraction - 1.5) < 1e-12 and sphere.Reflectance == 0.0,
      "Glass shows Transmittance 1, Index Of Refraction 1.5, Reflectance 0 (%s)" % fields(sphere))

sphere.MaterialPreset = "None"
pvs.Render(view)
check(abs(sphere.Transmittance - 0.9) < 1e-12 and sphere.IndexOfRefraction == 1.0,
      "None gives back the user's fields (Transmittance %s, index %s)" % (sphere.Transmittance,
                                                                          sphere.IndexOfRefraction))
check(rendered(sphere) == user_keys, "None renders the user's material again (%s vs %s)"
      % (rendered(sphere), user_keys))

sphere.MaterialPreset = "Glass"
sphere.IndexOfRefraction = 1.4
pvs.Render(view)
check(sphere.MaterialPreset == "None", "a field edited away from Glass switches the preset to None (%s)"
      % sphere.MaterialPreset)
expected = {"REFLECTANCE": [0.0] * 3, "TRANSMITTANCE": [1.0] * 3, "INDEX_OF_REFRACTION": [1.4],
            "ATTENUATION_COLOR": [1.0] * 3, "ATTENUATION_DISTANCE": [1.0]}
check(rendered(sphere) == expected, "the edit starts from Glass's values: keys %s" % rendered(sphere))
sphere.MaterialPreset = "None"
check(sphere.Transmittance == 1.0 and abs(sphere.IndexOfRefraction - 1.4) < 1e-12,
      "choosing None after an edit keeps the edited fields (%s)" % fields(sphere))

# States: one saved with Gold, and the same state with the fields reset to their defaults (a state saved before
# the fields followed presets)
sphere.MaterialPreset = "Gold"
gold = fields(sphere)
state = os.path.join(args.tmp, "preset_panel.pvsm")
pvs.SaveState(state)
text = open(state).read()
old_state = os.path.join(args.tmp, "preset_panel_old.pvsm")
marker = 'name="Reflectance" id="'
check(marker in text, "the state holds the Reflectance field")
with open(old_state, "w") as f:
    f.write(re.sub(r'(<Property name="Reflectance" id="[^"]*" number_of_elements="1">\s*<Element index="0" value=")'
                   r'[^"]*"', r'\g<1>0"', text))
for path, what in ((state, "saved state"), (old_state, "old state with default fields")):
    pvs.ResetSession()
    wt.load_plugin(args.plugin)
    pvs.LoadState(path)
    reps = [r for r in pvs.GetRepresentations().values() if r.GetProperty("MaterialPreset") is not None]
    loaded = [r for r in reps if r.MaterialPreset == "Gold"]
    check(len(loaded) == 1, "%s: one Gold sphere (%d)" % (what, len(loaded)))
    if loaded:
        check(fields(loaded[0]) == gold, "%s: Gold's fields after loading %s vs %s" % (what, fields(loaded[0]), gold))

check.finish("preset_panel")
