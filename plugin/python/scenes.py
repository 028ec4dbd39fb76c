"""Scenes built from VTK sources, shared by the demo (whitted_demo.py) and the tests.

Every function takes a vtkRenderer, adds actors and lights, sets the background and the camera, and
returns a dict of the actors it created (by name) so callers can tweak them.
"""
from .vtkWhitted import vtkWhittedClassicScene, vtkWhittedMaterialKeys


def set_whitted(prop, reflectance=None, transmittance=None, ior=None):
    """Sets the Whitted material keys on a vtkProperty (scalars or RGB triples)."""
    info = prop.GetInformation()
    for key, value in ((vtkWhittedMaterialKeys.REFLECTANCE(), reflectance),
                       (vtkWhittedMaterialKeys.TRANSMITTANCE(), transmittance)):
        if value is None:
            continue
        values = [float(value)] if isinstance(value, (int, float)) else [float(v) for v in value]
        info.Set(key, values, len(values))
    if ior is not None:
        info.Set(vtkWhittedMaterialKeys.INDEX_OF_REFRACTION(), float(ior))


def classic_scene(renderer, resolution=48):
    """Whitted's 1980 scene: red/yellow checkerboard floor, mirror sphere, glass sphere, one point
    light (vtkWhittedClassicScene: the core's one description of the scene, also traced by the
    core's built-in "classic" scene). resolution: the spheres' phi resolution (theta twice that)."""
    scene = vtkWhittedClassicScene()
    scene.SetResolution(resolution)
    scene.AddToRenderer(renderer)
    return {"floor": scene.GetFloor(), "mirror": scene.GetMirror(), "glass": scene.GetGlass(),
            "light": scene.GetLight()}
