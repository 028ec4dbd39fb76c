"""The error annotation with a remote server: the server traces, its root sends the annotation's text to the
client after the image, and the client draws it and reports it.

    python3 test_error_remote.py --plugin P --tmp DIR --connect 127.0.0.1:PORT

The shared scene at 400x300, rendered on the server (RemoteRenderThreshold 0):
  1. The client's tracer stays idle (TracedFrameCount 0: information properties come from the client's view
     object), yet its ErrorAnnotationText is the server's frame: 1 spp, a positive estimated error, "no target".
  2. The screenshot with the annotation differs from the one without in the lower left corner only, and there in
     more than a few pixels (the client's non-composited renderer drew the text).
  3. A TargetError the first frame misses: after the refined still frame the text says "met" and reports more
     samples per pixel than 1.
"""
import argparse
import os
import re
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import whitted_pvtest as wt  # noqa: E402

ap = argparse.ArgumentParser()
ap.add_argument("--plugin", required=True)
ap.add_argument("--tmp", required=True)
ap.add_argument("--connect", required=True, help="host:port of a pvserver")
args = ap.parse_args()
os.makedirs(args.tmp, exist_ok=True)

import numpy as np  # noqa: E402
from paraview.simple import Connect, GetSettingsProxy, Render  # noqa: E402

host, port = args.connect.rsplit(":", 1)
Connect(host, int(port))
GetSettingsProxy("RenderViewSettings").RemoteRenderThreshold = 0.0
wt.load_plugin(args.plugin)
size = wt.SIZE
view = wt.make_view(size)
wt.build_scene(view)
check = wt.Checks()
pattern = re.compile(r"Whitted: \d+ ms, ([0-9.]+) spp, error ([0-9.]+) \(RMS estimate\)\n(.*)")


def shot(name):
    return wt.screenshot(view, os.path.join(args.tmp, "error_remote_%s.png" % name), size)


# 1. The text reaches the client
plain = shot("plain")
view.ShowErrorAnnotation = 1
annotated = shot("annotation")
text = wt.info(view, "ErrorAnnotationText")
m = pattern.match(text)
check(wt.info(view, "TracedFrameCount") == 0, "client's tracer idle: %d frames" % wt.info(view, "TracedFrameCount"))
check(bool(m) and float(m.group(1)) == 1.0 and float(m.group(2)) > 0.0 and m.group(3) == "no target",
      "client's annotation text is the server's frame: %r" % text)
first = float(m.group(2)) if m else 0.0

# 2. ... and is drawn there
rows, cols = np.nonzero(np.any(plain != annotated, axis=2))
# read_png's rows are VTK's (bottom row first): the lower left corner is at small row and column indices
check(len(rows) > 200 and rows.max() < 60 and cols.min() >= 4 and cols.max() < size[0] - 4,
      "annotation drawn on the client: %d pixels differ, rows %s, columns %s" % (
          len(rows), (rows.min(), rows.max()) if len(rows) else "-", (cols.min(), cols.max()) if len(cols) else "-"))

# 3. A refined frame: the text follows it
view.TargetError = 0.5 * first
Render(view)
text = wt.info(view, "ErrorAnnotationText")
m = pattern.match(text)
check(bool(m) and float(m.group(1)) > 1.0 and float(m.group(2)) <= 0.5 * first and m.group(3).endswith(" met"),
      "refined frame: %r (target %.4f)" % (text, 0.5 * first))

check.finish("test_error_remote")
