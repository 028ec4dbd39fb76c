#!/usr/bin/env python3
"""Measures what the image tolerances of the ParaView tests rest on (not a test; run it by hand, under Xvfb):

    PYTHONPATH=<python3-paraview prefix>/usr/lib/python3/dist-packages \\
    xvfb-run -a -s "-screen 0 1280x1024x24 -noreset" python3 measure_compositing.py \\
        --plugin build/paraview/.../WhittedView.so --tmp DIR [--runs 3]

Renders each test scene of test_render.py (scene, translucent, view features) RUNS times in every way ParaView
runs it: builtin pvbatch (the single-process reference), mpirun -np 2 pvbatch (IceT compositing),
python3 client + pvserver rendering on the server (image delivery) and on the client. Prints, for each way and
scene, the largest channel difference to the first builtin image and how many pixels differ at all, over all
runs, and the same for the first builtin image against the committed baseline. whitted_pvtest.COMPOSITING and
CHANGE_GUARD are set from these numbers.
"""
import argparse
import os
import subprocess
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)
import whitted_pvtest as wt  # noqa: E402

ap = argparse.ArgumentParser()
ap.add_argument("--plugin", required=True)
ap.add_argument("--tmp", required=True)
ap.add_argument("--runs", type=int, default=3)
args = ap.parse_args()
os.makedirs(args.tmp, exist_ok=True)
baselines = os.path.join(HERE, "..", "baselines", "paraview")
render = [os.path.join(HERE, "test_render.py"), "--plugin", os.path.abspath(args.plugin), "--tmp", args.tmp,
          "--save-only"]
mpirun = ["mpirun", "--allow-run-as-root", "--oversubscribe", "--mca", "btl", "self,vader", "-x", "DISPLAY",
          "-x", "PYTHONPATH", "-np", "2"]
server = [sys.executable, os.path.join(HERE, "run_server_test.py"), "--pvserver", "pvserver", "--timeout", "240"]
scenes = {"scene": [], "translucent": ["--translucent"], "features": ["--view-features"]}
ways = {
    "builtin": lambda name: ["pvbatch"] + render + ["--name", name],
    "mpi2": lambda name: mpirun + ["pvbatch"] + render + ["--name", name],
    "cs_server": lambda name: server + ["--", sys.executable] + render + [
        "--name", name, "--connect", "127.0.0.1:{port}", "--render-on", "server"],
    "cs_client": lambda name: server + ["--", sys.executable] + render + [
        "--name", name, "--connect", "127.0.0.1:{port}", "--render-on", "client"],
}
baseline_of = {"scene": "scene.png", "translucent": "scene_translucent.png", "features": "scene_features.png"}
for scene, flags in scenes.items():
    images = {}
    for way, cmd in ways.items():
        for run in range(args.runs):
            name = "%s_%s_%d" % (scene, way, run)
            c = cmd(name) + flags + ["--baseline", os.path.join(baselines, baseline_of[scene])]
            r = subprocess.run(c, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
            if r.returncode != 0:
                print(r.stdout[-2000:])
                sys.exit("%s failed" % name)
            images.setdefault(way, []).append(wt.read_png(os.path.join(args.tmp, name + ".png")))
    reference = images["builtin"][0]
    base = wt.read_png(os.path.join(baselines, baseline_of[scene]))
    d = abs(reference - base).max(axis=2)
    print("%-12s builtin run 0 vs baseline: max %3d, %6d pixels differ" % (scene, d.max(), int((d > 0).sum())))
    for way, imgs in images.items():
        maxd = max(int(abs(i - reference).max()) for i in imgs)
        count = max(int((abs(i - reference).max(axis=2) > 0).sum()) for i in imgs)
        print("%-12s %-10s vs builtin run 0 over %d runs: max %3d, at most %6d of %d pixels differ" % (
            scene, way, len(imgs), maxd, count, reference.shape[0] * reference.shape[1]))
    sys.stdout.flush()
