"""Scaling of our frame time with triangles, image size and threads."""
from .. import plots
from ..markdown import commands_block, md_table
from ..runner import available_scenes, drop_tags, read_csv
from . import build as build_section


def run(ctx):
    c = ctx.cfg
    frames = ctx.path("frames.csv")
    drop_tags(frames, ["scale"])
    common = ["--data", ctx.data, "--reps", str(c["frame_reps"]), "--warmup", "1", "--csv", frames]
    for s in available_scenes(c["scaling_tri"], ctx.data):
        ctx.runner.run([ctx.bench, "frame", "--scene", s, "--sizes", c["scaling_thread_size"], "--threads-list", "0",
                        "--tag", "scale-triangles"] + common, "scaling triangles " + s)
    s = c["scaling_size_scene"]
    if available_scenes([s], ctx.data):
        ctx.runner.run([ctx.bench, "frame", "--scene", s, "--sizes", ",".join(c["scaling_sizes"]), "--threads-list",
                        "0", "--tag", "scale-size"] + common, "scaling image size " + s)
    threads = sorted({1, 2, ctx.threads} | ({ctx.threads * 2} if not c["quick"] else set()))
    for s in available_scenes(c["scaling_thread_scenes"], ctx.data):
        ctx.runner.run([ctx.bench, "frame", "--scene", s, "--sizes", c["scaling_thread_size"], "--threads-list",
                        ",".join(map(str, threads)), "--tag", "scale-threads"] + common, "scaling threads " + s)


def outputs(ctx):
    return ["frames.csv", "scaling.png"]


def report(ctx, head):
    frames = [r for r in read_csv(ctx.path("frames.csv")) if r["tag"].startswith("scale")]
    if not frames:
        return []
    plots.scaling(ctx, frames, build_section.read_build(ctx))
    tab = [[r["tag"][6:], r["scene"], r["primitives"], "%dx%d" % (r["width"], r["height"]), r["threads"],
            "%.1f" % (r["commit_seconds"] * 1e3), "%.1f" % (r["seconds_median"] * 1e3), "%.2f" % r["mrays"]]
           for r in frames]
    return ["\n## Scaling\n",
            md_table(["sweep", "scene", "prims", "size", "threads", "build ms", "trace ms", "Mrays/s"], tab),
            commands_block(ctx, "scaling"),
            "\nParallel efficiency is T1 / (min(n, cores) x Tn); thread counts above the core count show the cost "
            "of oversubscription.\n\n![scaling](scaling.png)\n"]
