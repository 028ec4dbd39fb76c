#!/usr/bin/env python3
"""Composes this folder's study of the progressive mode against the fixed settings' Pareto front.

usage: compose.py --fixed A.csv[,B.csv...] --passes DIR [--before DIR] --out DIR

--fixed: `whitted_bench error` CSVs whose fixed-setting rows make the front (their progressive rows are ignored);
--passes: DIR/pass*/run_<scene>.csv, each a `whitted_bench error --progressive-only` run (its default row, then one
row per budget, in the same order in every pass); --before: the same for another build, run interleaved with
--passes (its medians are the table's "before" column).

Per scene and budget (by position) the pass with the median RMSE is kept. Its cost is its CPU time scaled by (the
fixed rows' default CPU time / that pass's default CPU time), so that runs made at different times compare with the
front; its wall time is scaled the same way. Writes error.csv (the fixed rows, then the kept progressive rows,
scaled: what `run_benchmark.py --report-only --sections error` draws), error_progressive_run.csv (every pass's rows
as measured, unscaled) and front.md (the table: the front at a point's cost is the least RMSE of the fixed settings
whose CPU time is at most that cost)."""
import argparse
import csv
import glob
import os

SCENES = ["classic", "tubes", "glassmirror", "mirrors", "lightinglass", "nestedglass", "iso1m", "points100k",
          "fence", "text"]
FACTORS = ["1.5", "3", "6", "12"]


def read_fixed(paths):
    header, rows = None, []
    for p in paths:
        with open(p) as f:
            r = csv.DictReader(f)
            header = header or r.fieldnames
            rows += [row for row in r if row["progressive"] != "1"]
    return header, rows


def read_passes(root):
    """{scene: [[(rmse, scaled cpu, scaled row, raw row) per budget] per pass]} and every raw row in pass order"""
    out, raw = {}, []
    for d in sorted(glob.glob(os.path.join(root, "pass*")), key=lambda p: int(p.rsplit("pass", 1)[1])):
        for scene in SCENES:
            p = os.path.join(d, "run_%s.csv" % scene)
            if not os.path.exists(p):
                continue
            with open(p) as f:
                rows = list(csv.DictReader(f))
            raw += rows
            out.setdefault(scene, []).append(rows)
    return out, raw


def medians(passes, fixed_default):
    """{scene: [(rmse, cost, scaled row) per budget]}: per budget the pass with the median RMSE"""
    res = {}
    for scene, runs in passes.items():
        if scene not in fixed_default:
            continue
        per_budget = {}
        for rows in runs:
            d = [r for r in rows if r["is_default"] == "1" and r["progressive"] != "1"]
            if not d:
                continue
            scale = fixed_default[scene] / float(d[0]["cpu_seconds_median"])
            k = 0
            for r in rows:
                if r["progressive"] != "1":
                    continue
                s = dict(r)
                for key in ("cpu_seconds_median", "seconds_median", "seconds_min"):
                    s[key] = "%g" % (float(r[key]) * scale)
                per_budget.setdefault(k, []).append((float(r["rmse"]), float(s["cpu_seconds_median"]), s))
                k += 1
        res[scene] = []
        for k in sorted(per_budget):
            runs_k = sorted(per_budget[k], key=lambda x: x[0])
            res[scene].append(runs_k[(len(runs_k) - 1) // 2])
    return res


def front_at(fixed_rows, scene, cost):
    cand = [r for r in fixed_rows if r["scene"] == scene and r["is_reference"] != "1" and
            float(r["cpu_seconds_median"]) <= cost]
    return min(cand, key=lambda r: float(r["rmse"])) if cand else None


def setting(r):
    return "%s spp%s d%s thr %g/255" % (r["spp"], "a" if r["adaptive"] == "1" else "", r["depth"],
                                        round(float(r["threshold"]) * 255))


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--fixed", required=True)
    ap.add_argument("--passes", required=True)
    ap.add_argument("--before")
    ap.add_argument("--out", required=True)
    a = ap.parse_args()
    header, fixed = read_fixed(a.fixed.split(","))
    fixed_default = {r["scene"]: float(r["cpu_seconds_median"]) for r in fixed if r["is_default"] == "1"}
    passes, raw = read_passes(a.passes)
    now = medians(passes, fixed_default)
    before = medians(read_passes(a.before)[0], fixed_default) if a.before else {}
    with open(os.path.join(a.out, "error.csv"), "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=header)
        w.writeheader()
        for r in fixed:
            w.writerow(r)
        for scene in SCENES:
            for _, _, r in now.get(scene, []):
                w.writerow(r)
    with open(os.path.join(a.out, "error_progressive_run.csv"), "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=header)
        w.writeheader()
        for r in raw:
            w.writerow(r)
    lines = ["| scene | budget (x default frame) | cost, ms CPU | RMSE | front at that cost | front's setting there | "
             "on or below | RMSE before |", "|---|---|---|---|---|---|---|---|"]
    below = total = 0
    for scene in SCENES:
        for k, (rmse, cost, _) in enumerate(now.get(scene, [])):
            fr = front_at(fixed, scene, cost)
            ok = fr is None or rmse <= float(fr["rmse"])
            below += ok
            total += 1
            b = before.get(scene, [])
            lines.append("| %s | %s | %.1f | %s | %s | %s | %s | %s |" % (
                scene, FACTORS[k] if k < len(FACTORS) else k, cost * 1e3,
                ("**%.5f**" if ok else "%.5f") % rmse, "%.5f" % float(fr["rmse"]) if fr else "-",
                setting(fr) if fr else "-", "yes" if ok else "no (+%.0f%%)" % (100 * (rmse / float(fr["rmse"]) - 1)),
                "%.5f" % b[k][0] if k < len(b) else "-"))
    lines.append("")
    lines.append("On or below the front: %d of %d points." % (below, total))
    with open(os.path.join(a.out, "front.md"), "w") as f:
        f.write("\n".join(lines) + "\n")
    print("\n".join(lines))


if __name__ == "__main__":
    main()
