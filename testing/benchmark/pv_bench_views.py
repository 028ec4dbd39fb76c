"""What the pvbatch benchmark scripts (pv_view_bench.py, pv_time_bench.py) share: ParaView's Render View and the
Whitted Ray Trace view in one process, warmed up, and one camera for both."""


def make_views(plugin, size, first, all_lights=False):
    """Loads the plugin and creates both views at size, keyed "render" and "whitted" (the Whitted view at its
    defaults: shadows from the light kit's key light only), with all_lights also "whitted_all" (every light of
    the light kit casts shadows: ShadowsFromBrightestLightOnly 0); returns (views, order) with order the view
    names, `first` first. Each view renders a small sphere once (window, OpenGL context, shaders), then hides
    it, so nothing timed later pays for them."""
    from paraview.simple import CreateView, Hide, LoadPlugin, Render, Show, Sphere

    LoadPlugin(plugin, remote=False, ns=globals())
    views = {"render": CreateView("RenderView"), "whitted": CreateView("WhittedRayTraceView")}
    if all_lights:
        views["whitted_all"] = CreateView("WhittedRayTraceView")
        views["whitted_all"].ShadowsFromBrightestLightOnly = 0
    order = [first] + [v for v in views if v != first]
    for v in views.values():
        v.ViewSize = list(size)
    warm = Sphere()
    for name in order:
        Show(warm, views[name])
        Render(views[name])
        Hide(warm, views[name])
    return views, order


def share_camera(views, source):
    """Gives every view the camera that resets the Render View's current one to the bounds of source's data (what
    ParaView's ResetCamera computes: vtkRenderer::ResetCamera on the shown data's bounds), without rendering or
    updating any view. paraview.simple.ResetCamera renders the view it resets: done on the Render View, that render
    delivered and drew the new data untimed, so its timed "first" frame was a second frame of data already on the
    GPU, while the Whitted view's was a true first frame. source must be up to date (its data information is read)."""
    from vtkmodules.vtkRenderingCore import vtkRenderer

    ren = vtkRenderer()  # no window: aspect 1; the same camera as any view at least as wide as high
    cam = ren.GetActiveCamera()
    start = views["render"].GetActiveCamera()
    cam.SetPosition(start.GetPosition())
    cam.SetFocalPoint(start.GetFocalPoint())
    cam.SetViewUp(start.GetViewUp())
    cam.SetViewAngle(start.GetViewAngle())
    ren.ResetCamera(source.GetDataInformation().GetBounds())
    for v in views.values():
        c = v.GetActiveCamera()
        c.SetPosition(cam.GetPosition())
        c.SetFocalPoint(cam.GetFocalPoint())
        c.SetViewUp(cam.GetViewUp())
        c.SetViewAngle(cam.GetViewAngle())


def append_csv(path, rows):
    """Appends rows (dicts with the same keys) to the CSV file at path, with a header if the file is new."""
    import csv
    import os

    new = not os.path.exists(path) or os.path.getsize(path) == 0
    with open(path, "a", newline="") as f:
        w = csv.DictWriter(f, fieldnames=list(rows[0].keys()))
        if new:
            w.writeheader()
        w.writerows(rows)
