"""The benchmark's PNG plots, each drawn from a section's CSV rows (matplotlib, Agg backend)."""
import math
import os
import statistics

from .config import DEFAULT_LABEL


def plt_module():
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    plt.rcParams.update({"font.size": 10, "axes.grid": True, "grid.alpha": 0.3, "savefig.dpi": 110})
    return plt


def plain_log_ticks(ax, axis="both"):
    """Log axes labelled 2, 5, 10, 20 ... instead of 2x10^0."""
    from matplotlib.ticker import FuncFormatter, LogLocator
    fmt = FuncFormatter(lambda v, _: ("%g" % v) if v >= 1e-3 else ("%.0e" % v))
    for a in ([ax.xaxis] if axis == "x" else [ax.yaxis] if axis == "y" else [ax.xaxis, ax.yaxis]):
        if a.get_scale() != "log":
            continue
        a.set_major_locator(LogLocator(base=10, subs=(1.0, 2.0, 5.0)))
        a.set_major_formatter(fmt)
        a.set_minor_formatter(FuncFormatter(lambda v, _: ""))


def pov(ctx, row):
    """Our image, POV-Ray's and their difference (first size); kept as it is when the images are not there (a
    results folder kept without them)."""
    images = [ctx.path("pov_%s_%s.png" % (who, row["size"])) for who in ("ours", "povray")]
    if not all(os.path.exists(f) for f in images):
        return
    plt = plt_module()
    import matplotlib.image as mpimg
    import numpy as np
    a, b = (mpimg.imread(f)[..., :3] for f in images)
    fig, ax = plt.subplots(1, 3, figsize=(15, 4.4))
    ax[0].imshow(a)
    ax[0].set_title("Whitted: trace %.0f ms (process %.0f ms)" % (row["ours_trace_median"] * 1e3,
                                                                  row["ours_wall_median"] * 1e3))
    ax[1].imshow(b)
    ax[1].set_title("POV-Ray 3.7: trace %.0f ms (process %.0f ms)" % (row["pov_trace_median"] * 1e3,
                                                                     row["pov_wall_median"] * 1e3))
    if a.shape == b.shape:
        ax[2].imshow(np.clip(np.abs(a - b).max(axis=2) * 4, 0, 1), cmap="magma", vmin=0, vmax=1)
    ax[2].set_title("|difference| x 4 (RMSE %.2g, max %d/255)" % (row["image_rmse_8bit"], row["image_max_levels"]))
    for x in ax:
        x.axis("off")
    fig.suptitle("Classic scene %s, depth %d (POV max_trace_level %d), %d threads, no antialiasing" % (
        row["size"], row["depth"], row["pov_max_trace_level"], row["threads"]))
    fig.tight_layout(rect=[0, 0, 1, 0.94])
    fig.savefig(ctx.path("pov_compare.png"))
    plt.close(fig)


def vtk(ctx, frames, rows):
    """Our images and VTK's (OpenGL, shadow maps, vtkWhittedPass) side by side with their frame times."""
    plt = plt_module()
    import matplotlib.image as mpimg
    labels = {"opengl": "VTK OpenGL", "shadowmap": "VTK OpenGL + shadow maps", "whitted": "vtkWhittedPass"}
    scene = frames[-1]["scene"]
    panels = []
    for spp in sorted({r["spp"] for r in frames}):
        t = statistics.mean(r["seconds_median"] for r in frames if r["spp"] == spp)
        panels.append((ctx.path("vtk_ours_%s_spp%d.png" % (scene, spp)),
                       "Whitted core, shadows, %d spp: %.0f ms" % (spp, t * 1e3)))
    for r in rows:
        if r.get("status") == "ok" and r.get("screenshot"):
            samples = "%d spp" % r.get("spp", 1) if r["mode"] == "whitted" else "MSAA %d" % r["msaa"]
            panels.append((ctx.path(r["screenshot"]), "%s, %s: %.0f ms" % (labels[r["mode"]], samples,
                                                                          r["seconds_median"] * 1e3)))
    panels = [p for p in panels if os.path.exists(p[0])]
    if not panels:
        return
    cols = min(3, len(panels))
    nrows = (len(panels) + cols - 1) // cols
    fig, ax = plt.subplots(nrows, cols, figsize=(5.2 * cols, 5.4 * nrows), squeeze=False)
    ax = list(ax.flat)
    for x in ax:
        x.axis("off")
    for x, (p, title) in zip(ax, panels):
        x.imshow(mpimg.imread(p))
        x.set_title(title, fontsize=11)
    fig.suptitle("%s at %dx%d (median frame time after a camera move)" % (scene, frames[-1]["width"],
                                                                         frames[-1]["height"]))
    fig.tight_layout(rect=[0, 0, 1, 0.94])
    fig.savefig(ctx.path("vtk_compare.png"))
    plt.close(fig)


def rays(ctx, rays):
    """Mrays/s per scene and ray kind: Whitted solid, Embree hatched, Embree robust dotted."""
    plt = plt_module()
    import numpy as np
    scenes = list(dict.fromkeys(r["scene"] for r in rays))
    kinds = ["primary", "shadow", "shadow4", "incoherent"]
    engines = [("whitted", "Whitted", 1.0, None), ("embree", "Embree", 0.45, "//"),
               ("embree-robust", "Embree robust", 0.3, "..")]
    threads = sorted({r["threads"] for r in rays})
    fig, axes = plt.subplots(1, len(threads), figsize=(8 * len(threads), 4.8), squeeze=False)
    width = 0.8 / (len(kinds) * len(engines))
    for ax, t in zip(axes[0], threads):
        x = np.arange(len(scenes))
        for k, kind in enumerate(kinds):
            for e, (eng, label, alpha, hatch) in enumerate(engines):
                vals = []
                for s in scenes:
                    m = [r["mrays_median"] for r in rays if r["scene"] == s and r["kind"] == kind and
                         r["threads"] == t and r["engine"] == eng]
                    vals.append(m[0] if m else 0)
                off = (len(engines) * k + e - (len(kinds) * len(engines) - 1) / 2) * width
                ax.bar(x + off, vals, width, color="C%d" % k, alpha=alpha, hatch=hatch, edgecolor="k",
                       linewidth=0.3, label="%s %s" % (label, kind))
        ax.set_xticks(x)
        ax.set_xticklabels(scenes, rotation=20)
        ax.set_yscale("log")
        plain_log_ticks(ax, "y")
        ax.set_ylabel("Mrays/s (log)")
        ax.set_title("%d thread%s" % (t, "s" if t > 1 else ""))
    handles, labels = axes[0][0].get_legend_handles_labels()
    fig.legend(handles, labels, fontsize=8, ncol=len(kinds) * len(engines) // 2 + 1, loc="lower center")
    fig.suptitle("Ray throughput: Whitted (solid) vs Embree 3 default (hatched) and robust (dotted), same rays")
    fig.tight_layout(rect=[0, 0.1, 1, 1])
    fig.savefig(ctx.path("rays.png"))
    plt.close(fig)


def build(ctx, build):
    """Build speed (left) and memory (right) per scene, ours and Embree's, at each thread count."""
    plt = plt_module()
    import numpy as np
    scenes = list(dict.fromkeys(r["scene"] for r in build))
    threads = sorted({r["threads"] for r in build})
    variants = [("whitted", "Scene::commit SAH"), ("whitted", "Scene::commit fast")] + [
        ("embree", q) for q in ("low", "medium", "high")]
    ours_style = {"Scene::commit SAH": ("k", "Whitted SAH"), "Scene::commit fast": ("0.45", "Whitted fast")}
    fig, ax = plt.subplots(1, 2, figsize=(13, 4.6))
    x = np.arange(len(scenes))
    bars = [(eng, var, t) for t in threads for eng, var in variants]
    width = 0.8 / len(bars)

    def pick(s, eng, var, t):
        m = [r for r in build if r["scene"] == s and r["engine"] == eng and r["variant"] == var and r["threads"] == t]
        return m[0] if m else None

    for i, (eng, var, t) in enumerate(bars):
        sp = [(pick(s, eng, var, t) or {}).get("mprims_per_s", 0) for s in scenes]
        label = "%s, %d thr" % (ours_style[var][1] if eng == "whitted" else "Embree " + var, t)
        color = ours_style[var][0] if eng == "whitted" else "C%d" % ["low", "medium", "high"].index(var)
        ax[0].bar(x + (i - len(bars) / 2 + 0.5) * width, sp, width, color=color,
                  alpha=1.0 if t == threads[-1] else 0.5, label=label)
    for i, (eng, var) in enumerate(variants):
        mem = [(pick(s, eng, var, threads[-1]) or {}).get("bytes_per_prim", 0) for s in scenes]
        ax[1].bar(x + (i - len(variants) / 2 + 0.5) * 0.16, mem, 0.16,
                  color=ours_style[var][0] if eng == "whitted" else "C%d" % ["low", "medium", "high"].index(var),
                  label=ours_style[var][1] if eng == "whitted" else "Embree " + var)
    ax[0].set_yscale("log")
    plain_log_ticks(ax[0], "y")
    ax[0].set_ylabel("build speed, Mprims/s (log)")
    ax[1].set_ylabel("acceleration structure, bytes per primitive")
    for a in ax:
        a.set_xticks(x)
        a.set_xticklabels(scenes)
    ax[0].legend(fontsize=8, ncol=2)
    ax[1].legend(fontsize=8)
    ax[0].set_title("BVH build speed (equal threads; faded: fewer threads)")
    ax[1].set_title("BVH memory")
    fig.tight_layout()
    fig.savefig(ctx.path("build.png"))
    plt.close(fig)


def scaling(ctx, frames, build):
    """Time vs triangles, vs image size, and thread efficiency."""
    plt = plt_module()
    fig, ax = plt.subplots(1, 3, figsize=(16, 4.6))
    tri = sorted([r for r in frames if r["tag"] == "scale-triangles"], key=lambda r: r["primitives"])
    if tri:
        n = [r["primitives"] for r in tri]
        ax[0].loglog(n, [r["seconds_median"] * 1e3 for r in tri], "o-", label="Whitted trace (%dx%d, %d thr)" % (
            tri[0]["width"], tri[0]["height"], tri[0]["threads"]))
        if all(isinstance(r.get("cpu_seconds_median"), float) for r in tri):
            ax[0].loglog(n, [r["cpu_seconds_median"] * 1e3 for r in tri], "o:", color="C0", alpha=0.6,
                         label="Whitted trace, CPU time (all threads)")
        for variant, name in [("Scene::commit SAH", "SAH"), ("Scene::commit fast", "fast")]:
            wb = {r["primitives"]: r["seconds_median"] for r in build if r["variant"] == variant and
                  r["threads"] == ctx.threads}
            if wb:
                pts = [(r["primitives"], wb[r["primitives"]] * 1e3) for r in tri if r["primitives"] in wb]
                if pts:
                    ax[0].loglog(*zip(*pts), "s-", label="Whitted BVH build (commit, %s), %d thr" % (
                        name, ctx.threads))
        em = {r["primitives"]: r["seconds_median"] * 1e3 for r in build if r["engine"] == "embree" and
              r["variant"] == "medium" and r["threads"] == ctx.threads}
        pts = [(k, em[k]) for k in n if k in em]
        if pts:
            ax[0].loglog(*zip(*pts), "^--", label="Embree build, medium, %d thr" % ctx.threads)
        ax[0].set_xlabel("triangles")
        ax[0].set_ylabel("ms")
        ax[0].set_title("Time vs triangle count (isosurfaces)")
        ax[0].legend(fontsize=8)
        plain_log_ticks(ax[0], "y")
    sz = sorted([r for r in frames if r["tag"] == "scale-size"], key=lambda r: r["width"] * r["height"])
    if sz:
        px = [r["width"] * r["height"] for r in sz]
        ms = [r["seconds_median"] * 1e3 for r in sz]
        ax[1].loglog(px, ms, "o-", label="%s trace" % sz[0]["scene"])
        if all(isinstance(r.get("cpu_seconds_median"), float) for r in sz):
            ax[1].loglog(px, [r["cpu_seconds_median"] * 1e3 for r in sz], "o:", color="C0", alpha=0.6,
                         label="%s trace, CPU time" % sz[0]["scene"])
        ax[1].loglog(px, [ms[0] * p / px[0] for p in px], ":", color="gray", label="linear in pixels")
        ax[1].set_xlabel("pixels")
        ax[1].set_ylabel("ms")
        ax[1].set_title("Time vs image size (%d threads)" % sz[0]["threads"])
        ax[1].legend(fontsize=8)
        plain_log_ticks(ax[1], "y")
    th = [r for r in frames if r["tag"] == "scale-threads"]
    for i, s in enumerate(dict.fromkeys(r["scene"] for r in th)):
        rs = sorted([r for r in th if r["scene"] == s], key=lambda r: r["threads"])
        t1 = [r["seconds_median"] for r in rs if r["threads"] == 1]
        if not t1:
            continue
        ax[2].plot([r["threads"] for r in rs], [t1[0] / (r["seconds_median"] * min(r["threads"], ctx.threads))
                                                for r in rs], "o-", color="C%d" % i, label="%s (wall)" % s)
        c1 = [r.get("cpu_seconds_median") for r in rs if r["threads"] == 1]
        if c1 and isinstance(c1[0], float):
            ax[2].plot([r["threads"] for r in rs], [c1[0] / r["cpu_seconds_median"] for r in rs], "s--", color="C%d" % i,
                       alpha=0.7, label="%s (CPU: threading overhead only)" % s)
    ax[2].axhline(1.0, color="gray", ls=":")
    ax[2].axvline(ctx.threads, color="gray", ls="--", lw=0.8)
    ax[2].set_ylim(0, 1.2)
    if th:
        ax[2].set_xticks(sorted({r["threads"] for r in th}))
    ax[2].set_xlabel("threads (dashed: hardware threads)")
    ax[2].set_ylabel("efficiency: T1 / (min(n, cores) Tn); CPU1 / CPUn")
    ax[2].set_title("Thread scaling")
    if th:
        ax[2].legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(ctx.path("scaling.png"))
    plt.close(fig)


def update(ctx, upd):
    """Commit and trace time per edit case."""
    plt = plt_module()
    fig, ax = plt.subplots(figsize=(10, 4.2))
    names = [r["case"] for r in upd]
    c = [r["commit_seconds"] * 1e3 for r in upd]
    t = [r["trace_seconds"] * 1e3 for r in upd]
    y = range(len(names))
    ax.barh(y, c, color="C3", label="commit (BVH rebuilds)")
    ax.barh(y, t, left=c, color="C0", label="trace")
    for i in y:
        ax.text(c[i] + t[i], i, " %.0f ms" % (c[i] + t[i]), va="center", fontsize=9)
    ax.set_yticks(list(y))
    ax.set_yticklabels(names)
    ax.invert_yaxis()
    ax.set_xlabel("ms (median)")
    ax.set_title("Re-render cost after an edit: %s, %d instances, %dx%d" % (
        upd[0]["scene"], upd[0]["instances"], upd[0]["width"], upd[0]["height"]))
    ax.legend(loc="upper right")
    ax.set_xlim(0, max(a + b for a, b in zip(c, t)) * 1.15)
    fig.tight_layout()
    fig.savefig(ctx.path("update.png"))
    plt.close(fig)


SAMPLING_LABELS = {(1, 0): "1 spp", (4, 0): "4 spp", (4, 1): "4 spp adaptive", (16, 0): "16 spp",
                   (16, 1): "16 spp adaptive"}


def pareto(points):
    """Indices of the points not dominated in (time, error), sorted by time."""
    idx = sorted(range(len(points)), key=lambda i: (points[i][0], points[i][1]))
    front, best = [], float("inf")
    for i in idx:
        if points[i][1] < best:
            front.append(i)
            best = points[i][1]
    return front


def error(ctx, err, tkey, tlabel, progressive=()):
    """Per scene: RMSE and 1 - SSIM against cost, the Pareto front, the default marked, and the progressive mode's
    curve (error against cost at increasing time budgets); returns the file names."""
    plt = plt_module()
    out = []
    for scene in dict.fromkeys(r["scene"] for r in err):
        rows = [r for r in err if r["scene"] == scene and not r["is_reference"]]
        if not rows:
            continue
        ref = [r for r in err if r["scene"] == scene and r["is_reference"]][0]
        fig, ax = plt.subplots(1, 2, figsize=(14, 5.2))
        for k, (metric, ylabel) in enumerate([("rmse", "RMSE vs reference (linear RGB in [0,1])"),
                                              ("one_minus_ssim", "1 - SSIM vs reference")]):
            a = ax[k]
            val = (lambda r: max(1e-6, 1 - r["ssim"])) if metric == "one_minus_ssim" else (lambda r: max(1e-6, r["rmse"]))
            for i, key in enumerate(SAMPLING_LABELS):
                sel = [r for r in rows if (r["spp"], r["adaptive"]) == key]
                if sel:
                    a.scatter([r[tkey] * 1e3 for r in sel], [val(r) for r in sel], s=14,
                              color="C%d" % i, alpha=0.7, label=SAMPLING_LABELS[key])
            pts = [(r[tkey], val(r)) for r in rows]
            front = pareto(pts)
            a.plot([pts[i][0] * 1e3 for i in front], [pts[i][1] for i in front], "k-", lw=1.2, drawstyle="steps-post",
                   label="Pareto front")
            placed = []
            for i in front:
                r = rows[i]
                lx, ly = math.log10(pts[i][0] * 1e3), math.log10(pts[i][1])
                if any(abs(lx - px) < 0.15 and abs(ly - py) < 0.06 for px, py in placed):
                    continue  # too close to a label already drawn
                placed.append((lx, ly))
                a.annotate("d%d t%.0f%s" % (r["depth"], r["threshold"] * 255,
                                            "" if r["spp"] == 1 else " %d%s" % (r["spp"], "a" if r["adaptive"] else "")),
                           (pts[i][0] * 1e3, pts[i][1]), fontsize=7, xytext=(4, 3), textcoords="offset points")
            prog = sorted([r for r in progressive if r["scene"] == scene], key=lambda r: r[tkey])
            if prog:
                a.plot([r[tkey] * 1e3 for r in prog], [val(r) for r in prog], "m-o", ms=4, lw=1.2,
                       label="progressive (TimeBudget)")
            d = [r for r in rows if r["is_default"]]
            if d:
                a.scatter([d[0][tkey] * 1e3], [val(d[0])], marker="*", s=260, color="gold",
                          edgecolor="k", zorder=5, label="default (%s)" % DEFAULT_LABEL)
            a.set_xscale("log")
            a.set_yscale("log")
            a.set_xlabel(tlabel % ctx.threads if "%d" in tlabel else tlabel)
            a.set_ylabel(ylabel)
            plain_log_ticks(a)
        ax[0].legend(fontsize=7.5, loc="lower left")  # nothing lies below-left of the Pareto front
        size = "%s" % ctx.cfg["error_size"]
        fig.suptitle("%s %s: error vs cost (labels on the front: d = depth, t = threshold x 255, then spp, a = "
                     "adaptive); reference %d spp, depth %d, threshold 0: %.1f s" % (
                         scene, size, ref["spp"], ref["depth"], ref[tkey]), fontsize=10)
        fig.tight_layout(rect=[0, 0, 1, 0.95])
        name = "error_%s.png" % scene
        fig.savefig(ctx.path(name))
        plt.close(fig)
        out.append(name)
    return out


def estimate(ctx, err):
    """The renderer's error estimate against the measured error."""
    rows = [r for r in err if not r["is_reference"]]
    if not rows:
        return
    plt = plt_module()
    fig, ax = plt.subplots(1, 2, figsize=(13, 5.2))
    lo = 1e-5
    for i, scene in enumerate(dict.fromkeys(r["scene"] for r in rows)):
        sel = [r for r in rows if r["scene"] == scene]
        for a, key in zip(ax, ["trunc_rms", "rmse"]):
            fixed = [r for r in sel if not r["adaptive"]]
            adap = [r for r in sel if r["adaptive"]]
            a.scatter([max(lo, r[key]) for r in fixed], [max(lo, r["est_rms"]) for r in fixed], s=14, color="C%d" % i,
                      alpha=0.7, label=scene)
            a.scatter([max(lo, r[key]) for r in adap], [max(lo, r["est_rms"]) for r in adap], s=14, color="C%d" % i,
                      alpha=0.7, marker="x")
    for a in ax:
        a.plot([lo, 1], [lo, 1], "k--", lw=1, label="estimate = measured")
        a.set_xscale("log")
        a.set_yscale("log")
        a.set_xlim(lo / 2, 1.5)
        a.set_ylim(lo / 2, 1.5)
        a.set_ylabel("FrameStats::truncation.rms")
    ax[0].set_xlabel("measured: RMS over pixels of max-channel error vs same samples at depth %d, threshold 0" %
                     ctx.cfg["error_ref_depth"])
    ax[1].set_xlabel("measured: RMSE vs the high-quality reference (includes sampling error)")
    ax[0].set_title("What the estimate bounds (points above the line: bound holds)")
    ax[1].set_title("Total error (the estimate does not cover sampling)")
    ax[0].legend(fontsize=8, loc="upper left")
    fig.suptitle("Renderer's error estimate vs measured error (o: fixed sampling, x: adaptive; zeros drawn at 1e-5)")
    fig.tight_layout(rect=[0, 0, 1, 0.95])
    fig.savefig(ctx.path("error_estimate.png"))
    plt.close(fig)


def volume_steps(ctx, rows):
    """The volume step study: error against the reference step, by step and by frame time (log-log)."""
    plt = plt_module()
    fig, (a1, a2) = plt.subplots(1, 2, figsize=(10, 4))
    rows = sorted(rows, key=lambda r: -r["step"])
    step = [r["step"] for r in rows]
    err = [max(r["rmse"], 1e-9) for r in rows]
    ms = [r["seconds_median"] * 1e3 for r in rows]
    a1.loglog(step, err, "o-", label="RMSE against step %g" % rows[0]["reference_step"])
    # Second order: error proportional to step^2 through the largest step
    a1.loglog(step, [err[0] * (s / step[0]) ** 2 for s in step], "--", color="grey", label="slope 2")
    if all("step_estimate_rms" in r for r in rows):  # the step's error estimate beside the measured, in its units
        a1.loglog(step, [max(r["max_channel_rms"], 1e-9) for r in rows], "s-", label="measured, largest channel")
        a1.loglog(step, [max(r["step_estimate_rms"], 1e-9) for r in rows], "^-", label="the step's estimate")
    a1.set_xlabel("sample distance (world units)")
    a1.set_ylabel("RMSE (linear RGB)")
    a1.legend()
    a2.loglog(ms, err, "o-")
    for s, x, y in zip(step, ms, err):
        a2.annotate("%g" % s, (x, y), textcoords="offset points", xytext=(4, 4), fontsize=8)
    a2.set_xlabel("frame ms (median, %s threads)" % rows[0]["threads"])
    a2.set_ylabel("RMSE (linear RGB)")
    for ax in (a1, a2):
        plain_log_ticks(ax)
    fig.suptitle("Volume step: %s %dx%d" % (rows[0]["scene"], rows[0]["width"], rows[0]["height"]))
    fig.tight_layout()
    fig.savefig(ctx.path("volume_steps.png"))
    plt.close(fig)
