"""What a ParaView user sees of the error estimate, and progressive display, in pvbatch.

    pvbatch test_error_display.py --plugin P --tmp DIR

The shared scene at 400x300:
  1. ShowErrorAnnotation: the annotation's text (ErrorAnnotationText) states the frame's samples per pixel and
     its estimated error as LastEstimatedError reports it; the screenshot with it differs from the one without
     only in the lower left corner, and there in more than a few pixels (the text is drawn).
  2. ShowErrorImage: the screenshot is grey (r = g = b) and grey / 255 / ErrorImageScale has the RMS and the
     largest value of the per-pixel estimated error the view reports (LastEstimatedError), to the 8-bit step.
  3. Progressive display: with RefinementRoundsPerRender 1 and a TargetError, each Render() runs one more round
     (LastRefinementRounds 1, 2, 3, ...), the estimate never grows, RefinementUnfinished turns 0 when the target
     is met; an interactive render (1 sample per pixel, annotation says so) and the still render after it starts
     over at round 1. With RefinementRoundsPerRender 0 a script's Render() refines fully.
"""
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import whitted_pvtest as wt  # noqa: E402

args = wt.parse_args(tmp=True)

import numpy as np  # noqa: E402
from paraview.simple import Render  # noqa: E402

wt.load_plugin(args.plugin)
size = wt.SIZE
view = wt.make_view(size)
wt.build_scene(view)
check = wt.Checks()


def info(name):
    return wt.info(view, name)


def shot(name):
    return wt.screenshot(view, os.path.join(args.tmp, "error_display_%s.png" % name), size)


# 1. The annotation
plain = shot("plain")
view.ShowErrorAnnotation = 1
annotated = shot("annotation")
text = info("ErrorAnnotationText")
est = info("LastRMSError")
check("1.00 spp" in text and ("error %.4f" % est[0]) in text and "no target" in text,
      "annotation text %r states 1 spp and the calibrated RMS estimate %.4f" % (text, est[0]))
rows, cols = np.nonzero(np.any(plain != annotated, axis=2))
# read_png's rows are VTK's (bottom row first): the lower left corner is at small row and column indices
check(len(rows) > 200 and rows.max() < 60 and cols.min() >= 4 and cols.max() < size[0] - 4,
      "annotation drawn: %d pixels differ, rows %s, columns %s" % (
          len(rows), (rows.min(), rows.max()) if len(rows) else "-", (cols.min(), cols.max()) if len(cols) else "-"))
view.ShowErrorAnnotation = 0

# 2. The error image
scale = min(1000.0, max(1.0, 0.9 / max(est[2], 1e-3)))  # no pixel clipped at white (the error is at most 1)
view.ErrorImageScale = scale
view.ShowErrorImage = 1
grey = shot("error_image")
est = info("LastEstimatedError")
values = grey[:, :, 0] / 255.0 / scale
step = 1.0 / 255.0 / scale
check(np.array_equal(grey[:, :, 0], grey[:, :, 1]) and np.array_equal(grey[:, :, 0], grey[:, :, 2]),
      "error image is grey")
rms = float(np.sqrt(np.mean(values ** 2)))
check(abs(rms - est[0]) <= step and abs(values.max() - est[2]) <= step,
      "error image RMS %.5f, max %.5f; reported %.5f, %.5f (8-bit step %.5f)" % (rms, values.max(), est[0], est[2],
                                                                               step))
view.ShowErrorImage = 0

# 3. Progressive display (a target a tenth of the first frame's RMS estimate, which TargetError compares: several
# rounds)
Render(view)
first = info("LastRMSError")[0]
view.TargetError = 0.1 * first
view.RefinementRoundsPerRender = 1
rounds, estimates = [], []
while len(rounds) < 50:
    Render(view)
    rounds.append(info("LastRefinementRounds"))
    estimates.append(info("LastRMSError")[0])
    if not info("RefinementUnfinished"):
        break
check(len(rounds) > 1 and rounds == list(range(1, len(rounds) + 1)),
      "one round per Render(): rounds %s" % rounds)
check(estimates[-1] < estimates[0] and info("LastTargetErrorMet") and estimates[-1] <= 0.1 * first,
      "estimate %s falls to the target %.4f" % (" ".join("%.4f" % e for e in estimates), 0.1 * first))
view.SMProxy.InteractiveRender()
check(info("ErrorAnnotationText").startswith("Whitted: interactive"), "interactive frame: %r"
      % info("ErrorAnnotationText"))
Render(view)
check(info("LastRefinementRounds") == 1 and info("RefinementUnfinished") == 1,
      "still frame after interaction starts over: round %d" % info("LastRefinementRounds"))
view.RefinementRoundsPerRender = 0
Render(view)
check(info("RefinementUnfinished") == 0 and info("LastTargetErrorMet") == 1,
      "RefinementRoundsPerRender 0 in a script: one Render() refines fully (%d rounds)"
      % info("LastRefinementRounds"))

check.finish("test_error_display")
