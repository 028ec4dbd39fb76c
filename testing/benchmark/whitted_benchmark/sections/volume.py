"""Volumes (issue 29): a vtkRTAnalyticSource volume rendered by VTK's vtkGPUVolumeRayCastMapper (llvmpipe here) and
vtkFixedPointVolumeRayCastMapper, and traced by vtkWhittedPass with its effects off, with shadows on a floor and
with a mirror floor, and the three with Shade on (vtk_volume_bench.py): first frame, frame after a camera turn,
peak memory; each mode in a process of its own."""
import os

from .. import plots
from ..markdown import commands_block, fmt_ratio, md_table, ms, ratio
from ..runner import HERE, VTK_PYTHON, XVFB, fresh, read_csv, vtk_tools_ok, whitted_env

MODES = ["gpu", "fixedpoint", "whitted", "whitted-shadow", "whitted-mirror", "gpu-shade", "fixedpoint-shade",
         "whitted-shade"]
LABELS = {"gpu": "VTK vtkGPUVolumeRayCastMapper (llvmpipe)",
          "fixedpoint": "VTK vtkFixedPointVolumeRayCastMapper",
          "whitted": "vtkWhittedPass, effects off",
          "whitted-shadow": "vtkWhittedPass, floor and shadows",
          "whitted-mirror": "vtkWhittedPass, mirror floor and shadows",
          "gpu-shade": "VTK vtkGPUVolumeRayCastMapper, Shade on",
          "fixedpoint-shade": "VTK vtkFixedPointVolumeRayCastMapper, Shade on",
          "whitted-shade": "vtkWhittedPass, effects off, Shade on"}


def run(ctx):
    c = ctx.cfg
    # The step study in the core (no VTK): error against a far finer step, and time, per sample distance
    ctx.runner.run([ctx.bench, "steps", "--scene", c["vol_step_scene"], "--size", c["vol_step_size"], "--steps",
                    c["vol_steps"], "--reference-step", str(c["vol_reference_step"]), "--reps", str(c["vol_reps"]),
                    "--threads-list", "0", "--csv", fresh(ctx.path("volume_steps.csv"))], "volume steps")
    path = fresh(ctx.path("volume.csv"))
    if not vtk_tools_ok():
        ctx.notes.append("xvfb-run or VTK Python missing: volume comparison skipped")
        return
    env = whitted_env(ctx.args)
    # The anchors and the effects-off trace twice, interleaved (the machine's speed drifts between runs)
    order = MODES + ["gpu", "fixedpoint", "whitted"] if not c["quick"] else MODES
    for mode in order:
        cmd = XVFB + [VTK_PYTHON, os.path.join(HERE, "vtk_volume_bench.py"), "--modes", mode,
                      "--dims", str(c["vol_dims"]), "--size", c["vol_size"], "--reps", str(c["vol_reps"]),
                      "--csv", path]
        rc, _, _ = ctx.runner.run(cmd, "volume %s" % mode, env=env, check=False, timeout=1800)
        if rc != 0:
            ctx.notes.append("volume %s failed (exit %d), see logs/" % (mode, rc))


def outputs(ctx):
    return ["volume_steps.csv", "volume_steps.png"] + (["volume.csv"] if vtk_tools_ok() else [])


def _median_row(rows, mode):
    """The row of mode with the median frame time (of its runs in this results folder), or None."""
    sel = sorted((r for r in rows if r["mode"] == mode and r["status"] == "ok"), key=lambda r: r["seconds_median"])
    return sel[(len(sel) - 1) // 2] if sel else None


def _steps_report(ctx):
    rows = read_csv(ctx.path("volume_steps.csv"))
    if not rows:
        return []
    plots.volume_steps(ctx, rows)
    r0 = rows[0]
    return ["\n### Step size: error against time\n",
            "The same volume in the core alone (`whitted_bench steps --scene %s`, %dx%d, all threads): each sample "
            "distance against the frame at distance %g. The march itself is second order in the step "
            "(`VolumeStep.TransmittanceConvergesToTheIntegralAsTheStepShrinks` checks it against a closed form); "
            "with the default contribution threshold 1/255 a ray ends within a step of where its transmittance "
            "falls below it, which adds a first-order term (below 1e-4 at the voxel spacing, the VTK mappers' "
            "default, 1 here).\n" % (
                r0["scene"], r0["width"], r0["height"], r0["reference_step"]),
            "\nThe last two columns are in the units of the frame's error estimate (largest channel per pixel, RMS "
            "over pixels): the measured difference, and the step's error estimate (`IntegratorSettings::"
            "volumeStepEstimate`: the march again at twice the step; on where refinement steers, so not in the "
            "timed frames).\n\n",
            md_table(["step", "frame ms (wall / CPU)", "volume samples", "RMSE", "largest difference (8-bit levels)",
                      "measured (largest channel)", "step's estimate"],
                     [["%g" % r["step"], "%s / %s" % (ms(r["seconds_median"]), ms(r["cpu_seconds_median"])),
                       r["volume_samples"], "%.2g" % r["rmse"], r["max_levels"],
                       "%.2g" % r["max_channel_rms"] if "max_channel_rms" in r else "-",
                       "%.2g" % r["step_estimate_rms"] if "step_estimate_rms" in r else "-"] for r in rows]),
            "\n![volume steps](volume_steps.png)\n"]


def report(ctx, head):
    rows = read_csv(ctx.path("volume.csv"))
    if not rows:
        return _steps_report(ctx)
    r0 = rows[0]
    L = ["\n## Volumes against VTK's volume mappers\n",
         "A %s vtkRTAnalyticSource volume (cool-warm colour over its range; opacity 0 up to 130, 0.2 at the top per "
         "unit distance 1: the rim of the cube is transparent), sample distance 1 (the voxel spacing, automatic "
         "adjustment off), trilinear, %dx%d, one light (`testing/benchmark/vtk_volume_bench.py`). vtkWhittedPass "
         "traces the GPU mapper's vtkVolume at 1 sample per pixel; 'effects off' has no floor, no shadows, no "
         "reflections (like for like with the mappers); the other two add a floor under the volume with shadows, "
         "then make it a mirror (kr 0.6). First frame = the first Render() (upload or conversion); frame = median "
         "over %s frames after a 0.5 degree azimuth each; wall and CPU seconds of the process (llvmpipe and the "
         "tracer both use its threads); memory = the process's peak resident size. Each mode runs in a process of "
         "its own; the anchors and the effects-off trace run twice, interleaved, and the run with the median frame "
         "is shown.\n" % (r0["dims"], r0["width"], r0["height"], r0["runs"])]
    tab = []
    for r in rows:
        if r["status"] != "ok":
            tab.append([LABELS.get(r["mode"], r["mode"]), "", "", "", r["status"]])
            continue
        tab.append([LABELS.get(r["mode"], r["mode"]),
                    ms(r["first_frame_seconds"]),
                    "%s / %s" % (ms(r["seconds_median"]), ms(r["cpu_seconds_median"])),
                    "%.0f" % r["peak_rss_mb"], r["status"]])
    L.append(md_table(["renderer", "first frame ms (wall)", "frame ms (wall / CPU)", "peak memory MB",
                       "status"], tab))
    w = _median_row(rows, "whitted")
    anchors = [a for a in (_median_row(rows, "gpu"), _median_row(rows, "fixedpoint")) if a]
    if w and anchors:
        best = min(anchors, key=lambda a: a["seconds_median"])
        head.append(["%s volume, vtkWhittedPass (effects off) vs %s, %dx%d; memory %.0f MB vs %.0f MB" % (
                         w["dims"], "the faster VTK mapper (%s)" % LABELS[best["mode"]], w["width"], w["height"],
                         w["peak_rss_mb"], best["peak_rss_mb"]),
                     "%s ms" % ms(w["seconds_median"]), "%s ms" % ms(best["seconds_median"]),
                     fmt_ratio(ratio(best["seconds_median"], w["seconds_median"])),
                     fmt_ratio(ratio(best["cpu_seconds_median"], w["cpu_seconds_median"]))])
        costs = []
        for mode in ("whitted-shadow", "whitted-mirror"):
            e = _median_row(rows, mode)
            if e:
                costs.append("%s: %.2fx the effects-off frame" % (LABELS[mode],
                                                                  e["seconds_median"] / w["seconds_median"]))
        shaded = _median_row(rows, "whitted-shade")
        if shaded:
            costs.append("%s: %.2fx" % (LABELS["whitted-shade"], shaded["seconds_median"] / w["seconds_median"]))
        if costs:
            L.append("\nCost of each effect: " + "; ".join(costs) + ".\n")
        shaded_anchors = [a for a in (_median_row(rows, "gpu-shade"), _median_row(rows, "fixedpoint-shade")) if a]
        if shaded and shaded_anchors:
            best = min(shaded_anchors, key=lambda a: a["seconds_median"])
            L.append("With Shade on, vtkWhittedPass takes %s ms against %s ms for the faster VTK mapper shading too "
                     "(%s): %s of its time.\n" % (ms(shaded["seconds_median"]), ms(best["seconds_median"]),
                                                  LABELS[best["mode"]],
                                                  fmt_ratio(ratio(shaded["seconds_median"], best["seconds_median"]))))
    L += _steps_report(ctx)
    L.append(commands_block(ctx, "volume"))
    return L
