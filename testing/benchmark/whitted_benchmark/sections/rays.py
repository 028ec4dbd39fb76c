"""Ray throughput against Embree 3, default mode and robust mode (RTC_SCENE_FLAG_ROBUST), on the same rays."""
from .. import plots
from ..markdown import commands_block, fmt_ratio, geomean, md_table, ratio
from ..runner import available_scenes, fresh, is_num, read_csv

KINDS = ["primary", "shadow", "shadow4", "incoherent"]
ANCHORS = [("embree", "Embree"), ("embree-robust", "Embree robust")]


def run(ctx):
    c = ctx.cfg
    path = fresh(ctx.path("rays.csv"))
    agree = fresh(ctx.path("rays_agreement.csv"))
    for s in available_scenes(c["ray_scenes"], ctx.data):
        ctx.runner.run([ctx.bench, "rays", "--scene", s, "--data", ctx.data, "--size", c["ray_size"], "--reps",
                        str(c["ray_reps"]), "--warmup", "1", "--threads-list", "1,0", "--csv", path,
                        "--agreement-csv", agree], "rays " + s)


def outputs(ctx):
    return ["rays.csv", "rays.png"]


def _cpu_rate(r):
    v = r.get("mrays_per_cpu_second") if r else None
    return v if is_num(v) and v > 0 else float("nan")


def report(ctx, head):
    rays = read_csv(ctx.path("rays.csv"))
    agree = read_csv(ctx.path("rays_agreement.csv"))
    if not rays:
        return []
    plots.rays(ctx, rays)

    def pick(s, kind, t, eng):
        m = [r for r in rays if r["scene"] == s and r["kind"] == kind and r["threads"] == t and r["engine"] == eng]
        return m[0] if m else None

    L = ["## Ray throughput against Embree %s\n" % ctx.env.get("embree", "3"),
         "Same rays for every engine (%s image: primary rays through pixel centres; shadow rays from every primary "
         "hit to the first light; incoherent rays in uniform random directions over the hemisphere facing the "
         "viewer). Secondary rays start at our robust offset origin with tMin = 1e-5 x scene diagonal; materials "
         "are made opaque so the shadow query is a pure any-hit (Scene::transmittance vs rtcOccluded1); shadow4: "
         "the same shadow rays as packets of four consecutive ones (Scene::occludedPacket vs rtcOccluded4); closest "
         "hits use Scene::intersect vs rtcIntersect1 (single-ray calls on both sides, the same work-sharing loop "
         "and thread count). Geometry is rounded to float so all engines see identical primitives. One Embree "
         "geometry per instance (triangles, SPHERE_POINT, ROUND_LINEAR_CURVE), build quality medium, in its "
         "default mode and with `RTC_SCENE_FLAG_ROBUST` (conservative traversal, watertight: the like-for-like "
         "anchor of our exact traversal). The three engines alternate run by run.\n" % ctx.cfg["ray_size"]]
    tab = []
    threads = sorted({r["threads"] for r in rays})
    for s in dict.fromkeys(r["scene"] for r in rays):
        for kind in KINDS:
            for t in threads:
                o = pick(s, kind, t, "whitted")
                if not o:
                    continue
                row = [s, kind, t, o["rays"], "%.2f" % o["mrays_median"]]
                for eng, _ in ANCHORS:
                    e = pick(s, kind, t, eng)
                    row += ["%.2f" % e["mrays_median"] if e else "n/a",
                            "%s / %s" % (fmt_ratio(ratio(o["mrays_median"], e["mrays_median"])),
                                         fmt_ratio(ratio(_cpu_rate(o), _cpu_rate(e)))) if e else "n/a"]
                row.append("%.0f" % o["nodes_per_ray"] if is_num(o["nodes_per_ray"]) else "")
                tab.append(row)
    L.append(md_table(["scene", "rays", "threads", "count", "Whitted Mrays/s", "Embree Mrays/s",
                       "speed ratio vs Embree (wall / CPU)", "Embree robust Mrays/s",
                       "speed ratio vs robust (wall / CPU)", "Whitted nodes/ray"], tab))
    L.append("\nSpeed ratio (CPU time) compares rays per CPU-second of the tracing threads: immune to other jobs "
             "taking cores away, which the wall-time ratio is only partly (the engines alternate run by run).\n")
    L.append(commands_block(ctx, "rays"))
    L.append("\n![rays](rays.png)\n")

    scenes = list(dict.fromkeys(r["scene"] for r in rays))
    main = ctx.headline_scene if ctx.headline_scene in scenes else scenes[0]
    for eng, label in ANCHORS:
        for kind in KINDS:
            for t in threads:
                ratios = [ratio(pick(s, kind, t, "whitted")["mrays_median"], pick(s, kind, t, eng)["mrays_median"])
                          for s in scenes if pick(s, kind, t, "whitted") and pick(s, kind, t, eng)]
                o, e = pick(main, kind, t, "whitted"), pick(main, kind, t, eng)
                if o and e:
                    head.append(["%s rays, %d thr, %s vs %s (geomean over %d scenes: %s)" % (
                        kind, t, main, label, len(ratios), fmt_ratio(geomean(ratios))),
                        "%.2f Mrays/s" % o["mrays_median"], "%s %.2f Mrays/s" % (label, e["mrays_median"]),
                        fmt_ratio(ratio(o["mrays_median"], e["mrays_median"])),
                        fmt_ratio(ratio(_cpu_rate(o), _cpu_rate(e)))])
    if agree:
        L.append("\nHit agreement with each anchor (differences at shared edges and grazing hits are expected; a "
                 "'tie' is a different primitive at the same distance within 1e-4):\n")
        L.append(md_table(["scene", "rays", "anchor", "count", "hits Whitted", "hits anchor", "hit/miss differ",
                           "other primitive", "of which ties", "max rel. t diff", "99.9% rel. t diff"],
                          [[a["scene"], a["kind"], a.get("anchor", "embree"), a["rays"], a["hits_ours"],
                            a["hits_embree"], a["hit_mismatch"], a["prim_mismatch"], a["prim_mismatch_same_t"],
                            "%.2g" % a["t_rel_err_max"], "%.2g" % a["t_rel_err_p999"]] for a in agree]))
    return L
