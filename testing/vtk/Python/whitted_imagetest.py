"""Shared helpers of the Python image tests: an offscreen render of one renderer and its framebuffer as numpy."""
import numpy as np
from vtkmodules.vtkRenderingCore import vtkRenderWindow, vtkWindowToImageFilter
import vtkmodules.vtkRenderingOpenGL2  # noqa: F401
from vtkmodules.util.numpy_support import vtk_to_numpy


def grab(window, rerender=True):
    """The window's back buffer as a float array of RGB in 0..255, rows bottom to top; rerender=False reads the
    last frame as it is (no new frame)."""
    f = vtkWindowToImageFilter()
    f.SetInput(window)
    f.ReadFrontBufferOff()
    f.SetShouldRerender(rerender)
    f.Update()
    image = f.GetOutput()
    w, h, _ = image.GetDimensions()
    return vtk_to_numpy(image.GetPointData().GetScalars()).reshape(h, w, -1)[:, :, :3].astype(float)


def offscreen_render(ren, size, render_pass=None, after=None):
    """Renders ren alone in an offscreen size x size window without multisampling, through render_pass if given,
    and returns (RGB image, after(render_pass) or None); after runs while the frame is still the pass's last one.
    The renderer is detached from the pass and the window afterwards, so it can be rendered again."""
    win = vtkRenderWindow()
    win.SetOffScreenRendering(1)
    win.SetMultiSamples(0)
    win.SetSize(size, size)
    win.AddRenderer(ren)
    if render_pass is not None:
        ren.SetPass(render_pass)
    win.Render()
    image = grab(win)
    extra = after(render_pass) if after else None
    if render_pass is not None:
        ren.SetPass(None)
    win.RemoveRenderer(ren)
    win.Finalize()
    return image, extra


def edge_mask(rgb):
    """Pixels of a reddish edge colour (red above 120, blue below half of it) in an RGB image."""
    return (rgb[:, :, 0] > 120) & (rgb[:, :, 2] < 0.5 * rgb[:, :, 0])


def near(mask, other):
    """Share of mask's pixels within one pixel (8-neighbourhood) of a pixel of other (boolean images)."""
    grown = other.copy()
    for dy in (-1, 0, 1):
        for dx in (-1, 0, 1):
            grown |= np.roll(np.roll(other, dy, 0), dx, 1)
    return (mask & grown).sum() / max(1, mask.sum())


def grab_with_depth(window):
    """The window's back buffer as int RGB (0..255) and its depth buffer, both numpy arrays, rows bottom to top."""
    from vtkmodules.vtkCommonCore import vtkFloatArray

    rgb = grab(window).astype(int)
    h, w = rgb.shape[:2]
    z = vtkFloatArray()
    window.GetZbufferData(0, 0, w - 1, h - 1, z)
    return rgb, vtk_to_numpy(z).reshape(h, w).copy()


def quad_actor(origin, point1, point2, color, reflectance=None):
    """A plane source's quad as an actor of the given colour; reflectance sets the Whitted REFLECTANCE key."""
    from vtkmodules.vtkFiltersSources import vtkPlaneSource
    from vtkmodules.vtkRenderingCore import vtkActor, vtkPolyDataMapper

    plane = vtkPlaneSource()
    plane.SetOrigin(*origin)
    plane.SetPoint1(*point1)
    plane.SetPoint2(*point2)
    mapper = vtkPolyDataMapper()
    mapper.SetInputConnection(plane.GetOutputPort())
    actor = vtkActor()
    actor.SetMapper(mapper)
    actor.GetProperty().SetColor(*color)
    if reflectance is not None:
        from whitted import vtkWhittedPass

        actor.GetProperty().GetInformation().Set(vtkWhittedPass.REFLECTANCE(), [reflectance], 1)
    return actor


def light_and_camera(ren, light_position, eye, focal):
    """A positional light shining every way from light_position, the test background, a camera at eye looking at
    focal (clipping range reset)."""
    from vtkmodules.vtkRenderingCore import vtkLight

    light = vtkLight()
    light.SetPositional(True)
    light.SetPosition(*light_position)
    light.SetConeAngle(180)
    ren.AddLight(light)
    ren.SetBackground(0.2, 0.22, 0.3)
    camera = ren.GetActiveCamera()
    camera.SetPosition(*eye)
    camera.SetFocalPoint(*focal)
    ren.ResetCameraClippingRange()
