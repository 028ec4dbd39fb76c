"""Regression-image test of the Whitted Ray Trace view, for every way ParaView runs a script.

    pvbatch test_render.py --plugin P --baseline B --tmp DIR [options]          (builtin, also mpirun -np 2)
    pvbatch test_render.py --baseline B --tmp DIR     (no --plugin: ParaView must have loaded it, as installed)
    python3 test_render.py ... --connect 127.0.0.1:PORT [--render-on server|client]   (client of a pvserver)

Builds the shared scene (whitted_pvtest.build_scene), renders it at 400x300, saves a screenshot and
compares it with the baseline. Checks, depending on the mode:
  --connect + --render-on server: the server traces (image == builtin baseline) and the client's pass does
      no work (its view traced no frame); --render-on client: the client traces.
  --expect-ranks N: the view runs on N MPI ranks and the geometry is really split between them (a
      Process Id Scalars filter sees ids 0..N-1) -- so the image is only right if geometry is replicated;
      then renders again with ReplicateGeometry off and checks that the image changes (secondary rays
      miss the other rank's geometry), proving the replication is what makes the N-rank image correct.
  --reference R: the compositing oracle. R is the single-process (builtin pvbatch) image of the same scene by the
      same build (the ctest fixture of paraview.pvbatch / translucent / view_features writes it); this image,
      made by MPI ranks or a server, must equal it within the compositing round-off (whitted_pvtest.COMPOSITING).
  --render-view-oracle: the independent check of a single-process image. The tracer's effects off (no shadows, no
      secondary rays), the Whitted image must equal ParaView's own Render View raster of the same scene, compared
      where the effects cannot matter: outside the mirror and glass spheres (which look different by definition)
      and away from silhouettes (whitted_pvtest.compare_to_render_view). With the effects on, those pixels may only
      get darker (shadows), never lighter.
  --negative-control N: the same checks on a deliberately wrong image (vtkWhittedPass::ShadingErrorForTesting:
      N/255 more on 1% of the pixels); the test passes only if at least one image check fails.
"""
import argparse
import os
import sys
import time

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import whitted_pvtest as wt  # noqa: E402

ap = argparse.ArgumentParser()
ap.add_argument("--plugin", help="WhittedView.so to load; without it, the plugin must be loaded already (installed "
                                   "plugin, loaded through ParaView's plugins configuration)")
ap.add_argument("--baseline", required=True)
ap.add_argument("--tmp", required=True, help="folder for the test image and diffs")
ap.add_argument("--name", default="scene", help="name of the test image")
ap.add_argument("--translucent", action="store_true", help="make the box 50%% opaque")
ap.add_argument("--view-features", action="store_true",
                help="add gradient background, light kit, orientation axes, text, colour legend, parallel "
                     "projection")
ap.add_argument("--connect", help="host:port of a pvserver")
ap.add_argument("--render-on", choices=["server", "client"], default="server")
ap.add_argument("--expect-ranks", type=int, default=0)
ap.add_argument("--expect-split", type=int, default=0,
                help="the rendering rank 0 traced every N-th tile")
ap.add_argument("--reference", help="single-process image of the same scene (compositing oracle)")
ap.add_argument("--render-view-oracle", action="store_true",
                help="compare, effects off, with the Render View's raster of the same scene")
ap.add_argument("--negative-control", type=int, default=0,
                help="ShadingErrorForTesting N: the image checks must fail")
ap.add_argument("--save-only", action="store_true", help="render and save the image, check nothing (measurements)")
args = ap.parse_args()

from paraview import servermanager as sm  # noqa: E402
from paraview.simple import (Connect, GetSettingsProxy, ProcessIdScalars, Render,  # noqa: E402
                             SaveScreenshot)

if args.connect:
    host, port = args.connect.rsplit(":", 1)
    Connect(host, int(port))
    # 0: always render on the server and ship images; huge: ship geometry and render on the client.
    GetSettingsProxy("RenderViewSettings").RemoteRenderThreshold = 0.0 if args.render_on == "server" else 1e9
if args.plugin:
    wt.load_plugin(args.plugin)

view = wt.make_view()
shown = wt.build_scene(view, opacity=0.5 if args.translucent else 1.0)
if args.view_features:
    wt.add_view_features(view, shown)
if args.negative_control:
    view.ShadingErrorForTesting = args.negative_control

start = time.perf_counter()
Render(view)
print("first frame (conversion + BVH + trace): %.3f s" % (time.perf_counter() - start))
os.makedirs(args.tmp, exist_ok=True)
image = os.path.join(args.tmp, args.name + ".png")
start = time.perf_counter()
SaveScreenshot(image, view, ImageResolution=wt.SIZE)
print("screenshot frame: %.3f s" % (time.perf_counter() - start))


def checks():
    """Every check of this test, after the image is saved."""
    # Image checks: each appends to image_failures (the negative control expects at least one)
    image_failures = []
    ok, _ = wt.compare_image(image, args.baseline, args.tmp, **wt.CHANGE_GUARD)
    if not ok:
        image_failures.append("image differs from the baseline (change guard)")
    if args.reference:
        ok, _ = wt.compare_image(image, args.reference, args.tmp, **wt.COMPOSITING)
        if not ok:
            image_failures.append("image differs from the single-process image beyond compositing round-off")
    if args.render_view_oracle:
        image_failures += wt.check_against_render_view(view, shown, args, image)
    if args.negative_control:
        if not image_failures:
            wt.fail("negative control: %d/255 on 1%% of the pixels passed every image check" % args.negative_control)
        print("negative control: the wrong image failed %d check(s), as it must: %s" % (
            len(image_failures), "; ".join(image_failures)))
        print("OK")
        sys.stdout.flush()
        os._exit(0)
    if image_failures:
        wt.fail("; ".join(image_failures))

    view.UpdatePropertyInformation()
    traced_here = view.GetProperty("TracedFrameCount").GetData()
    print("frames traced by this (client/builtin) process: %d" % traced_here)
    if args.connect and args.render_on == "server" and traced_here != 0:
        wt.fail("the client traced %d frames although the server renders" % traced_here)
    if (not args.connect or args.render_on == "client") and traced_here == 0:
        wt.fail("no traced frame on the rendering process")

    if args.expect_ranks:
        ranks = sm.vtkProcessModule.GetProcessModule().GetNumberOfLocalPartitions() if not args.connect else \
            sm.ActiveConnection.GetNumberOfDataPartitions()
        print("rendering ranks: %d" % ranks)
        if ranks != args.expect_ranks:
            wt.fail("expected %d ranks" % args.expect_ranks)
        # The geometry is split: each rank holds only part of each sphere.
        pid = ProcessIdScalars(Input=shown["mirror"].Input)
        pid.UpdatePipeline()
        rng = pid.PointData["ProcessId"].GetRange()
        print("ProcessId range of the mirror sphere: %s" % (rng,))
        if rng[1] < args.expect_ranks - 1:
            wt.fail("the data is not distributed over the ranks")
        if not args.connect:
            split = view.GetProperty("LastImageSplit").GetData()
            print("image split on rank 0 (stride, offset): %s" % (split,))
            if args.expect_split and list(split) != [args.expect_split, 0]:
                wt.fail("expected rank 0 to trace every %d-th tile" % args.expect_split)
            # Translucent geometry switches IceT from depth compositing to ordered blending.
            ordered = view.GetClientSideObject().GetUseOrderedCompositing()
            print("IceT compositing: %s" % ("ordered blend" if ordered else "depth (z-buffer)"))
            if ordered != args.translucent:
                wt.fail("unexpected compositing mode")
        # Without replication each rank traces only its part: shadows and reflections of the other rank's
        # geometry go missing and the image must change.
        view.ReplicateGeometry = 0
        noreplica = os.path.join(args.tmp, args.name + "_noreplication.png")
        SaveScreenshot(noreplica, view, ImageResolution=wt.SIZE)
        same, err = wt.compare_image(noreplica, args.baseline, args.tmp, **wt.CHANGE_GUARD)
        if same:
            wt.fail("the image without replication equals the baseline: the test scene does not exercise it")
        print("without replication %.2f%% of the pixels differ, as expected" % (100 * err))

    print("OK")


if args.save_only:  # a measurement (measure_compositing.py): the image only; every rank finishes normally
    print("OK (saved only)")
else:
    checks()
