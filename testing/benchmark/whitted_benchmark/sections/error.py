"""Error against run time: a sweep of samples per pixel x depth x contribution threshold against a high-quality
reference, the Pareto front, and the renderer's error estimate against the error it bounds."""
import statistics

from .. import plots
from ..config import DEFAULT_LABEL
from ..markdown import commands_block, md_table
from ..runner import available_scenes, fresh, read_csv


def run(ctx):
    c = ctx.cfg
    path = fresh(ctx.path("error.csv"))
    for s in available_scenes(c["error_scenes"], ctx.data):
        cmd = [ctx.bench, "error", "--scene", s, "--data", ctx.data, "--size", c["error_size"], "--ref-spp",
               str(c["error_ref_spp"]), "--ref-depth", str(c["error_ref_depth"]), "--reps", str(c["error_reps"]),
               "--warmup", "1", "--budget", str(c["error_budget"]), "--csv", path, "--png-dir", ctx.out]
        if c["quick"]:
            cmd.append("--quick")
        if c.get("error_progressive_only"):
            cmd.append("--progressive-only")
        if c.get("error_budgets"):
            cmd += ["--budgets", c["error_budgets"]]
        ctx.runner.run(cmd, "error " + s)


def outputs(ctx):
    return ["error.csv", "error_estimate.png"] + ["error_%s.png" % s for s in ctx.cfg["error_scenes"]]


def time_key(err):
    """Cost axis of the error study: CPU time of the render when recorded (stable on a shared machine; on an
    idle machine it is threads x wall time), else wall time."""
    if err and all(isinstance(r.get("cpu_seconds_median"), float) and r["cpu_seconds_median"] > 0 for r in err):
        return "cpu_seconds_median", "render CPU time, ms (median, all %d threads summed, log)"
    return "seconds_median", "render time, ms (median, wall, log)"


def dominated_by(rows, d, key, tol=0.1):
    """Settings clearly better than d: >= tol faster at no more error, or >= tol less error at no more time."""
    # A cheaper setting must also trace fewer rays: settings that give the same image with the same rays (e.g.
    # any depth in a scene without mirrors) differ only by timing noise
    return [r for r in rows if r is not d and (
        (r[key] <= (1 - tol) * d[key] and r["rays"] < d["rays"] and r["rmse"] <= d["rmse"]) or
        (r[key] <= d[key] and r["rmse"] <= (1 - tol) * d["rmse"]))]


def report(ctx, head):
    everything = read_csv(ctx.path("error.csv"))
    err = [r for r in everything if not r.get("progressive")]
    progressive = [r for r in everything if r.get("progressive")]
    if not err:
        return []
    tkey, tlabel = time_key(err)
    error_plots = plots.error(ctx, err, tkey, tlabel, progressive)
    plots.estimate(ctx, err)
    c = ctx.cfg
    L = ["\n## Error against run time\n",
         "Reference per scene: %d spp, depth %d, threshold 0. Sweep: spp 1/4/16 (4 and 16 also adaptive) x depth "
         "1..8 x threshold 0, 1, 4, 16, 64 /255 (scenes without mirrors or glass: sampling only, since depth and "
         "threshold cannot change them). Error on linear RGB clamped to [0,1]; SSIM: Gaussian 11x11, sigma 1.5, "
         "mean over RGB. Full data: `error.csv`. Defaults: %s.\n" % (c["error_ref_spp"], c["error_ref_depth"],
                                                                     DEFAULT_LABEL),
         "Cost is measured as %s. On a shared machine (see load average) wall times of millisecond renders scatter "
         "by 2x, CPU time and the ray count (`rays` in the CSV, machine-independent) do not. 'Clearly better' = at "
         "least 10%% less cost at no more RMSE (and fewer rays traced), or at least 10%% less RMSE at no more "
         "cost.\n" % ("the CPU time of the render (all threads)" if tkey.startswith("cpu") else "wall time")]
    tab = []
    desc = lambda r: "spp %d%s d%d t%.0f" % (r["spp"], "a" if r["adaptive"] else "", r["depth"], r["threshold"] * 255)
    for scene in dict.fromkeys(r["scene"] for r in err):
        rows = [r for r in err if r["scene"] == scene and not r["is_reference"]]
        ref = [r for r in err if r["scene"] == scene and r["is_reference"]][0]
        d = [r for r in rows if r["is_default"]]
        if not d:
            continue
        d = d[0]
        better = dominated_by(rows, d, tkey)
        # The best alternative: least RMSE among those no costlier than the default, else the cheapest
        alt = min([r for r in better if r[tkey] <= d[tkey]] or better, key=lambda r: (r["rmse"], r[tkey])) \
            if better else None
        tab.append([scene, "%.2f s (%s rays)" % (ref[tkey], "{:,}".format(ref["rays"])),
                    "%.1f ms (%.1f ms wall, %s rays): RMSE %.4f, PSNR %.1f, SSIM %.4f" % (
                        d[tkey] * 1e3, d["seconds_median"] * 1e3, "{:,}".format(d["rays"]), d["rmse"], d["psnr"],
                        d["ssim"]),
                    "no (%d settings clearly better)" % len(better) if better else "yes",
                    "%s: %.1f ms, RMSE %.4f" % (desc(alt), alt[tkey] * 1e3, alt["rmse"]) if alt else "-",
                    "%.0f" % (ref[tkey] / d[tkey])])
    L.append(commands_block(ctx, "error"))
    L.append(md_table(["scene", "reference cost", "default settings (cost)", "default on the Pareto front",
                       "best clearly better setting", "reference / default cost"], tab))
    L.append("")
    L += ["![%s](%s)" % (p, p) for p in error_plots]
    L.append("\n### The renderer's error estimate\n")
    L.append("FrameStats::truncation (its RMS, est_rms) bounds what the depth cap and the threshold leave out (per pixel, largest "
             "channel, clamped to 1). It is compared with the same quantity measured against a render with the "
             "same samples at depth %d and threshold 0 (so sampling error cancels), and with the RMSE against the "
             "high-quality reference (which includes sampling error it does not claim to cover).\n" %
             c["error_ref_depth"])
    tab = []
    for scene in dict.fromkeys(r["scene"] for r in err):
        for adaptive in (0, 1):
            rows = [r for r in err if r["scene"] == scene and not r["is_reference"] and r["adaptive"] == adaptive]
            if not rows:
                continue
            ratios = [r["est_rms"] / r["trunc_rms"] for r in rows if r["trunc_rms"] > 1e-6]
            tab.append([scene, "adaptive" if adaptive else "fixed", len(rows),
                        "%.3g / %.3g / %.3g" % (min(ratios), statistics.median(ratios), max(ratios)) if ratios
                        else "n/a (no truncation error)",
                        "%d" % sum(1 for r in rows if r["est_rms"] < r["trunc_rms"] - 1e-7),
                        "%d" % sum(1 for r in rows if r["est_max"] < r["trunc_max"] - 1e-7),
                        "%d" % sum(1 for r in rows if r["est_rms"] < r["rmse"])])
    L.append(md_table(["scene", "sampling", "settings", "estimate / measured (min / median / max)",
                       "underestimates (RMS)", "underestimates (max pixel)", "estimate < RMSE vs reference"], tab))
    fixed = [r for r in err if not r["is_reference"] and not r["adaptive"]]
    L.append("\nThe test of the bound is the fixed-sampling rows: %d settings, %d underestimates of the RMS, %d of the "
             "largest pixel. With adaptive sampling the comparison is not exact: which pixels get supersampled "
             "depends on the first-pass image, hence on depth and threshold, so a render and its depth-%d twin "
             "refine different pixels and their difference includes sampling error the estimate does not claim to "
             "cover.\n" % (len(fixed), sum(1 for r in fixed if r["est_rms"] < r["trunc_rms"] - 1e-7),
                           sum(1 for r in fixed if r["est_max"] < r["trunc_max"] - 1e-7), c["error_ref_depth"]))
    L.append("\n![estimate](error_estimate.png)\n")
    L += calibration(err, progressive, tkey, c)
    return L


def calibration(err, progressive, tkey, c):
    """The per-pixel estimate's calibration (issue 11): truncation bound pixel by pixel and RMS against the measured
    truncation error; sampling coverage against its stated confidence; the progressive mode against the front."""
    L = ["\n### Calibration of the per-pixel error estimate\n",
         "Truncation: per setting, the pixels where the bound is below the measured difference to the same samples "
         "at depth %d, threshold 0 (must be 0), and bound RMS / measured RMS (median over the settings where the "
         "measured RMS is above 1e-4, so that the check can fail). Sampling: share of pixels whose difference between "
         "the untruncated render and the reference is within the estimate (stated: 2 standard errors, about 95%%, for "
         "several samples; a neighbour heuristic at 1 spp), over all pixels and over the pixels with an error of at "
         "least 1/255.\n" % c["error_ref_depth"]]
    tab = []
    for scene in dict.fromkeys(r["scene"] for r in err):
        rows = [r for r in err if r["scene"] == scene and not r["is_reference"] and not r["adaptive"]]
        if not rows or "trunc_under_pixels" not in rows[0]:
            continue
        checked = [r for r in rows if r["trunc_rms"] > 1e-4]
        ratios = [r["est_rms"] / r["trunc_rms"] for r in checked]
        cover = {}
        for r in rows:
            cover.setdefault(r["spp"], (r["samp_coverage"], r["samp_coverage_err"], r["samp_err_pixels"]))
        tab.append([scene, len(rows), len(checked), sum(int(r["trunc_under_pixels"]) for r in rows),
                    "%.2f" % statistics.median(ratios) if ratios else "n/a",
                    "; ".join("%d spp: %.3f / %.3f (%d px)" % (spp, v[0], v[1], v[2]) for spp, v in sorted(cover.items()))])
    L.append(md_table(["scene", "settings (fixed sampling)", "settings that can fail", "pixels under the bound",
                       "bound RMS / measured RMS (median)", "sampling coverage: all / error >= 1/255"], tab))
    if progressive:
        L.append("\nProgressive mode (defaults plus TimeBudget, no target): error against the reference at each "
                 "budget, next to the fixed settings' Pareto front (RMSE of the front's cheapest setting costing at "
                 "most as much). The curve is drawn on the scenes' error plots.\n")
        tab = []
        for scene in dict.fromkeys(r["scene"] for r in progressive):
            rows = [r for r in err if r["scene"] == scene and not r["is_reference"]]
            for p in [r for r in progressive if r["scene"] == scene]:
                affordable = [r["rmse"] for r in rows if r[tkey] <= p[tkey]]
                tab.append([scene, "%.1f" % (p["time_budget"] * 1e3), "%.1f" % (p[tkey] * 1e3),
                            "%.2f" % (p["samples"] / max(1, [r for r in rows if r["is_default"]][0]["samples"])),
                            "%.4f" % p["rmse"], "%.4f" % p["total_est_rms"],
                            "%.4f" % min(affordable) if affordable else "-"])
        L.append(md_table(["scene", "budget, ms (wall)", "cost, ms", "samples per pixel", "RMSE", "estimated error RMS",
                           "best fixed setting at no more cost: RMSE"], tab))
    return L
