"""Progressive display with a Time Budget in a script (issue 28): successive renders keep refining.

    pvbatch test_progressive_budget.py --plugin P

The shared scene at 200x150 with Refinement Rounds Per Render 1; each case renders again while
RefinementUnfinished is 1 (at most a fixed number of renders):
  A. Target Error (0.15 x the first pass's estimate) and a Time Budget of 3600 s: each Render() runs one more round
     (LastRefinementRounds 1, 2, 3, ...) and adds samples (or traces the same ones at a looser depth where the
     truncation bound dominates), RefinementUnfinished stays 1 until the render that meets
     the target, then 0; the renders reach the same rounds and samples as without a budget (a budget that is not
     spent changes nothing), and a render after the end adds nothing.
  B. Time Budget 3600 s alone (no target): 8 renders, each one more round with more samples, all unfinished.
  C. A budget that is spent (0.5 s, no target): renders continue (each unfinished one a round more, with more
     samples) until RefinementUnfinished is 0, and then the refinement has taken the whole budget
     (LastRefinementSeconds >= 0.5); the next render adds nothing; the annotation states "of 0.5 s".
No verdict depends on timing: A and B cannot spend 3600 s in the renders they make (a round of this scene takes
milliseconds); C stops only because the budget is spent (no target, and 256 samples per pixel everywhere would
take far longer than 0.5 s), however many renders that takes. Fails on the code of issue 28: the second render
of A, B or C added no sample and reported RefinementUnfinished 0.
"""
import argparse
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import whitted_pvtest as wt  # noqa: E402

ap = argparse.ArgumentParser()
ap.add_argument("--plugin", required=True)
args = ap.parse_args()

from paraview.simple import Render  # noqa: E402

wt.load_plugin(args.plugin)
view = wt.make_view([200, 150])
wt.build_scene(view)
view.ShowErrorAnnotation = 1
check = wt.Checks()


def info(name):
    return wt.info(view, name)


def state():
    view.UpdatePropertyInformation()
    seconds = view.GetProperty("LastRefinementSeconds")  # (None before issue 28's fix: the verdicts still run)
    return dict(rounds=info("LastRefinementRounds"), samples=info("LastNumberOfSamples"),
                unfinished=info("RefinementUnfinished"), met=info("LastTargetErrorMet"),
                seconds=seconds.GetData() if seconds is not None else -1.0, text=info("ErrorAnnotationText"))


def progressive(target, budget, most):
    """Renders with one round each while RefinementUnfinished (at most `most` renders, a new frame first)."""
    view.TargetError = target
    view.TimeBudget = budget
    view.RefinementRoundsPerRender = 1
    view.SMProxy.InteractiveRender()  # an interactive frame: the still frames after it start over
    frames = []
    while len(frames) < most:
        Render(view)
        frames.append(state())
        if not frames[-1]["unfinished"]:
            break
    return frames


def describe(frames):
    return " ".join("%d:%d%s" % (f["rounds"], f["samples"], "+" if f["unfinished"] else ".") for f in frames)


def keeps_refining(frames, name, loosens=False):
    """Each render one round more than the one before, with more samples (loosens: or, with a target, the same
    samples traced again at a looser depth and threshold where the truncation bound dominates), and unfinished
    but the last"""
    rounds = [f["rounds"] for f in frames]
    samples = [f["samples"] for f in frames]
    check(rounds == list(range(1, len(frames) + 1)), "%s: one more round per render (rounds:samples) %s"
          % (name, describe(frames)))
    if loosens:
        check(all(b >= a for a, b in zip(samples, samples[1:])) and samples[-1] > samples[0],
              "%s: renders add samples (or loosen: no sample lost)" % name)
    else:
        check(all(b > a for a, b in zip(samples, samples[1:])), "%s: every render adds samples" % name)
    check(all(f["unfinished"] for f in frames[:-1]), "%s: RefinementUnfinished 1 until the last" % name)


def render_after_end(frames, name):
    Render(view)
    after = state()
    check(after["samples"] == frames[-1]["samples"] and after["rounds"] == frames[-1]["rounds"]
          and not after["unfinished"], "%s: a render after the end adds nothing (%d rounds, %d samples)"
          % (name, after["rounds"], after["samples"]))


Render(view)
first = info("LastEstimatedError")[0]
pixels = 200 * 150
check(info("LastNumberOfSamples") == pixels, "first pass: 1 sample per pixel, estimate %.4f" % first)
target = 0.15 * first

# A. Target and budget
reference = progressive(target, 0.0, 60)
check(not reference[-1]["unfinished"] and reference[-1]["met"] and len(reference) > 2,
      "no budget: target %.4f met after %d renders" % (target, len(reference)))
frames = progressive(target, 3600.0, 60)
keeps_refining(frames, "A target + budget", loosens=True)
check(not frames[-1]["unfinished"] and frames[-1]["met"], "A: the last render met the target and says so")
check([(f["rounds"], f["samples"]) for f in frames] == [(f["rounds"], f["samples"]) for f in reference],
      "A: the same rounds and samples as without a budget (%s)" % describe(reference))
check(" of 3600 s" in frames[0]["text"] and "refining" in frames[0]["text"],
      "A: the annotation shows the budget: %r" % frames[0]["text"])
render_after_end(frames, "A")

# B. Budget alone
frames = progressive(0.0, 3600.0, 8)
keeps_refining(frames, "B budget alone")
check(len(frames) == 8 and frames[-1]["unfinished"], "B: still unfinished after 8 renders")

# C. A budget that is spent
budget = 0.5
frames = progressive(0.0, budget, 5000)
check(not frames[-1]["unfinished"], "C: refinement ended after %d renders" % len(frames))
keeps_refining(frames[:-1] if len(frames) > 1 else frames, "C budget spent")
check(len(frames) < 2 or frames[-1]["samples"] >= frames[-2]["samples"], "C: the last render lost no sample")
check(frames[-1]["seconds"] >= budget and not frames[-1]["met"],
      "C: ended by the budget: %.3f s of refinement for a budget of %.1f s" % (frames[-1]["seconds"], budget))
check(all(f["seconds"] >= 0.0 for f in frames) and
      all(b["seconds"] >= a["seconds"] for a, b in zip(frames, frames[1:])),
      "C: refinement seconds only grow: %s" % " ".join("%.3f" % f["seconds"] for f in frames[-5:]))
check(" of 0.5 s" in frames[-1]["text"] and "refining" not in frames[-1]["text"],
      "C: the annotation: %r" % frames[-1]["text"])
render_after_end(frames, "C")

check.finish("test_progressive_budget")
