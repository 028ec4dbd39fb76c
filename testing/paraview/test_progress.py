"""A long still frame of the Whitted view reports progress through ParaView's progress handler (the object
the GUI's progress bar listens to, and that relays a server's progress to its client).

    pvbatch test_progress.py --plugin P
    python3 test_progress.py --plugin P --connect 127.0.0.1:PORT      (progress of the server's frame)
"""
import argparse
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import whitted_pvtest as wt  # noqa: E402

ap = argparse.ArgumentParser()
ap.add_argument("--plugin", required=True)
ap.add_argument("--connect", help="host:port of a pvserver (render there, receive its progress)")
args = ap.parse_args()

from paraview import servermanager as sm  # noqa: E402
from paraview.simple import Connect, GetSettingsProxy, Render  # noqa: E402

if args.connect:
    host, port = args.connect.rsplit(":", 1)
    Connect(host, int(port))
    GetSettingsProxy("RenderViewSettings").RemoteRenderThreshold = 0.0
wt.load_plugin(args.plugin)
view = wt.make_view(size=[640, 480])
wt.build_scene(view)
view.SamplesPerPixel = 32  # a frame long enough (about a second here) to report progress several times
Render(view)  # conversion and BVH; progress is checked on the next, pure tracing frame

handler = sm.ActiveConnection.Session.GetProgressHandler()
handler.SetProgressInterval(0.01)
events = []


def on_progress(obj, event):
    events.append((obj.GetLastProgressText(), obj.GetLastProgress()))


tag = handler.AddObserver("ProgressEvent", on_progress)
view.GetActiveCamera().Azimuth(5.0)
Render(view)
handler.RemoveObserver(tag)
ours = [e for e in events if "Whitted" in (e[0] or "")]
print("progress events: %d (%d from the Whitted view): %s" % (len(events), len(ours), ours[:12]))
if not ours:
    wt.fail("no progress reported by the Whitted view during a still frame")
print("OK")
