"""Progressive display in the real GUI: paraview --dr --plugins=WhittedView --script=gui_progressive.py

A Whitted view with a Target Error and/or a Time Budget in the GUI's layout: once the GUI has laid out the view
(1.5 s after its first frame), a fresh still frame (the script's Target Error and Time Budget set then; from a
state file, a camera nudge; for toolbar and shell, the playback's camera drag) and one Render(); the view must
render again by itself (its timer on the Qt interactor), one refinement round per frame, the annotation showing
"refining" with a falling estimate (below its first value at the end and never above it; not frame by frame: new
samples can reveal variance; samples per pixel grow, or a truncation round traces them again deeper) and
"<seconds> of <budget> s" with a budget, until a frame reports the end:
the target met, or (a budget without target) the whole budget spent or nothing left to refine (the annotation says
which); then it must stop rendering. The script
exits the GUI with 0 when that was seen, 1 when a frame went wrong or nothing happened for 90 s.

Environment (each a ctest of its own, testing/paraview/CMakeLists.txt):
  WHITTED_GUI_VIEW    "script" (default): the view is made by this startup script; "state": the script builds
                      the same view, saves a state file, and loads it (paraview.simple.LoadState, the File > Load
                      State path: the old views are removed) -- the view traced is the one the state file made,
                      with the state's Target Error and Time Budget. "toolbar" / "shell": the GUI's XML playback
                      (--test-script, gui_progressive_toolbar.xml.in / gui_progressive_shell.xml.in) makes the
                      view, from the view selector and the Properties panel / by commands typed into the Python
                      shell, sets Target Error and Time Budget there and drags the camera; this script only
                      watches that view: the first interactive frame after a still frame whose annotation shows
                      the case's settings (what the view traces with) starts the observation.
  WHITTED_GUI_TARGET  Target Error (default 0.006; 0 = none).
  WHITTED_GUI_BUDGET  Time Budget in seconds (default 0 = none).
No verdict depends on timing: with a target, a budget of 600 s cannot be spent before it is met (measured: about
1 s); without a target the refinement ends by spending the budget (2 s) or by having nothing left to refine
(seen on a fast machine after 3.5 s at 30 spp with a 4 s budget; the annotation then says so), and the script
checks the last frame's seconds against the budget unless the annotation gives that reason, not how many frames
came.
Fails on the code of issue 28 with a budget: the view stopped after its first rounds, "target not met".
"""
import os
import re
import tempfile
import time

from vtkmodules.util.misc import calldata_type
from vtkmodules.util.vtkConstants import VTK_INT
from paraview import servermanager
from paraview.simple import (AssignViewToLayout, Box, CreateView, GetViews, LoadState, Render, SaveState, Show,
                             Sphere)

MODE = os.environ.get("WHITTED_GUI_VIEW", "script")
TARGET = float(os.environ.get("WHITTED_GUI_TARGET", "0.006"))
BUDGET = float(os.environ.get("WHITTED_GUI_BUDGET", "0"))
GUI_MADE = ("toolbar", "shell")  # views the GUI's playback makes (--test-script): this script only watches
texts = []
timers = {}  # interactor timer id -> what to do when it fires (Python threads do not run in the GUI's loop)


def finish(code, message):
    print(("ok: " if code == 0 else "FAILED: ") + message, flush=True)
    os._exit(code)


def number(pattern, text, default=-1.0):
    m = re.search(pattern, text)
    return float(m.group(1)) if m else default


def on_frame(obj, event):
    global interactor, observing, scheduled, settled, start
    if interactor is None:  # (the interactor's timers work once it has rendered: not before the first frame)
        interactor = view.GetInteractor()
        interactor.AddObserver("TimerEvent", on_timer)
    if not observing and MODE in GUI_MADE:
        # The playback set Target Error and Time Budget, then dragged in the view: its first interactive frame
        # with these settings starts the observation (the still frames after it are a fresh refinement)
        view.UpdatePropertyInformation()
        text = view.GetProperty("ErrorAnnotationText").GetData()
        # (the annotation tells what the view traces with: a panel edit may be in the property, not yet applied)
        if not text.startswith("Whitted: interactive"):
            settled = (("target %g " % TARGET if TARGET > 0 else "no target") in text and
                       (("of %g s" % BUDGET) in text) == (BUDGET > 0))
            return
        if not settled:
            return
        observing = True
        start = time.time()
        after(90000, lambda: finish(1, "no end of the refinement within 90 s: %d frames" % len(texts)))
    if not observing:
        if not scheduled:
            scheduled = True
            after(1500, begin)
        return
    view.UpdatePropertyInformation()
    text = view.GetProperty("ErrorAnnotationText").GetData()
    if not text.startswith("Whitted: ") or text in texts[-1:]:
        return
    texts.append(text)
    print("frame %d at %.2f s: %s" % (len(texts), time.time() - start, text.replace("\n", " / ")), flush=True)
    if "refining" in text or text.startswith("Whitted: interactive"):
        return
    # The series of still frames that ended here: those since the last start-over (an interactive frame, or
    # fewer samples per pixel than the frame before)
    series = []
    for t in texts:
        if t.startswith("Whitted: interactive") or (series and number(r"([0-9.]+) spp", t) <
                                                   number(r"([0-9.]+) spp", series[-1])):
            series = []
        if not t.startswith("Whitted: interactive"):
            series.append(t)
    refining = [t for t in series if "refining" in t]
    errors = [number(r"error ([0-9.]+)", t) for t in series]
    problems = []
    # The view rendered again by itself: the script asked for one still frame, so a series of two or more (one
    # refining, then the end) came from the view's own timer (on the code of issue 28 the series stopped at its
    # first frame). How many frames a refinement takes depends on the machine's speed (3 at 0.2 s with the target
    # on a fast machine, many more under load): not counted beyond that
    if not refining or len(series) < 2:
        problems.append("the view did not render again by itself: %d frames, %d refining" % (len(series),
                                                                                             len(refining)))
    # Every round adds samples or, a truncation round, traces its pixels' samples again at a deeper depth, so
    # samples per pixel need not grow over the frames shown (seen in CI: 3.75 spp in both frames of a series whose
    # target the second met; a fall starts a new series above). The calibrated estimate falls over the series: it
    # ends below where it started and never goes above it. Not frame by frame: a round's new samples may reveal
    # variance its pixels' first samples hid (seen in CI: 0.0009 -> 0.0011 at 13 spp, the annotation's 4 decimals
    # making it look 22%), and how many rounds a frame shows depends on timing
    if errors[-1] >= errors[0] or any(e > errors[0] for e in errors[1:]):
        problems.append("the estimate did not fall: %s" % errors)
    if TARGET > 0 and ("target %g met" % TARGET) not in text:
        problems.append("the last frame did not meet the target")
    if BUDGET > 0:
        spent = number(r"([0-9.]+) of %g s" % BUDGET, text)
        if any(("of %g s" % BUDGET) not in t for t in series):
            problems.append("a frame's annotation does not show the budget")
        # Without a target the refinement ends by spending the budget or, on a machine fast enough, when nothing
        # is left to refine (every pixel whose samples disagree has the most samples a still frame takes), which
        # the annotation says: either end is right, an end before the budget without that reason is not
        if TARGET <= 0 and spent < BUDGET and "nothing left to refine" not in text:
            problems.append("ended after %.2f s of a %g s budget with something left to refine" % (spent, BUDGET))
    what = "%d frames refined round by round, then %s and rendering stopped" % (
        len(refining), "the target was met" if TARGET > 0 else
        "nothing was left to refine" if "nothing left to refine" in text else "the budget was spent")
    # Stopped: no frame for 3 s after the one that ended the refinement
    after(3000, lambda: finish(0 if not problems and texts[-1] == text else 1,
                               what if not problems and texts[-1] == text else
                               "; ".join(problems + (["rendering went on"] if texts[-1] != text else []))))


def after(ms, action):
    timers[interactor.CreateOneShotTimer(ms)] = action


@calldata_type(VTK_INT)
def on_timer(obj, event, timer_id):
    # By the timer's id: while its event runs, a one-shot timer that fired is still registered
    action = timers.pop(timer_id, None)
    if action:
        action()


def build_view():
    """The view made by this script (and, for "state", saved and loaded again)"""
    global view
    view = CreateView("WhittedRayTraceView")
    AssignViewToLayout(view)
    view.OrientationAxesVisibility = 0
    d = Show(Sphere(ThetaResolution=64, PhiResolution=32), view)
    d.Representation = "Whitted Surface"
    d.Reflectance = 0.5
    Show(Box(Center=[1.2, 0.0, 0.0]), view)
    view.ResetCamera()
    view.ShowErrorAnnotation = 1
    view.TargetError = TARGET
    view.TimeBudget = BUDGET
    if MODE == "state":  # the state file holds the Target Error and Time Budget
        path = os.path.join(tempfile.mkdtemp(prefix="whitted_gui_"), "progressive.pvsm")
        SaveState(path)
        LoadState(path)  # removes the views and layouts, then makes them again from the file
        views = [v for v in GetViews() if v.GetXMLName() == "WhittedRayTraceView"]
        if len(views) != 1 or views[0] is view:
            finish(1, "the state file made %d Whitted views" % len(views))
        view = views[0]
        print("view from the state file: Target Error %g, Time Budget %g" % (view.TargetError, view.TimeBudget))
        if view.TargetError != TARGET or view.TimeBudget != BUDGET:
            finish(1, "the state file's view has other settings")


def watch(v):
    """Observe the frames of the view v"""
    global view
    view = v
    view.GetRenderWindow().AddObserver("EndEvent", on_frame)


def on_register(obj, event):
    """toolbar, shell: the Whitted view appears when the GUI's playback makes it"""
    if view is None:
        made = [v for v in GetViews() if v.GetXMLName() == "WhittedRayTraceView"]
        if made:
            print("view made by %s" % MODE, flush=True)
            watch(made[0])


def begin():
    """Once the GUI has laid out the view (its first frames may be traced at another size): a fresh still frame,
    from the state file's settings (a camera nudge starts it over) or from the script's"""
    global observing, start
    if MODE == "state":
        position = list(view.CameraPosition)
        view.CameraPosition = [position[0] * 1.001, position[1], position[2]]
    else:
        view.TargetError = TARGET
        view.TimeBudget = BUDGET
    observing = True
    start = time.time()
    after(90000, lambda: finish(1, "no end of the refinement within 90 s: %d frames" % len(texts)))
    Render(view)


view = interactor = None
observing = scheduled = settled = False
start = time.time()
if MODE in GUI_MADE:
    servermanager.ProxyManager().SMProxyManager.AddObserver("RegisterEvent", on_register)
else:
    build_view()
    print("view made by %s: Target Error %g, Time Budget %g s" % (MODE, TARGET, BUDGET), flush=True)
    watch(view)
    if MODE != "state":
        view.TargetError = view.TimeBudget = 0.0  # set by begin(): the frames before it trace once
    Render(view)
