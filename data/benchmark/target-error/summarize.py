#!/usr/bin/env python3
"""Summary of a `whitted_bench target` study (issue 28's done-when) from its CSVs: the stop rows (one per scene and
target: SCENE.csv) and, if given, every call's row (--frames-csv). Prints the Markdown table and the figures the
issue asks for: met implies measured <= target; reported / measured RMS (median over settings, share of frames
below 1.0); time to met against the oracle time (median, worst)."""
import argparse
import csv
import glob
import os
import statistics


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("folder")
    ap.add_argument("--scenes", default="classic,iso60k,iso1m,iso4m,points100k,tubes,glassmirror,mirrors,lightinglass,"
                    "nestedglass,fence,text")
    ap.add_argument("--frames", default="frames.csv")
    a = ap.parse_args()
    rows = []
    for scene in a.scenes.split(","):
        for name in (scene + ".csv", scene + "_truth_depth64.csv"):  # mirrors: against its depth-64 truth
            path = os.path.join(a.folder, name)
            if os.path.exists(path):
                rows += list(csv.DictReader(open(path)))
                break
    print("| scene | target | met | reported | measured | ratio | spp | seconds | oracle s | time / oracle |")
    print("| --- | --- | --- | --- | --- | --- | --- | --- | --- | --- |")
    to = []
    for r in rows:
        t = float(r["seconds"]) / float(r["oracle_seconds"]) if r["oracle_seconds"] else float("inf")
        to.append(t)
        print("| %s | %.3f | %s | %.4f | %.4f | %.2f | %.1f | %.2f | %s | %.2f |" % (
            r["scene"], float(r["target"]), "yes" if r["met"] == "1" else "no", float(r["reported_rms"]),
            float(r["measured_rms"]), float(r["ratio"]), float(r["spp"]), float(r["seconds"]),
            "%.2f" % float(r["oracle_seconds"]) if r["oracle_seconds"] else "never", t))
    ratios = [float(r["ratio"]) for r in rows]
    above = sum(1 for r in rows if r["met"] == "1" and r["measured_below"] != "1")
    print()
    print("Stops: %d rows; met but measured above the target: %d; ratio min %.2f median %.2f max %.2f, below 1.0: %d, "
          "above 1.5: %d; time / oracle median %.2f max %.2f, above 1.5: %d, above 3: %d." % (
              len(rows), above, min(ratios), statistics.median(ratios), max(ratios), sum(x < 1.0 for x in ratios),
              sum(x > 1.5 for x in ratios), statistics.median(to), max(to), sum(x > 1.5 for x in to),
              sum(x > 3.0 for x in to)))
    per_scene = {}
    for r in rows:
        per_scene.setdefault(r["scene"], []).append(float(r["ratio"]))
    print("Median ratio per scene: " + ", ".join("%s %.2f" % (s, statistics.median(v)) for s, v in per_scene.items()))
    fpath = os.path.join(a.folder, a.frames)
    if os.path.exists(fpath):
        frames = [f for f in csv.DictReader(open(fpath)) if f["scene"] in per_scene]
        below = [f for f in frames if float(f["ratio"]) < 1.0]
        print("Frames (every call of every refinement): %d, reported / measured below 1.0 in %d (%.1f%%)%s" % (
            len(frames), len(below), 100.0 * len(below) / len(frames),
            ": " + ", ".join("%s %s call %s %.2f" % (f["scene"], f["target"], f["call"], float(f["ratio"]))
                             for f in below) if below else ""))


if __name__ == "__main__":
    main()
