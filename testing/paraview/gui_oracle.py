"""Independent checks of the GUI playback tests (paraview.gui, paraview.gui.selection, paraview.gui.volume).

The playbacks (gui_whitted.xml.in, gui_selection.xml.in, gui_volume.xml.in) build their scene with the GUI's menus, panels and mouse,
then type one command into View > Python Shell: gui_oracle.main(kind, result), which checks the view the GUI made
against ParaView's own Render View, made here with the same sources, colouring, light kit, background and camera,
and writes "ok" or the failures to result (run_gui_test.py fails the test unless it reads "ok"). The playback's
committed baseline stays beside it as a change guard.

- "whitted": the Whitted view with its effects off (no shadows, reflections or refractions) equals the Render View's
  raster on the pixels the Whitted Surface sphere does not cover and away from edges (RENDER_VIEW tolerance); with
  its effects on, those pixels only darken (the sphere's shadow on the plane, which must be there).
- "volume": the Wavelet the GUI shows as Volume is traced (the frame report: one volume traced, no prop left to
  OpenGL), the mirror floor shows it (pixels outside its direct footprint change when it is shown: only its
  reflection can change them), and a colour-map edit converts no grid, updates one transfer function and changes
  the reflection in the next frame (ParaView's Render View cannot reflect: paraview.volume compares the volume itself
  with it, in pvbatch).
- "selection": the cells the rubber band selected in the Whitted view (the hardware selector) lie between the
  Render View's selections with the same rectangle shrunk and grown by 2 pixels (rounding of the playback's
  fractional mouse positions), and the highlighted image with effects off equals the Render View's raster of the
  same selection away from edges.
"""
import os
import traceback

# The playback's rubber band, as fractions of the view (gui_selection.xml.in: press at (0.38, 0.38), release at
# (0.62, 0.62), Qt's y down): the same fractions with VTK's y up, as the band is symmetric
BAND = (0.38, 0.62)
# Pixels compared (geometry off edges): at least this many (else the oracle says little). Measured: 2147 (gui,
# 300x300), 9965 (gui.selection, the GUI's view size)
MIN_PIXELS = 1000


LOOK = ("CameraPosition", "CameraFocalPoint", "CameraViewUp", "CameraViewAngle", "CameraParallelScale",
        "CameraParallelProjection", "OrientationAxesVisibility", "UseColorPaletteForBackground", "BackgroundColorMode",
        "Background", "Background2", "UseLight", "LightSwitch")


def _copy_look(src_view, dst_view):
    """Copies the camera, background and light kit switches; returns the properties that could not be copied."""
    skipped = []
    for prop in LOOK:
        try:
            setattr(dst_view, prop, getattr(src_view, prop))
        except (AttributeError, ValueError):
            skipped.append(prop)
    return skipped


def _clone(src):
    """A new source proxy with src's properties (the Render View shows clones, so that selecting there leaves the
    GUI's sources and their selections untouched)."""
    from paraview import servermanager

    pxm = servermanager.ProxyManager()
    smproxy = pxm.SMProxyManager.NewProxy(src.SMProxy.GetXMLGroup(), src.SMProxy.GetXMLName())
    smproxy.Copy(src.SMProxy)
    smproxy.UpdateVTKObjects()
    clone = servermanager._getPyProxy(smproxy)
    pxm.RegisterProxy("sources", "oracle_" + src.SMProxy.GetXMLName(), clone)
    return clone


def _render_view_of(view, size, report):
    """A Render View in a layout of its own (the GUI renders a view only in a layout), showing clones of view's
    shown sources with their colouring, and view's look. Returns (layout, view, {name: (clone, GUI display, Render
    View display)}, {GUI source: clone})."""
    from paraview.simple import AssignViewToLayout, CreateLayout, CreateView, GetDisplayProperties, GetSources, Show

    layout = CreateLayout("oracle")
    rv = CreateView("RenderView")
    AssignViewToLayout(view=rv, layout=layout, hint=0)
    rv.ViewSize = list(size)
    rv.EnableRenderOnInteraction = 0
    skipped = _copy_look(view, rv)
    report(True, "the view's look copied (not copied: %s)" % (", ".join(skipped) or "none"))
    shown, clones = {}, {}
    for (name, _), src in list(GetSources().items()):
        wd = GetDisplayProperties(src, view=view)
        if not wd.Visibility:
            continue
        clone = _clone(src)
        rd = Show(clone, rv)
        rd.Representation = "Surface"
        rd.ColorArrayName = [wd.ColorArrayName.GetAssociation(), wd.ColorArrayName.GetArrayName()]
        rd.LookupTable = wd.LookupTable
        rd.DiffuseColor = wd.DiffuseColor
        rd.AmbientColor = wd.AmbientColor
        rd.Specular = wd.Specular
        shown[name] = (clone, wd, rd)
        clones[src] = clone
    return layout, rv, shown, clones


def _drop(layout, rv, clones):
    from paraview.simple import Delete, RemoveLayout

    RemoveLayout(layout)
    Delete(rv)
    for clone in clones.values():
        Delete(clone)


def _compared(pvt, rv, shown, raster, hidden, tmp):
    """The pixels where raster shows geometry, off the sources in hidden (dilated by 2) and off colour edges:
    background pixels would only dilute a wrong shading among pixels that cannot be wrong."""
    import numpy as np
    from paraview.simple import Hide, Show

    for src in hidden:
        Hide(src, rv)
    without = pvt.screenshot(rv, os.path.join(tmp, "renderview_without.png"), raster.shape[1::-1])
    for src, _, _ in shown.values():
        Hide(src, rv)
    empty = pvt.screenshot(rv, os.path.join(tmp, "renderview_empty.png"), raster.shape[1::-1])
    for src, _, rd in shown.values():
        Show(src, rv)
    geometry = np.abs(raster - empty).max(axis=2) > 0
    return geometry & pvt.off_props_and_edges(raster, without)


def _effects(view, on=None, saved=None):
    """Switches the view's shadows, reflections and refractions all on or off and returns what they were; with
    saved, puts them back."""
    names = ("Shadows", "Reflections", "Refractions")
    before = [getattr(view, n) for n in names]
    for n, v in zip(names, saved if saved is not None else [int(on)] * 3):
        setattr(view, n, v)
    return before


def check_whitted(tmp, report):
    import numpy as np
    import whitted_pvtest as pvt
    from paraview.simple import GetActiveView, SetActiveView

    view = GetActiveView()
    report(view.GetXMLName() == "WhittedRayTraceView", "the active view is a Whitted view (%s)" % view.GetXMLName())
    size = (300, 300)
    legends = _hide_legends(view)  # 2D annotations laid out for the GUI's view size: not the tracer's
    on = pvt.screenshot(view, os.path.join(tmp, "gui_whitted_on.png"), size)
    saved = _effects(view, False)
    off_png = os.path.join(tmp, "gui_whitted_off.png")
    off = pvt.screenshot(view, off_png, size)
    _effects(view, saved=saved)
    layout, rv, shown, clones = _render_view_of(view, size, report)
    raster_png = os.path.join(tmp, "gui_whitted_renderview.png")
    raster = pvt.screenshot(rv, raster_png, size)
    spheres = [src for (src, wd, _) in shown.values() if wd.Representation == "Whitted Surface"]
    report(len(spheres) == 1 and len(shown) == 2, "the GUI showed a Whitted Surface and one more source (%d, %d)"
           % (len(spheres), len(shown)))
    compared = _compared(pvt, rv, shown, raster, spheres, tmp)
    report(compared.sum() >= MIN_PIXELS, "%d pixels compared (the plane off the Whitted Surface and off edges)"
           % compared.sum())
    ok, bad = pvt.compare_image(off_png, raster_png, tmp, mask=compared, **pvt.RENDER_VIEW)
    report(ok, "effects off: the Whitted view equals the Render View there (%.4f%% differ)" % (100 * bad))
    lighter = int((np.where(compared, (on - off).max(axis=2), 0) > pvt.EFFECTS_LIGHTER).sum())
    darker = int((np.where(compared, (off - on).max(axis=2), 0) > 8).sum())
    report(lighter == 0, "effects on: no compared pixel lighter than with effects off (%d)" % lighter)
    report(darker >= 100, "effects on: the sphere's shadow darkens compared pixels by more than 8/255 (%d)" % darker)
    _drop(layout, rv, clones)
    for bar in legends:
        bar.Visibility = 1
    SetActiveView(view)


def _volume_report(view):
    """(volumes traced, grids converted, transfer updates, props drawn by OpenGL) of the view's last frame, or
    None."""
    import re

    view.UpdatePropertyInformation()
    m = re.search(r"(\d+) volumes traced \((\d+) converted, (\d+) transfer updates\), (\d+) props drawn by OpenGL",
                  view.GetProperty("LastFrameReport").GetData())
    return tuple(int(g) for g in m.groups()) if m else None


def check_volume(tmp, report):
    import numpy as np
    import whitted_pvtest as pvt
    from paraview.simple import (GetActiveView, GetColorTransferFunction, GetDisplayProperties, GetSources, Hide,
                                 Render, Show)

    view = GetActiveView()
    report(view.GetXMLName() == "WhittedRayTraceView", "the active view is a Whitted view (%s)" % view.GetXMLName())
    size = (300, 300)
    legends = _hide_legends(view)
    sources = {src.SMProxy.GetXMLName(): src for src in GetSources().values()}
    wavelet, floor = sources.get("RTAnalyticSource"), sources.get("PlaneSource")
    report(wavelet is not None and floor is not None, "the GUI made a Wavelet and a Plane (%s)" % sorted(sources))
    wd = GetDisplayProperties(wavelet, view=view)
    report(wd.Representation == "Volume", "the Wavelet is shown as Volume (%s)" % wd.Representation)

    def shot(name):
        return pvt.screenshot(view, os.path.join(tmp, "gui_volume_%s.png" % name), size)

    with_volume = shot("mirror")
    frame = _volume_report(view)
    report(frame is not None and frame[0] == 1 and frame[3] == 0, "the volume is traced, nothing drawn by OpenGL "
           "(frame report: %s)" % (frame,))
    # Its direct footprint: the volume alone against nothing shown, dilated by 3 pixels
    Hide(floor, view)
    alone = shot("alone")
    Hide(wavelet, view)
    empty = shot("empty")
    Show(wavelet, view)
    footprint = pvt.dilate(np.abs(alone - empty).max(axis=2) > 3, 3)
    report(footprint.sum() > 2000, "the volume covers %d pixels" % footprint.sum())
    Show(floor, view)
    Hide(wavelet, view)
    without = shot("mirror_hidden")
    Show(wavelet, view)
    reflection = (np.abs(with_volume - without).max(axis=2) > 8) & ~footprint
    report(reflection.sum() > 1000, "the mirror shows the volume: %d pixels outside its footprint change when it is "
           "shown" % reflection.sum())
    # A colour-map edit: the next frame updates the transfer function only, and the reflection changes
    shot("settled")
    lut = GetColorTransferFunction(wd.ColorArrayName.GetArrayName())
    lut.ApplyPreset("Viridis (matplotlib)", True)
    Render(view)  # the next frame (a screenshot renders more than one)
    frame = _volume_report(view)
    edited = shot("edited")
    report(frame is not None and frame[1] == 0 and frame[2] == 1, "the colour-map edit converts no grid and updates "
           "one transfer function (frame report: %s)" % (frame,))
    changed = int(((np.abs(edited - with_volume).max(axis=2) > 8) & reflection).sum())
    report(changed > 0.3 * reflection.sum(), "the edit shows in the mirror in the next frame (%d of %d reflection "
           "pixels change)" % (changed, reflection.sum()))
    # Shade (the Volume Rendering section's checkbox): still traced, a transfer update, and lit by the view's light
    # kit in the mirror too
    wd.Shade = 1
    Render(view)
    frame = _volume_report(view)
    shaded = shot("shaded")
    report(frame is not None and frame[0] == 1 and frame[3] == 0 and frame[1] == 0 and frame[2] == 1,
           "Shade on: the volume is still traced, one transfer update, no grid converted (frame report: %s)" % (frame,))
    changed = int(((np.abs(shaded - edited).max(axis=2) > 8) & reflection).sum())
    report(changed > 0.3 * reflection.sum(), "the shaded volume shows in the mirror (%d of %d reflection pixels "
           "change)" % (changed, reflection.sum()))
    wd.Shade = 0
    for bar in legends:
        bar.Visibility = 1


def _hide_legends(view):
    """Hides the colour legends shown in view; returns them (to show them again)."""
    bars = []
    for proxy in view.Representations:
        if proxy.GetXMLName() == "ScalarBarWidgetRepresentation" and proxy.Visibility:
            proxy.Visibility = 0
            bars.append(proxy)
    return bars


def _selected_cells(src):
    """Original ids of the cells selected on src's first output (its selection input)."""
    from paraview import servermanager
    from paraview.simple import Delete, ExtractSelection
    from vtkmodules.numpy_interface import dataset_adapter as dsa

    sel = src.SMProxy.GetSelectionInput(0)
    if sel is None:
        return set()
    ex = ExtractSelection(Input=src, Selection=servermanager._getPyProxy(sel))
    data = servermanager.Fetch(ex)
    Delete(ex)
    ids = dsa.WrapDataObject(data).CellData["vtkOriginalCellIds"]
    return set(int(i) for i in ids) if ids is not None and not isinstance(ids, dsa.VTKNoneArray) else set()


def check_selection(tmp, report):
    import whitted_pvtest as pvt
    from paraview.simple import (ClearSelection, Delete, GetActiveSource, GetActiveView, IDSelectionSource,
                                 SelectSurfaceCells, SetActiveSource, SetActiveView)

    view = GetActiveView()
    src = GetActiveSource()
    report(view.GetXMLName() == "WhittedRayTraceView", "the active view is a Whitted view (%s)" % view.GetXMLName())
    gui_cells = _selected_cells(src)
    w, h = [int(x) for x in view.ViewSize]
    size = (w, h)
    report(True, "the view is %d x %d pixels" % (w, h))
    # The Render View's selections (on the clone) with the rubber band's rectangle (pixels, origin bottom left),
    # shrunk and grown
    layout, rv, shown, clones = _render_view_of(view, size, report)
    clone = clones[src]
    pvt.screenshot(rv, os.path.join(tmp, "gui_selection_renderview_plain.png"), size)
    bands = {}
    for name, grow in (("inner", -2), ("outer", 2)):
        rect = [int(round(BAND[0] * w)) - grow, int(round(BAND[0] * h)) - grow,
                int(round(BAND[1] * w)) + grow, int(round(BAND[1] * h)) + grow]
        SetActiveSource(clone)
        SelectSurfaceCells(Rectangle=rect, View=rv)
        bands[name] = _selected_cells(clone)
        ClearSelection(clone)
    inner, outer = bands["inner"], bands["outer"]
    report(len(inner) >= 10, "the Render View selects cells in the band (%d inner, %d outer)" % (len(inner), len(outer)))
    report(inner <= gui_cells <= outer, "the Whitted view selected %d cells, between the Render View's %d and %d "
           "(missing %d, extra %d)" % (len(gui_cells), len(inner), len(outer), len(inner - gui_cells),
                                        len(gui_cells - outer)))
    # The GUI's cells selected on the clone too, highlighted in both views: effects off against the raster, away
    # from edges
    ids = IDSelectionSource(FieldType="CELL", IDs=[v for c in sorted(gui_cells) for v in (0, c)])
    clone.SMProxy.SetSelectionInput(0, ids.SMProxy, 0)
    raster_png = os.path.join(tmp, "gui_selection_renderview.png")
    raster = pvt.screenshot(rv, raster_png, size)
    saved = _effects(view, False)
    off_png = os.path.join(tmp, "gui_selection_off.png")
    pvt.screenshot(view, off_png, size)
    _effects(view, saved=saved)
    compared = _compared(pvt, rv, shown, raster, [], tmp)
    report(compared.sum() >= MIN_PIXELS, "%d pixels compared (the sphere off edges)" % compared.sum())
    magenta = ((raster[:, :, 0] > 200) & (raster[:, :, 1] < 80) & (raster[:, :, 2] > 200) & compared).sum()
    report(magenta >= 50, "the Render View draws the selection's highlight (%d pixels)" % magenta)
    ok, bad = pvt.compare_image(off_png, raster_png, tmp, mask=compared, **pvt.RENDER_VIEW)
    report(ok, "effects off: the highlighted Whitted view equals the Render View off edges (%.4f%% differ)"
           % (100 * bad))
    ClearSelection(clone)
    Delete(ids)
    _drop(layout, rv, clones)
    SetActiveView(view)
    SetActiveSource(src)


def main(kind, result):
    """Runs the checks of kind ("whitted", "selection" or "volume") and writes "ok" or the failures to result."""
    failures, log = [], []

    def report(ok, message):
        log.append(("ok    " if ok else "FAIL  ") + message)
        if not ok:
            failures.append(message)

    try:
        perturb = int(os.environ.get("WHITTED_GUI_ORACLE_PERTURB", "0"))
        if perturb:  # negative control: every 100th opaque traced pixel off by this many 8-bit steps
            from paraview.simple import GetActiveView

            GetActiveView().ShadingErrorForTesting = perturb
            log.append("negative control: ShadingErrorForTesting %d" % perturb)
        if os.environ.get("WHITTED_GUI_ORACLE_NO_REFLECTIONS"):  # negative control: the mirror cannot show anything
            from paraview.simple import GetActiveView

            GetActiveView().Reflections = 0
            log.append("negative control: the view's reflections off")
        tmp = os.path.abspath(result) + ".images"  # per result file: a test and its control may run at once
        os.makedirs(tmp, exist_ok=True)
        {"whitted": check_whitted, "selection": check_selection, "volume": check_volume}[kind](tmp, report)
    except Exception:  # noqa: BLE001 - any error is a failure of the test, written where run_gui_test.py reads it
        failures.append("exception:\n" + traceback.format_exc())
    with open(result, "w") as f:  # the verdict first (run_gui_test.py reads it), then every check
        f.write(("ok" if not failures else "FAILED: %d checks" % len(failures)) + "\n" + "\n".join(log) + "\n")
        for failure in failures:
            if failure.startswith("exception"):
                f.write(failure + "\n")
