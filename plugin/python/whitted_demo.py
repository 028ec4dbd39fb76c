#!/usr/bin/python3
"""Renders the classic Whitted scene (built from VTK sources) through vtkWhittedPass offscreen,
writes a PNG and prints the frame report.

    xvfb-run -a -s "-screen 0 1280x1024x24 -noreset" \\
        env PYTHONPATH=<build>/lib/python3/dist-packages /usr/bin/python3 whitted_demo.py \\
        --out whitted.png --size 800x600

Exit status: 0 on success, 1 when rendering failed (VTK error, nothing traced, image not written),
2 on bad arguments.
"""
import argparse
import os
import sys
import time


def parse_size(text):
    try:
        w, h = (int(v) for v in text.lower().split("x"))
    except ValueError:
        raise argparse.ArgumentTypeError("--size wants WxH, e.g. 800x600")
    if w <= 0 or h <= 0:
        raise argparse.ArgumentTypeError("--size wants positive WxH")
    return w, h


def parse_args(argv):
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--out", default="whitted.png", help="PNG to write (default whitted.png)")
    ap.add_argument("--size", type=parse_size, default=(800, 600), help="WxH (default 800x600)")
    # The pass's settings; left out, they keep the pass's defaults (plugin/vtkWhittedSettings.h)
    ap.add_argument("--spp", type=int, help="samples per pixel (SamplesPerPixel)")
    ap.add_argument("--adaptive", action="store_true", help="adaptive sampling (AdaptiveSampling)")
    ap.add_argument("--depth", type=int, help="max secondary depth (MaxDepth)")
    ap.add_argument("--threshold", type=float, help="contribution threshold (ContributionThreshold)")
    ap.add_argument("--threads", type=int, help="threads, 0 = all cores (NumberOfThreads)")
    ap.add_argument("--target-error", type=float,
                    help="refine until the estimated error's RMS is at most this (TargetError)")
    ap.add_argument("--time-budget", type=float, help="refine for at most this many seconds (TimeBudget)")
    ap.add_argument("--no-shadows", action="store_true")
    ap.add_argument("--no-reflections", action="store_true")
    ap.add_argument("--no-refractions", action="store_true")
    ap.add_argument("--fresnel", action="store_true")
    ap.add_argument("--resolution", type=int, default=48,
                    help="sphere phi resolution (theta is twice that; default 48)")
    ap.add_argument("--frames", type=int, default=1,
                    help="render this many frames and report the last (default 1)")
    return ap.parse_args(argv)


def make_pass(args):
    """A vtkWhittedPass with the settings given on the command line (the others keep their defaults)."""
    from whitted import vtkWhittedPass
    whitted_pass = vtkWhittedPass()
    for value, setter in ((args.spp, whitted_pass.SetSamplesPerPixel), (args.depth, whitted_pass.SetMaxDepth),
                          (args.threshold, whitted_pass.SetContributionThreshold),
                          (args.threads, whitted_pass.SetNumberOfThreads),
                          (args.target_error, whitted_pass.SetTargetError),
                          (args.time_budget, whitted_pass.SetTimeBudget)):
        if value is not None:
            setter(value)
    for flag, setter in ((args.adaptive, whitted_pass.AdaptiveSamplingOn),
                         (args.no_shadows, whitted_pass.ShadowsOff),
                         (args.no_reflections, whitted_pass.ReflectionsOff),
                         (args.no_refractions, whitted_pass.RefractionsOff), (args.fresnel, whitted_pass.FresnelOn)):
        if flag:
            setter()
    return whitted_pass


def write_png(window, path):
    """The window's last frame (not rendered again) as a PNG."""
    from vtkmodules.vtkIOImage import vtkPNGWriter
    from vtkmodules.vtkRenderingCore import vtkWindowToImageFilter
    grab = vtkWindowToImageFilter()
    grab.SetInput(window)
    grab.ReadFrontBufferOff()
    grab.ShouldRerenderOff()
    grab.Update()
    writer = vtkPNGWriter()
    writer.SetFileName(path)
    writer.SetInputConnection(grab.GetOutputPort())
    writer.Write()


def check_frame(args, whitted_pass, errors):
    """What went wrong: VTK errors, rays or actors not as expected, an aborted frame, no PNG."""
    w, h = args.size
    problems = list(errors)
    stats = whitted_pass.GetLastFrameStatistics()
    spp = whitted_pass.GetSamplesPerPixel()
    if stats.GetPrimaryRays() != w * h * spp and not args.adaptive:
        problems.append("expected %d primary rays, traced %d" % (w * h * spp, stats.GetPrimaryRays()))
    if stats.GetNumberOfTracedActors() != 3:
        problems.append("expected 3 traced actors, got %d"
                        % stats.GetNumberOfTracedActors())
    if stats.GetAborted():
        problems.append("the frame was aborted")
    if not os.path.isfile(args.out) or os.path.getsize(args.out) == 0:
        problems.append("could not write " + args.out)
    return problems


def main(argv=None):
    args = parse_args(argv)

    from vtkmodules.vtkCommonCore import vtkCommand
    from vtkmodules.vtkRenderingCore import vtkRenderer, vtkRenderWindow
    import vtkmodules.vtkRenderingOpenGL2  # noqa: F401  (OpenGL factory)
    from whitted.scenes import classic_scene

    errors = []

    def on_error(obj, event, *rest):
        errors.append("%s: %s" % (obj.GetClassName(), event))

    # Scene, window, pass
    renderer = vtkRenderer()
    window = vtkRenderWindow()
    window.SetOffScreenRendering(True)
    window.SetMultiSamples(0)
    window.SetSize(*args.size)
    window.AddRenderer(renderer)
    classic_scene(renderer, args.resolution)
    whitted_pass = make_pass(args)
    renderer.SetPass(whitted_pass)
    for obj in (whitted_pass, window, renderer):
        obj.AddObserver(vtkCommand.ErrorEvent, on_error)

    # Frames, the PNG and the report
    frame_times = []
    for _ in range(max(1, args.frames)):
        if args.frames > 1:
            renderer.GetActiveCamera().Modified()
        t0 = time.perf_counter()
        window.Render()
        frame_times.append(time.perf_counter() - t0)
    write_png(window, args.out)
    print(whitted_pass.GetLastFrameReport(), end="")
    print("  window           Render() %.2f ms (last of %d frame(s))"
          % (frame_times[-1] * 1e3, len(frame_times)))

    problems = check_frame(args, whitted_pass, errors)
    if problems:
        for p in problems:
            print("whitted_demo: error: " + p, file=sys.stderr)
        return 1
    print("whitted_demo: wrote %s (%dx%d)" % (args.out, *args.size))
    return 0


if __name__ == "__main__":
    sys.exit(main())
