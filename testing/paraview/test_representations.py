"""Which data gets the "Whitted Surface" representation, and the material reaching the actor's vtkProperty.

    pvbatch test_representations.py --plugin P

For polygonal data, an unstructured grid, image data and a structured grid: "Whitted Surface" is offered,
Reflectance / Transmittance / IndexOfRefraction can be set by name, and they arrive on the rendered actor's
vtkProperty as vtkWhittedPass's information keys (read back through the vtkInformation's printout, since the
plugin classes have no Python wrapping); Transmittance 0 removes its key (1 - Opacity applies).
"""
import argparse
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import whitted_pvtest as wt  # noqa: E402

ap = argparse.ArgumentParser()
ap.add_argument("--plugin", required=True)
args = ap.parse_args()

from paraview.simple import (CreateView, ExtractSurface, Render, Show, Sphere, Tetrahedralize,  # noqa: E402
                             Wavelet)

wt.load_plugin(args.plugin)
view = CreateView("WhittedRayTraceView")
view.ViewSize = [200, 150]
wavelet = Wavelet(WholeExtent=[-4, 4, -4, 4, -4, 4])
sources = {
    "polygonal (vtkPolyData)": Sphere(),
    "unstructured (vtkUnstructuredGrid)": Tetrahedralize(Input=wavelet),
    "image data (vtkImageData)": wavelet,
    "surface of image data (vtkPolyData)": ExtractSurface(Input=wavelet),
}


def material_keys(display):
    rep = display.GetClientSideObject().GetActiveRepresentation()
    info = str(rep.GetActor().GetProperty().GetInformation())
    keys = {}
    for line in info.splitlines():
        line = line.strip()
        for key in ("REFLECTANCE", "TRANSMITTANCE", "INDEX_OF_REFRACTION"):
            if line.startswith(key + ":"):
                keys[key] = float(line.split(":")[1].split()[0])
    return rep.GetClassName(), keys


problems = []
for label, src in sources.items():
    d = Show(src, view)
    types = d.GetProperty("Representation").Available
    print("%-38s %s: %s" % (label, d.GetXMLName(), ", ".join(types)))
    if "Whitted Surface" not in types:
        problems.append("%s: no Whitted Surface" % label)
        continue
    d.Representation = "Whitted Surface"
    d.Reflectance = 0.5
    d.Transmittance = 0.25
    d.IndexOfRefraction = 1.33
    Render(view)
    cls, keys = material_keys(d)
    print("    active representation %s, keys %s" % (cls, keys))
    if keys != {"REFLECTANCE": 0.5, "TRANSMITTANCE": 0.25, "INDEX_OF_REFRACTION": 1.33}:
        problems.append("%s: keys %s" % (label, keys))
    d.Transmittance = 0.0
    Render(view)
    if "TRANSMITTANCE" in material_keys(d)[1]:
        problems.append("%s: Transmittance 0 left the key set" % label)
    d.Visibility = 0

if problems:
    wt.fail("; ".join(problems))
print("OK")
