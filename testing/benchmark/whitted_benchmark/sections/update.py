"""Update cost: what caching leaves out when the camera, a material, one actor or a mesh changes."""
from .. import plots
from ..markdown import commands_block, md_table
from ..runner import available_scenes, fresh, is_num, read_csv


def run(ctx):
    c = ctx.cfg
    path = fresh(ctx.path("update.csv"))
    s = c["update_scene"]
    if not available_scenes([s], ctx.data):
        ctx.notes.append("mesh for %s missing: update section skipped" % s)
        return
    ctx.runner.run([ctx.bench, "update", "--scene", s, "--data", ctx.data, "--size", c["update_size"], "--reps",
                    str(c["update_reps"]), "--warmup", "1", "--csv", path], "update " + s)


def outputs(ctx):
    return ["update.csv", "update.png"]


def report(ctx, head):
    upd = read_csv(ctx.path("update.csv"))
    if not upd:
        return []
    plots.update(ctx, upd)

    def cpu_ms(r, k):
        return "%.1f" % (r[k] * 1e3) if is_num(r.get(k)) else ""

    return ["\n## Update cost (what caching leaves out)\n",
            "%s plus %d small glyph actors (UV spheres, ~16k triangles each) at %dx%d. Each case edits the scene, "
            "calls commit() and renders; 'full rebuild' re-sets every object, as an adapter without caching "
            "would.\n" % (upd[0]["scene"], upd[0]["instances"] - 1, upd[0]["width"], upd[0]["height"]),
            md_table(["case", "commit ms (wall / CPU)", "trace ms (wall / CPU)", "total ms", "objects rebuilt",
                      "top level rebuilt"],
                     [[r["case"], "%.2f / %s" % (r["commit_seconds"] * 1e3, cpu_ms(r, "commit_cpu_seconds")),
                       "%.1f / %s" % (r["trace_seconds"] * 1e3, cpu_ms(r, "trace_cpu_seconds")),
                       "%.1f" % (r["total_seconds"] * 1e3), r["objects_rebuilt"], r["top_level_rebuilt"]]
                      for r in upd]),
            commands_block(ctx, "update"),
            "\n![update](update.png)\n"]
