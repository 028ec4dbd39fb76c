"""Whitted: a Whitted-style ray tracer for VTK.

    from whitted import vtkWhittedPass
    renderer.SetPass(vtkWhittedPass())
"""
# The pass derives from VTK's OpenGL rendering classes: load them (and their object factories) first
import vtkmodules.vtkRenderingCore  # noqa: F401
import vtkmodules.vtkRenderingOpenGL2  # noqa: F401

from .vtkWhitted import *  # noqa: F401,F403
