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


def report(ctx, head):
    build = read_csv(ctx.path("build.csv"))
    if not build:
        return []
    plots.build(ctx, build)
    L = ["\n## BVH build against Embree\n",
         "Whitted: `Scene::commit` of freshly set geometry (validity checks, boxes, binned SAH, leaf-order copies) "
         "and `Bvh::build` alone on precomputed boxes. Equal threads on both sides: Embree gets a device with N "
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
        o = pick("whitted", "Scene::commit", t)
        for q in ["low", "medium", "high"]:
            e = pick("embree", q, t)
            if o and e:
                head.append(["BVH build %s vs Embree %s, %d thr each (memory %.0f vs %.0f B/prim)" % (
                    main, q, t, o["bytes_per_prim"], e["bytes_per_prim"]), "%.2f Mprims/s" % o["mprims_per_s"],
                    "%.2f Mprims/s" % e["mprims_per_s"], fmt_ratio(ratio(o["mprims_per_s"], e["mprims_per_s"])),
                    fmt_ratio(ratio(e["cpu_seconds_median"], o["cpu_seconds_median"]))])
    return L
