"""Whole frame against POV-Ray 3.7 on the classic scene: the .pov file is written by `whitted_bench pov` from the
very scene we trace; same size, depth, threshold and threads, no antialiasing; wall and CPU time, of the trace
alone and of the whole process, and the frame's CPU time counted the same way on both sides (process CPU time
minus that of the same command at FIXED_SIZE: POV-Ray's own trace CPU time counts its render threads only, not
the pixel handling its other threads do, while ours counts the whole process during the render)."""
import json
import re
import shutil
import statistics

from .. import plots
from ..markdown import commands_block, fmt_ratio, md_table, ratio
from ..runner import drop_tags, fresh, read_csv, write_csv

DEPTH = 5
THRESHOLD = 1.0 / 255.0
FIXED_SIZE = (16, 12)  # a frame this small measures each program's fixed cost (start-up, parsing, build, output)


def _pov_time(text, what):
    m = re.search(r"%s Time:.*\(([\d.]+) seconds\)" % what, text)
    return float(m.group(1)) if m else float("nan")


def _pov_trace_cpu(text):
    m = re.search(r"Trace Time:.*\n\s*using \d+ thread\(s\) with ([\d.]+) CPU-seconds", text)
    return float(m.group(1)) if m else float("nan")


def image_difference(ctx, image, reference):
    """whitted_bench diff of two PNG files: dict with rmse, psnr, ssim, max_levels."""
    _, text, _ = ctx.runner.run([ctx.bench, "diff", "--image", image, "--reference", reference], "image difference")
    return json.loads(text)


def run(ctx):
    c = ctx.cfg
    frames = ctx.path("frames.csv")
    drop_tags(frames, ["pov"])
    pov_csv = fresh(ctx.path("pov.csv"))
    if not shutil.which("povray"):
        ctx.skip("pov", "povray not found: POV-Ray comparison skipped")
        return
    threads = ctx.threads
    scene_file = ctx.path("classic.pov")
    ctx.runner.run([ctx.bench, "pov", "--scene", "classic", "--out", scene_file], "write classic.pov")
    rows = []
    for size in c["pov_sizes"]:
        w, h = (int(v) for v in size.split("x"))
        ours_png, pov_png = ctx.path("pov_ours_%s.png" % size), ctx.path("pov_povray_%s.png" % size)
        common = [ctx.bench, "frame", "--scene", "classic", "--sizes", size, "--depth", str(DEPTH), "--threshold",
                  repr(THRESHOLD), "--threads-list", str(threads)]
        # Ours in-process: trace time median after a warm-up (the renderer's own timer)
        ctx.runner.run(common + ["--reps", str(c["frame_reps"]), "--warmup", "1", "--tag", "pov", "--csv", frames,
                                 "--png", ours_png], "ours classic " + size)
        # Whole processes, alternating ours and POV-Ray, each rendering once (cold, like POV-Ray's single frame):
        # process wall/CPU time includes start-up, parsing or scene build and PNG output; trace wall/CPU time is
        # each program's own timer
        def pov_cmd(pw, ph, png):
            return ["povray", "+I" + scene_file, "+O" + png, "+W%d" % pw, "+H%d" % ph, "-A", "+WT%d" % threads,
                    "-D", "+FN", "-V", "File_Gamma=1.0", "Declare=TraceLevel=%d" % (DEPTH + 1),
                    "Declare=Bailout=%.17g" % THRESHOLD, "Declare=Aspect=%.17g" % (w / h)]

        def ours_cmd(pw, ph, png):
            cmd = common + ["--reps", "1", "--warmup", "0", "--png", png]
            cmd[cmd.index("--sizes") + 1] = "%dx%d" % (pw, ph)
            return cmd

        fw, fh = FIXED_SIZE
        fixed_png = ctx.path("pov_fixed_cost.png")
        m = {k: [] for k in ["pov_wall", "pov_cpu", "pov_trace", "pov_trace_cpu", "ours_wall", "ours_cpu",
                             "ours_trace", "ours_trace_cpu", "pov_fixed_wall", "pov_fixed_cpu", "ours_fixed_wall",
                             "ours_fixed_cpu"]}
        for i in range(1 + c["pov_reps"]):  # the first round is the warm-up (file cache, binaries)
            _, text, wall = ctx.runner.run(pov_cmd(w, h, pov_png), "povray %s run %d" % (size, i))
            pcpu = ctx.runner.last_cpu
            _, otext, owall = ctx.runner.run(ours_cmd(w, h, ours_png), "ours process %s run %d" % (size, i))
            ocpu = ctx.runner.last_cpu
            # The same commands at FIXED_SIZE (the picture's aspect kept by the Aspect declaration): fixed cost
            _, _, pfwall = ctx.runner.run(pov_cmd(fw, fh, fixed_png), "povray fixed cost run %d" % i)
            pfcpu = ctx.runner.last_cpu
            _, _, ofwall = ctx.runner.run(ours_cmd(fw, fh, fixed_png), "ours fixed cost run %d" % i)
            ofcpu = ctx.runner.last_cpu
            if i == 0:
                continue
            for k, v in [("pov_fixed_wall", pfwall), ("pov_fixed_cpu", pfcpu), ("ours_fixed_wall", ofwall),
                         ("ours_fixed_cpu", ofcpu)]:
                m[k].append(v)
            mo = re.search(r"trace\s+([\d.]+) ms .*cpu ([\d.]+) ms", otext)
            for k, v in [("pov_wall", wall), ("pov_cpu", pcpu), ("pov_trace", _pov_time(text, "Trace")),
                         ("pov_trace_cpu", _pov_trace_cpu(text)), ("ours_wall", owall), ("ours_cpu", ocpu),
                         ("ours_trace", float(mo.group(1)) * 1e-3 if mo else float("nan")),
                         ("ours_trace_cpu", float(mo.group(2)) * 1e-3 if mo else float("nan"))]:
                m[k].append(v)
        fr = [r for r in read_csv(frames) if r["tag"] == "pov" and r["width"] == w and r["height"] == h][-1]
        diff = image_difference(ctx, ours_png, pov_png)
        row = dict(size=size, threads=threads, depth=DEPTH, pov_max_trace_level=DEPTH + 1, runs=len(m["pov_wall"]))
        row.update({k + "_median": statistics.median(v) for k, v in m.items()})
        # The frame's CPU time, counted alike: process CPU time above the fixed cost (medians)
        row.update(fixed_size="%dx%d" % FIXED_SIZE,
                   pov_frame_cpu=row["pov_cpu_median"] - row["pov_fixed_cpu_median"],
                   ours_frame_cpu=row["ours_cpu_median"] - row["ours_fixed_cpu_median"])
        row.update(ours_trace_warm_median=fr["seconds_median"], image_rmse_8bit=diff["rmse"],
                   image_ssim=diff["ssim"], image_max_levels=diff["max_levels"])
        rows.append(row)
    write_csv(pov_csv, rows)


def outputs(ctx):
    return ["pov.csv", "pov_compare.png", "classic.pov"]


def report(ctx, head):
    pov = read_csv(ctx.path("pov.csv"))
    if not pov:
        return []
    plots.pov(ctx, pov[0])
    L = ["\n## Whole frame against POV-Ray 3.7\n",
         "`classic.pov` is written by `whitted_bench pov --scene classic` from the scene we trace (same triangles "
         "and spheres, camera, light, VTK-style ambient/diffuse/Phong, kr, kt, IOR), rendered without "
         "antialiasing, `adc_bailout` = our threshold 1/255, both with %d threads (`+WT%d`, `--threads-list %d`). "
         "POV-Ray counts the camera ray as trace level 1, so `max_trace_level` = our depth + 1. Trace = each "
         "program's own timer (POV-Ray reports its CPU-seconds, ours the process CPU time of the render); "
         "process = the whole program run once, cold, ours and POV-Ray alternating (start-up, parsing or scene "
         "build, BVH, trace, PNG output), wall time and CPU time (`getrusage` of the finished child). The two "
         "trace CPU times are not counted alike: POV-Ray's own figure covers its render threads only, not the "
         "pixel handling its other threads do, ours the whole process during the render. Frame CPU counts both "
         "alike: the process CPU time minus that of the same command at %s pixels (start-up, parsing or scene "
         "build, output: each program's fixed cost, also run alternating); its ratio is the CPU comparison. POV-Ray's "
         "process wall time includes idle waiting (compare its fixed-cost wall and CPU time below). Image "
         "difference: `whitted_bench diff`.\n" % ((pov[0]["threads"],) * 3 + (pov[0].get("fixed_size", "16x12"),))]
    tab = []
    for r in pov:
        trace = (ratio(r["pov_trace_median"], r["ours_trace_median"]),
                 ratio(r["pov_trace_cpu_median"], r["ours_trace_cpu_median"]))
        proc = (ratio(r["pov_wall_median"], r["ours_wall_median"]), ratio(r["pov_cpu_median"], r["ours_cpu_median"]))
        frame_cpu = ratio(r.get("pov_frame_cpu"), r.get("ours_frame_cpu"))
        ms = lambda k: "%.0f" % (r[k] * 1e3) if isinstance(r.get(k), (int, float)) else "n/a"
        tab.append([r["size"], "%.0f / %.0f" % (r["ours_trace_median"] * 1e3, r["ours_trace_cpu_median"] * 1e3),
                    "%.0f / %.0f" % (r["pov_trace_median"] * 1e3, r["pov_trace_cpu_median"] * 1e3),
                    "%s / %s" % (fmt_ratio(trace[0]), fmt_ratio(trace[1])),
                    "%.0f / %.0f" % (r["ours_wall_median"] * 1e3, r["ours_cpu_median"] * 1e3),
                    "%.0f / %.0f" % (r["pov_wall_median"] * 1e3, r["pov_cpu_median"] * 1e3),
                    "%s / %s" % (fmt_ratio(proc[0]), fmt_ratio(proc[1])),
                    "%s / %s" % (ms("ours_frame_cpu"), ms("pov_frame_cpu")), fmt_ratio(frame_cpu),
                    "%s / %s, %s / %s" % (ms("ours_fixed_wall_median"), ms("ours_fixed_cpu_median"),
                                          ms("pov_fixed_wall_median"), ms("pov_fixed_cpu_median")),
                    "%.0f" % (r["ours_trace_warm_median"] * 1e3),
                    "%.2g (SSIM %.4f, max %s/255)" % (r["image_rmse_8bit"], r.get("image_ssim", float("nan")),
                                                      r["image_max_levels"])])
        head.append(["classic %s vs POV-Ray 3.7, trace, %d thr each" % (r["size"], r["threads"]),
                     "%.0f ms (CPU %.0f)" % (r["ours_trace_median"] * 1e3, r["ours_trace_cpu_median"] * 1e3),
                     "%.0f ms (CPU %.0f)" % (r["pov_trace_median"] * 1e3, r["pov_trace_cpu_median"] * 1e3),
                     fmt_ratio(trace[0]), fmt_ratio(trace[1])])
        if "ours_frame_cpu" in r:
            head.append(["classic %s vs POV-Ray 3.7, frame CPU (process CPU above a %s run), %d thr each"
                         % (r["size"], r["fixed_size"], r["threads"]),
                         "CPU %s ms" % ms("ours_frame_cpu"), "CPU %s ms" % ms("pov_frame_cpu"), "-",
                         fmt_ratio(frame_cpu)])
        head.append(["classic %s vs POV-Ray 3.7, whole process, %d thr each" % (r["size"], r["threads"]),
                     "%.0f ms (CPU %.0f)" % (r["ours_wall_median"] * 1e3, r["ours_cpu_median"] * 1e3),
                     "%.0f ms (CPU %.0f)" % (r["pov_wall_median"] * 1e3, r["pov_cpu_median"] * 1e3),
                     fmt_ratio(proc[0]), fmt_ratio(proc[1])])
    L.append(md_table(["size", "Whitted trace ms (wall / CPU)", "POV-Ray trace ms (wall / CPU)",
                       "speed ratio trace (wall / CPU)", "Whitted process ms (wall / CPU)",
                       "POV-Ray process ms (wall / CPU)", "speed ratio process (wall / CPU)",
                       "frame CPU ms (Whitted / POV-Ray)", "speed ratio frame CPU",
                       "fixed cost ms, wall / CPU (Whitted, POV-Ray)", "Whitted warm trace ms",
                       "image difference (RMSE)"], tab))
    L.append(commands_block(ctx, "pov"))
    L.append("\n![pov](pov_compare.png)\n")
    return L
