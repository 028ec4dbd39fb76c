"""BVH build speed and memory against Embree low / medium / high, at equal thread counts (1 and all cores)."""
from .. import plots
from ..markdown import commands_block, fmt_ratio, md_table, ratio
from ..runner import available_scenes, fresh, is_num, read_csv


def run(ctx):
    c = ctx.cfg
    path = fresh(ctx.path("build.csv"))
    for s in available_scenes(c["build_scenes"], ctx.data):
        ctx.runner.run([ctx.bench, "build", "--scene", s, "--data", ctx.data, "--reps", str(c["build_reps"]),
                        "--warmup", "1", "--threads-list", "1,0", "--csv", path], "build " + s)


def outputs(ctx):
    return ["build.csv", "build.png"]


SAH, FAST = "Scene::commit SAH", "Scene::commit fast"


def read_build(ctx):
    """build.csv rows; results written before the SAH/fast split timed only `Scene::commit` of replaced geometry,
    which the scene rebuilds with the fast (Morton) builder: those rows are the fast variant."""
    rows = read_csv(ctx.path("build.csv"))
    for r in rows:
        if r["engine"] == "whitted" and r["variant"] == "Scene::commit":
            r["variant"] = FAST
    return rows


def report(ctx, head):
    build = read_build(ctx)
    if not build:
        return []
    plots.build(ctx, build)
    L = ["\n## BVH build against Embree\n",
         "Whitted: `Scene::commit` of freshly set geometry (validity checks, boxes, build, leaf-order copies) with "
         "the binned SAH builder (what new geometry gets) and with the fast Morton builder (what replaced geometry "
         "gets by default: time steps, edited geometry), and the SAH builder alone (`Bvh::build`) on precomputed "
         "boxes. The headline compares like with like: SAH against Embree medium and high, fast against Embree "
         "low (results written before this split timed only the fast commit, then labelled `Scene::commit`; the "
         "SAH row of such a run is `Bvh::build`). Equal threads on both sides: Embree gets a device with N "
         "threads; our builder, which starts its own threads, runs confined to N cores (CPU affinity of the "
         "building thread, which the threads it starts inherit). Ours and Embree alternate run by run. Memory: "
         "Whitted = BVH nodes + index arrays + leaf-ordered triangle indices; Embree = bytes its memory monitor "
         "reports for the build (its leaves embed the triangles), peak during the build in brackets. Primary "
         "Mrays/s (512x512, all threads) shows what each build quality buys.\n"]
    tab = []
    for r in build:
        cpu = r.get("cpu_seconds_median")
        tab.append([r["scene"], r["primitives"], r["engine"], r["variant"], r["threads"],
                    "%.1f / %.1f" % (r["seconds_median"] * 1e3, cpu * 1e3 if is_num(cpu) else float("nan")),
                    "%.2f" % r["mprims_per_s"], "%.1f (%.1f)" % (r["bytes_per_prim"], r["peak_bytes_per_prim"]),
                    "%.2f" % r["primary_mrays"] if is_num(r["primary_mrays"]) else ""])
    L.append(md_table(["scene", "prims", "engine", "variant", "threads", "ms (wall / CPU)", "Mprims/s",
                       "bytes/prim (peak)", "primary Mrays/s"], tab))
    L.append(commands_block(ctx, "build"))
    L.append("\n![build](build.png)\n")

    main = ctx.headline_scene if ctx.headline_scene in {r["scene"] for r in build} else build[0]["scene"]

    def pick(engine, variant, t):
        m = [r for r in build if r["scene"] == main and r["engine"] == engine and r["variant"] == variant and
             r["threads"] == t]
        return m[0] if m else None

    for t in sorted({r["threads"] for r in build}):
        commit_sah = pick("whitted", SAH, t)
        sah = commit_sah or pick("whitted", "Bvh::build", t)
        sah_name = "SAH build (Scene::commit)" if commit_sah else "SAH builder alone (Bvh::build)"
        for ours, name, qualities in [(sah, sah_name, ["medium", "high"]),
                                      (pick("whitted", FAST, t), "fast build (Scene::commit)", ["low"])]:
            for q in qualities:
                e = pick("embree", q, t)
                if ours and e:
                    head.append(["%s %s vs Embree %s, %d thr each (memory %.0f vs %.0f B/prim)" % (
                        name, main, q, t, ours["bytes_per_prim"], e["bytes_per_prim"]),
                        "%.2f Mprims/s" % ours["mprims_per_s"], "%.2f Mprims/s" % e["mprims_per_s"],
                        fmt_ratio(ratio(ours["mprims_per_s"], e["mprims_per_s"])),
                        fmt_ratio(ratio(e["cpu_seconds_median"], ours["cpu_seconds_median"]))])
    return L
