// The calibrated RMS estimate (FrameStats::calibratedSampling, calibrated; image/error_estimate.h) against an
// independent reference: the same scene at 144 samples per pixel (other sample positions), depth 16, threshold 0.
// The estimate is an RMS estimate, so its ratio to the measured RMS must be near 1 at every sample count, with
// stratified samples; the old figure (two standard errors from the samples' variance, with the neighbour floor)
// must fail the same check (negative control). TargetError, steered by the calibrated estimate, must not stop
// above the target by the measure. Refinement with only a time budget, ranking by the samples' spread as well,
// measures lower than ranking by the calibrated estimate alone. No verdict depends on timing.
#include "image/renderer.h"
#include "scenes/scenes.h"
#include "scenes/stiff_scenes.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <functional>

using namespace whitted;

namespace {

// RMS over the pixels of the largest channel difference of the clamped colours (what the estimates state)
double measuredRms(const FrameBuffer& a, const FrameBuffer& b) {
  double sum2 = 0.0;
  for (std::size_t i = 0; i < a.color.size(); ++i) {
    float d = 0.0f;
    for (int c = 0; c < 3; ++c)
      d = std::max(d, std::abs(std::clamp(a.color[i][c], 0.0f, 1.0f) - std::clamp(b.color[i][c], 0.0f, 1.0f)));
    sum2 += double(d) * d;
  }
  return std::sqrt(sum2 / double(std::max<std::size_t>(1, a.color.size())));
}

struct Study {
  Scene scene;
  Camera cam;
  FrameBuffer ref;
  int w, h;
  Study(const std::function<void(Scene&, CameraSpec&)>& build, int width, int height) : w(width), h(height) {
    CameraSpec cs;
    build(scene, cs);
    scene.commit();
    cam = cs.make(double(w) / h, scene.bounds());
    RenderSettings rs = untruncated();
    rs.samplesPerPixel = 144;
    rs.errorEstimates = false;
    render(scene, cam, rs, w, h, ref);
  }
  // Depth 16 and threshold 0 (the reference's): only sampling error is left
  static RenderSettings untruncated() {
    RenderSettings rs;
    rs.integrator.maxDepth = 16;
    rs.integrator.contributionThreshold = 0.0f;
    return rs;
  }
};

const struct {
  const char* name;
  void (*build)(Scene&, CameraSpec&);
} kScenes[] = {{"fence", buildFenceScene}, {"mirrors", buildFacingMirrorsScene}};

}  // namespace

// Stratified 4, 9 and 16 samples per pixel: calibrated sampling RMS / measured RMS within [0.75, 1.5] (the
// measured error is large enough to matter: above a tenth of an 8-bit step); the old 95% figure is more than 1.5x
// the measured at each of them (it is a per-pixel bound, not an RMS estimate: the negative control).
TEST(Calibration, SamplingRmsEstimateMatchesReference) {
  for (const auto& sc : kScenes) {
    Study st(sc.build, 48, 36);
    for (int spp : {4, 9, 16}) {
      RenderSettings rs = Study::untruncated();
      rs.samplesPerPixel = spp;
      FrameBuffer fb;
      const FrameStats fs = render(st.scene, st.cam, rs, st.w, st.h, fb);
      const double measured = measuredRms(fb, st.ref);
      const double calibrated = fs.calibratedSampling.rms / measured, old = fs.sampling.rms / measured;
      std::printf("%-12s %2d spp: measured RMS %.5f, calibrated %.5f (x%.2f), old 95%% figure %.5f (x%.2f)\n",
                  sc.name, spp, measured, fs.calibratedSampling.rms, calibrated, fs.sampling.rms, old);
      EXPECT_GT(measured, 0.1 / 255) << sc.name << " " << spp;
      EXPECT_GE(calibrated, 0.75) << sc.name << " " << spp;
      EXPECT_LE(calibrated, 1.5) << sc.name << " " << spp;
      EXPECT_GT(old, 1.5) << sc.name << " " << spp << ": the negative control passed the calibration check";
    }
  }
}

// TargetError stops by the calibrated estimate: where it says the target is met, the image measured against the
// reference (depth 16, threshold 0: truncation counts too) is at most the target; and the estimate it stopped at is
// not far above the measured (at most 2x: the stop is not bought by overestimating).
TEST(Calibration, TargetMetMeansMeasuredBelowTarget) {
  Study st(buildFenceScene, 48, 36);
  for (double target : {0.03, 0.015}) {
    RenderSettings rs;
    rs.targetError = target;
    FrameBuffer fb;
    const FrameStats fs = render(st.scene, st.cam, rs, st.w, st.h, fb);
    const double measured = measuredRms(fb, st.ref);
    std::printf("fence target %.3f: met %d, estimate %.4f, measured %.4f, %llu samples\n", target,
                int(fs.targetMet), fs.calibrated.rms, measured, (unsigned long long)fs.samples);
    ASSERT_TRUE(fs.targetMet) << target;
    EXPECT_LE(fs.calibrated.rms, target);
    EXPECT_LE(measured, target);
    EXPECT_LE(fs.calibrated.rms, 2.0 * measured);
  }
}

// Progressive frames while one-sample pixels remain, on strokes a third of a pixel wide (the target study's text
// scene, 160x120, TargetError 0.008, one round per call): the neighbour rule cannot see a stroke no centre sample
// hit, so the frame's figure rates the remaining one-sample pixels by the probes (kProbeStride: every 16th such pixel
// gridded in the first round, whatever its estimate; their mean squared change per bucket of the neighbour rule).
// The calibrated RMS is within [0.95, 1.5] of the measured at each such frame (measured here: 1.12, 0.98, 0.98);
// the same figure with the neighbour rule for the one-sample pixels (as before the probes) is 0.76 of it at the
// second call. Where the target counts as met (one-sample pixels may be left once the probes have rated them), the
// image measures under it.
TEST(Calibration, ProbesRateTheOneSamplePixels) {
  Study st(buildTextScene, 160, 120);
  RenderSettings rs;
  rs.targetError = 0.008;
  rs.maxRefinementRounds = 1;
  RefinementState keep;
  rs.refinement = &keep;
  int framesWithSingles = 0, controls = 0;
  bool met = false;
  for (int call = 1; call <= 40; ++call) {
    FrameBuffer fb;
    const FrameStats fs = render(st.scene, st.cam, rs, st.w, st.h, fb);
    std::size_t singles = 0;
    double before2 = 0.0;  // the figure with the neighbour rule for one-sample pixels
    for (std::size_t i = 0; i < fb.color.size(); ++i) {
      singles += fb.samples[i] == 1;
      const float s = fb.samples[i] == 1 ? fb.sampling[i] : fb.samplingRms[i];
      const float t = calibratedTotal(fb.truncation[i], s);
      before2 += double(t) * t;
    }
    if (fs.targetMet) {
      // Met (with one-sample pixels left or not): the image measures under the target
      const double measured = measuredRms(fb, st.ref);
      std::printf("text met at call %d: %zu one-sample pixels; calibrated RMS %.4f, measured %.4f\n", call, singles,
                  fs.calibrated.rms, measured);
      EXPECT_LE(measured, rs.targetError);
      met = true;
      break;
    }
    if (singles == 0) continue;
    ++framesWithSingles;
    const double measured = measuredRms(fb, st.ref), before = std::sqrt(before2 / double(fb.color.size()));
    std::printf("text call %d: %zu one-sample pixels; calibrated RMS %.4f, measured %.4f (x%.2f); with the neighbour "
                "rule %.4f (x%.2f)\n",
                call, singles, fs.calibrated.rms, measured, fs.calibrated.rms / measured, before, before / measured);
    // An RMS estimate (each bucket's mean squared change), not a bound: within [0.95, 1.5] of the measured
    EXPECT_GE(fs.calibrated.rms, 0.95 * measured) << call;
    EXPECT_LE(fs.calibrated.rms, 1.5 * measured) << call;
    controls += before < 0.9 * measured;  // the negative control: the neighbour rule alone well under it
  }
  EXPECT_GE(framesWithSingles, 3);
  EXPECT_GE(controls, 1);
  EXPECT_TRUE(met);
}

// Refinement with a time budget and no target ranks a several-sample pixel by the larger of its calibrated estimate
// and its samples' spread (FrameJob::refine): the calibrated estimate alone, a noisy half difference, leaves the
// pixels whose estimate came out low by chance. Classic scene, 96x72, 4, 6 and 8 rounds of one call (a budget of an
// hour: round sizes go by rays, not time): the measured RMS against the reference, scaled to equal rays (error ~
// rays^-1/2), is under 0.94x that of ranking by the calibrated estimate alone (measured: 0.896, 0.918, 0.912; the
// benchmark's ten scenes: data/benchmark/progressive). Negative controls: the larger of the two figures without the
// rescaling to the calibrated sum measured 0.906, 0.954, 0.925 (fails at 6 rounds); the rule off, 1. The 6-round
// frame is also made by six calls of one round on one thread: the same image, bit for bit.
TEST(Calibration, BudgetRefinementRanksBySamplesSpread) {
  Study st([](Scene& s, CameraSpec& c) { buildClassicScene(s, c); }, 96, 72);
  for (int rounds : {4, 6, 8}) {
    double measured[2], rays[2];
    for (int spread = 0; spread < 2; ++spread) {
      RefinementState state;
      RenderSettings rs;
      rs.timeBudget = 3600.0;
      rs.refinement = &state;
      rs.maxRefinementRounds = rounds;
      rs.budgetRanksBySpread = spread == 1;
      FrameBuffer fb;
      const FrameStats fs = render(st.scene, st.cam, rs, st.w, st.h, fb);
      ASSERT_EQ(fs.refinementRounds, rounds);
      measured[spread] = measuredRms(fb, st.ref);
      rays[spread] = double(fs.rays.traced());
      if (spread == 1 && rounds == 6) {
        // The same frame from six calls of one round, on one thread: bit for bit
        RefinementState calls;
        RenderSettings step = rs;
        step.refinement = &calls;
        step.maxRefinementRounds = 1;
        step.threads = 1;
        FrameBuffer stepFb;
        for (int k = 0; k < rounds; ++k) render(st.scene, st.cam, step, st.w, st.h, stepFb);
        EXPECT_EQ(calls.rounds, rounds);
        EXPECT_TRUE(stepFb.color == fb.color) << "six calls of one round, one thread";
      }
    }
    const double ratio = measured[1] / measured[0] * std::sqrt(rays[1] / rays[0]);
    std::printf("classic, %d rounds: calibrated estimate alone %.5f (%.0f rays), with the spread %.5f (%.0f rays): "
                "x%.3f at equal rays\n",
                rounds, measured[0], rays[0], measured[1], rays[1], ratio);
    EXPECT_LT(ratio, 0.94) << rounds << " rounds";
  }
}

