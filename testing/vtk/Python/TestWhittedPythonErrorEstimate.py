#!/usr/bin/env python3
"""The pass's error estimate as a VTK user sees it (issue 11).

1. GetLastErrorImage: an image of the frame's size with the arrays TruncationError, SamplingError,
   EstimatedError, Samples, SamplingRMSError and RMSError (the calibrated estimate), whose RMS / largest values are the statistics' summaries, and whose truncation
   bound covers the measured difference to a deep (MaxDepth 16, ContributionThreshold 0) render at every pixel of
   a scene of facing mirrors (kr 0.9).
2. TargetError: a target above the first pass's estimate is met once every pixel has its 2 x 2 grid (the
   calibrated estimate needs two halves of samples: 4 per pixel, no more); a target at 0.6 x the first estimate is
   met (TargetErrorMet, EstimatedError RMS <= target) with more samples, counted per pixel in Samples.
3. TimeBudget: without a target the frame refines until the budget and stops within one tile's time.
4. Interactive frames skip the sampling estimate and never refine; the image is the same with or without a
   target on the first pass (the estimate is side data).
5. ShowErrorImage: the window shows grey = ErrorImageScale x EstimatedError of GetLastErrorImage, pixel by pixel.
6. RefinementRoundsPerFrame (progressive display): each Render() of the unchanged view runs one more round, the
   estimate never grows, RefinementFinished turns true when the target is met, with the samples and image of the
   same target refined in one Render(); a camera change or an interactive frame (1 sample per pixel) starts over.
"""
import sys
import time

import numpy as np
from vtkmodules.vtkCommonCore import vtkFloatArray
from vtkmodules.vtkCommonDataModel import vtkImageData
from vtkmodules.vtkFiltersSources import vtkPlaneSource, vtkSphereSource
from vtkmodules.vtkRenderingCore import (vtkActor, vtkLight, vtkPolyDataMapper, vtkRenderer, vtkRenderWindow,
                                         vtkWindowToImageFilter)
import vtkmodules.vtkRenderingOpenGL2  # noqa: F401
from vtkmodules.util.numpy_support import vtk_to_numpy
from whitted import vtkWhittedMaterialKeys, vtkWhittedPass

failures = []


def check(condition, message):
    print(("ok    " if condition else "FAIL  ") + message)
    if not condition:
        failures.append(message)


def actor(ren, source, color, kr=None):
    mapper = vtkPolyDataMapper()
    mapper.SetInputConnection(source.GetOutputPort())
    a = vtkActor()
    a.SetMapper(mapper)
    a.GetProperty().SetColor(*color)
    a.GetProperty().SetSpecular(0.3)
    if kr is not None:
        a.GetProperty().GetInformation().Set(vtkWhittedMaterialKeys.REFLECTANCE(), [kr], 1)
    ren.AddActor(a)


def plane(origin, p1, p2):
    p = vtkPlaneSource()
    p.SetOrigin(*origin)
    p.SetPoint1(*p1)
    p.SetPoint2(*p2)
    return p


ren = vtkRenderer()
ren.SetBackground(0.2, 0.3, 0.5)
actor(ren, plane((-0.5, -1, 4), (-0.5, -1, -36), (-0.5, 1, 4)), (0.6, 0.6, 0.6), kr=0.9)   # facing mirrors
actor(ren, plane((0.5, -1, 4), (0.5, 1, 4), (0.5, -1, -36)), (0.6, 0.6, 0.6), kr=0.9)
actor(ren, plane((-0.5, -1, 4), (0.5, -1, 4), (-0.5, -1, -36)), (0.8, 0.8, 0.8))
ball = vtkSphereSource()
ball.SetCenter(0.1, -0.6, -3)
ball.SetRadius(0.3)
ball.SetThetaResolution(32)
ball.SetPhiResolution(16)
actor(ren, ball, (0.9, 0.2, 0.1))
light = vtkLight()
light.SetPositional(True)
light.SetPosition(0, 0.8, 2)
light.SetConeAngle(180)
ren.AddLight(light)
cam = ren.GetActiveCamera()
cam.SetPosition(0, 0, 3.5)
cam.SetFocalPoint(0.35, -0.1, 0)
cam.SetViewAngle(50)
ren.ResetCameraClippingRange()

win = vtkRenderWindow()
win.SetOffScreenRendering(1)
win.SetMultiSamples(0)
win.SetSize(120, 90)
win.AddRenderer(ren)
p = vtkWhittedPass()
ren.SetPass(p)


def frame():
    win.Render()
    rgba = vtkFloatArray()
    p.GetLastFrame(rgba, None)
    image = vtkImageData()
    p.GetLastErrorImage(image)
    return vtk_to_numpy(rgba).reshape(-1, 4), image, p.GetLastFrameStatistics()


def array(image, name):
    return vtk_to_numpy(image.GetPointData().GetArray(name)).astype(float)


# 1. The error image against a deep reference
p.SetMaxDepth(16)
p.SetContributionThreshold(0.0)
reference, _, _ = frame()
p.SetMaxDepth(3)
p.SetContributionThreshold(0.05)
cheap, image, st = frame()
dims = image.GetDimensions()
check(dims[:2] == tuple(st.GetSize()) and dims[2] == 1, "error image is %s for a frame of %s" % (dims, st.GetSize()))
names = [image.GetPointData().GetArrayName(i) for i in range(image.GetPointData().GetNumberOfArrays())]
check(names == ["TruncationError", "SamplingError", "EstimatedError", "Samples", "SamplingRMSError", "RMSError"],
      "arrays %s" % names)
trunc = array(image, "TruncationError")
measured = np.abs(np.clip(reference[:, :3], 0, 1) - np.clip(cheap[:, :3], 0, 1)).max(axis=1)
check(measured.max() > 0.05, "depth 3 / threshold 0.05 lose something: largest pixel %.3f" % measured.max())
under = int(np.sum(trunc + 1e-5 < measured))
check(under == 0, "truncation bound under the measured error at %d pixels (bound RMS %.4f, measured RMS %.4f)"
      % (under, np.sqrt(np.mean(trunc ** 2)), np.sqrt(np.mean(measured ** 2))))
# Negative control of that per-pixel check: the bound zeroed at the pixel of the largest error is caught there alone
lowered = trunc.copy()
lowered[np.argmax(measured)] = 0.0
caught = np.flatnonzero(lowered + 1e-5 < measured)
check(list(caught) == [int(np.argmax(measured))], "a bound lowered at one pixel is caught there: %s" % caught[:5])
rms, p95, mx = st.GetTruncationError()
check(abs(rms - np.sqrt(np.mean(trunc ** 2))) < 1e-6 and abs(mx - trunc.max()) < 1e-6 and rms <= p95 + 1e-3 <= mx + 1e-3,
      "statistics TruncationError %.4f %.4f %.4f match the image" % (rms, p95, mx))
est = array(image, "EstimatedError")
check(abs(st.GetEstimatedError()[0] - np.sqrt(np.mean(est ** 2))) < 1e-6, "EstimatedError RMS matches the image")
check(st.GetSamplingError()[0] > 0, "1-spp sampling estimate %.4f > 0" % st.GetSamplingError()[0])
report = p.GetLastFrameReport()
check("truncation RMS" in report and "sampling RMS" in report, "frame report states both parts")

# 2. TargetError (deep enough that the truncation bound leaves the target to the samples)
p.SetMaxDepth(24)
p.SetContributionThreshold(0.0)
_, _, st = frame()
first = st.GetEstimatedError()[0]
pixels = st.GetSize()[0] * st.GetSize()[1]
check(st.GetNumberOfSamples() == pixels and st.GetRefinementRounds() == 0, "no target: one sample per pixel")
p.SetTargetError(first * 1.01)
_, grid_image, st = frame()
grid_samples = array(grid_image, "Samples")
check(st.GetTargetErrorMet() and st.GetNumberOfSamples() == 4 * pixels and grid_samples.min() == 4
      and grid_samples.max() == 4, "target above the first estimate: met with every pixel's 2 x 2 grid, %d samples "
      "(%d to %d per pixel)" % (st.GetNumberOfSamples(), grid_samples.min(), grid_samples.max()))
p.SetTargetError(first * 0.6)
_, image, st = frame()
check(st.GetTargetErrorMet() and st.GetEstimatedError()[0] <= first * 0.6,
      "target 0.6 x %.4f met: %.4f after %d rounds" % (first, st.GetEstimatedError()[0], st.GetRefinementRounds()))
samples = array(image, "Samples")
check(st.GetNumberOfSamples() > pixels and samples.sum() == st.GetNumberOfSamples() and samples.max() > 1,
      "refined: %d samples, %d on the most refined pixel" % (st.GetNumberOfSamples(), samples.max()))

# 3. TimeBudget (no target: only the budget stops the refinement)
p.SetTargetError(0.0)
p.SetTimeBudget(0.25)
_, _, st = frame()
# Not "more than one round": how many rounds fit in 0.25 s depends on the machine's load (a loaded 2-core machine
# fits one, sometimes none after a slow first pass). A frame that stops refining before its budget traces less
# than the budget (unbudgeted it refines for ~7 s): the lower bound below is what says that only the budget stopped it
check(not st.GetTargetErrorMet(), "no target: not met, %d rounds" % st.GetRefinementRounds())
# Upper bound: the budget, the tiles in flight and the final estimate pass. The margin (0.35 s) holds on a loaded
# 2-core machine (seen: +4 to +16 ms with both cores busy); a budget that is not honoured traces this frame for
# about 7 s (measured with the budget at 100 s)
check(0.25 <= st.GetTraceTime() <= 0.25 + 0.35, "budget 0.25 s: traced %.3f s" % st.GetTraceTime())

# 4. Interactive frames
p.SetInteractive(True)
_, image, st = frame()
check(st.GetRefinementRounds() == 0 and st.GetSamplingError()[0] == 0.0 and st.GetNumberOfSamples() == pixels,
      "interactive: no refinement, no sampling estimate")
p.SetInteractive(False)

# 5. The error image shown instead of the rendering
p.SetTimeBudget(0.0)
p.SetMaxDepth(3)
p.SetShowErrorImage(True)
p.SetErrorImageScale(8.0)
_, image, st = frame()
grab = vtkWindowToImageFilter()
grab.SetInput(win)
grab.ReadFrontBufferOff()
grab.SetInputBufferTypeToRGB()
grab.Update()
shown = vtk_to_numpy(grab.GetOutput().GetPointData().GetScalars()).astype(int).reshape(-1, 3)
expected = np.rint(255 * np.minimum(1.0, 8.0 * array(image, "EstimatedError"))).astype(int)
check(np.abs(shown - expected[:, None]).max() <= 1 and expected.max() - expected.min() > 50,
      "error image shown: largest difference %d of grey levels %d..%d"
      % (np.abs(shown - expected[:, None]).max(), expected.min(), expected.max()))
p.SetShowErrorImage(False)
rendered, _, _ = frame()
grab.Modified()
grab.Update()
shown = vtk_to_numpy(grab.GetOutput().GetPointData().GetScalars()).astype(int).reshape(-1, 3)
check(np.abs(shown - expected[:, None]).max() > 50, "ShowErrorImage off: the rendering again")

# 6. Progressive display: one round per Render()
p.SetMaxDepth(24)
p.SetContributionThreshold(0.0)
p.SetTargetError(first * 0.5)
once_rgba, _, st = frame()
once = (st.GetRefinementRounds(), st.GetNumberOfSamples())
p.SetRefinementRoundsPerFrame(1)
rounds, estimates, finished = [], [], False
while not finished and len(rounds) < 50:
    rgba, image, st = frame()
    rounds.append(st.GetRefinementRounds())
    estimates.append(st.GetEstimatedError()[0])
    finished = st.GetRefinementFinished()
check(rounds == list(range(1, len(rounds) + 1)) and len(rounds) == once[0],
      "one round per Render(): %s (in one Render(): %d rounds)" % (rounds, once[0]))
check(all(b <= a + 1e-9 for a, b in zip(estimates, estimates[1:])), "the estimate never grows: %s"
      % " ".join("%.4f" % e for e in estimates))
check(st.GetTargetErrorMet() and st.GetNumberOfSamples() == once[1] and np.array_equal(rgba, once_rgba),
      "progressive display ends with the frame refined in one Render(): %d samples" % st.GetNumberOfSamples())
cam.Azimuth(2.0)
_, _, st = frame()
check(st.GetRefinementRounds() == 1, "camera moved: starts over (round %d)" % st.GetRefinementRounds())
p.SetInteractive(True)
_, _, st = frame()
check(st.GetNumberOfSamples() == pixels and st.GetRefinementRounds() == 0, "interactive frame: 1 sample per pixel")
p.SetInteractive(False)
_, _, st = frame()
check(st.GetRefinementRounds() == 1, "the still frame after interaction starts over: %d round"
      % st.GetRefinementRounds())
p.SetRefinementRoundsPerFrame(0)
p.SetTargetError(0.0)

print("%d failures" % len(failures))
sys.exit(1 if failures else 0)
