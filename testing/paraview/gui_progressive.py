"""Progressive display in the real GUI: paraview --dr --plugins=WhittedView --script=gui_progressive.py

A Whitted view with a Target Error in the GUI's layout: after the script's one Render(), the view must render
again by itself (its timer on the Qt interactor), one refinement round per frame, the annotation showing
"refining" with a falling estimate, until a frame reports the target met; then it must stop rendering. The
script exits the GUI with 0 when that was seen, 1 when a frame went wrong or nothing happened for 60 s.
"""
import os
import time

from paraview.simple import AssignViewToLayout, Box, CreateView, Render, Show, Sphere

texts = []
timers = {}  # interactor timer id -> what to do when it fires (Python threads do not run in the GUI's loop)


def finish(code, message):
    print(("ok: " if code == 0 else "FAILED: ") + message, flush=True)
    os._exit(code)


def on_frame(obj, event):
    view.UpdatePropertyInformation()
    text = view.GetProperty("ErrorAnnotationText").GetData()
    if not text.startswith("Whitted: ") or text in texts[-1:]:
        return
    texts.append(text)
    print("frame %d at %.2f s: %s" % (len(texts), time.time() - start, text.replace("\n", " / ")), flush=True)
    if "refining" not in text:
        refining = [t for t in texts if "refining" in t]
        errors = [float(t.split("error ")[1].split()[0]) for t in refining]
        ok = "target 0.006 met" in text and len(refining) >= 3 and errors == sorted(errors, reverse=True)
        # Stopped: no frame for 3 s after the one that met the target
        after(3000, lambda: finish(0 if ok and texts[-1] == text else 1,
                                   "%d frames refined round by round, then the target was met and rendering "
                                   "stopped" % len(refining)))


def after(ms, action):
    timers[interactor.CreateOneShotTimer(ms)] = action


def on_timer(obj, event):
    for timer_id, action in list(timers.items()):
        if not interactor.IsOneShotTimer(timer_id):  # fired (a one-shot timer is gone once it fired)
            del timers[timer_id]
            action()


view = CreateView("WhittedRayTraceView")
AssignViewToLayout(view)
view.OrientationAxesVisibility = 0
d = Show(Sphere(ThetaResolution=64, PhiResolution=32), view)
d.Representation = "Whitted Surface"
d.Reflectance = 0.5
Show(Box(Center=[1.2, 0.0, 0.0]), view)
view.ResetCamera()
view.ShowErrorAnnotation = 1
view.TargetError = 0.006
start = time.time()
view.GetRenderWindow().AddObserver("EndEvent", on_frame)
interactor = view.GetInteractor()
interactor.AddObserver("TimerEvent", on_timer)
after(60000, lambda: finish(1, "no end of the refinement within 60 s: %d frames" % len(texts)))
Render(view)
