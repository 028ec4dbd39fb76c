// whitted_bench error --scene NAME --size WxH: error against a high-quality reference (--ref-spp, --ref-depth,
// threshold 0) vs run time over samples per pixel x depth x contribution threshold; RMSE, PSNR, SSIM and the
// renderer's own error estimate against what it bounds (truncation: every pixel checked; sampling: coverage against
// the reference); then the progressive mode (default settings, TimeBudget 1.5-12x the default frame's time).
// --budget S: slow settings get fewer timed runs; --quick: a few settings only; --png-dir DIR keeps the reference
// and default images; --progressive-only: of the sweep only the default setting (the progressive mode's start and
// time unit), then the progressive mode; --budgets F,F,...: the progressive mode's budgets as multiples of the
// default frame's time; --ref-cache FILE: the reference image's colours (raw floats) are read from FILE if it holds
// a whole image (the caller keeps it to one scene, size, --ref-spp and --ref-depth), else rendered and written there
// (a reference read from it has no timing or estimate in its row): reruns of the progressive rows skip the slowest
// render.
#include "bench_commands.h"
#include "image_metrics.h"

#include <cmath>
#include <cstdio>

namespace whitted::bench {

int cmdError(const Args& a) {
  BenchScene bs;
  if (!loadScene(a, bs)) return 2;
  bs.scene.commit();
  int w = 320, h = 240;
  a.size("size", w, h);
  int reps = a.integer("reps", 3), warmup = a.integer("warmup", 1);
  int refSpp = a.integer("ref-spp", 64), refDepth = a.integer("ref-depth", 16);
  bool quick = a.has("quick");
  const bool progressiveOnly = a.has("progressive-only");
  std::string pngDir = a.str("png-dir");
  Camera cam = bs.camera.make(double(w) / h, bs.scene.bounds());
  const Features& f = bs.scene.features();
  bool secondary = f.reflective || f.transmissive;

  CsvWriter csv(a.str("csv"), {"scene",
                               "spp",
                               "adaptive",
                               "depth",
                               "threshold",
                               "is_default",
                               "is_reference",
                               "seconds_median",
                               "seconds_min",
                               "runs",
                               "rays",
                               "rmse",
                               "psnr",
                               "ssim",
                               "est_rms",
                               "est_max",
                               "trunc_rms",
                               "trunc_max",
                               "trunc_rmse",
                               "cpu_seconds_median",
                               "pixels_supersampled",
                               "est_p95",
                               "trunc_under_pixels",
                               "samp_rms",
                               "samp_p95",
                               "samp_max",
                               "samp_coverage",
                               "samp_coverage_err",
                               "samp_err_pixels",
                               "total_est_rms",
                               "progressive",
                               "time_budget",
                               "samples"});
  double budget = a.real("budget", 3.0);
  // Wall time (the renderer's timer) and the process CPU time of the same runs: on a shared machine the CPU
  // time is the stable cost measure
  double cpuMedian = 0.0;
  auto renderTimed = [&](const RenderSettings& rs, FrameBuffer& fb, FrameStats& fs, int wu, int rp) {
    std::vector<double> cpu;
    Timing t = timeBudgeted(wu, rp, budget, [&] {
      double c0 = processCpuNow();
      fs = render(bs.scene, cam, rs, w, h, fb);
      cpu.push_back(processCpuNow() - c0);
      return fs.secondsTrace;
    });
    cpu.erase(cpu.begin(), cpu.end() - std::min<std::ptrdiff_t>(t.runs, std::ptrdiff_t(cpu.size())));
    cpuMedian = summarize(cpu).median;
    return t;
  };

  // High-quality reference
  RenderSettings ref;
  ref.samplesPerPixel = refSpp;
  ref.integrator.maxDepth = refDepth;
  ref.integrator.contributionThreshold = 0.0f;
  FrameBuffer refFb;
  FrameStats refFs;
  Timing refT{};
  const std::string refCache = a.str("ref-cache");
  if (!readColorCache(refCache, w, h, refFb)) {
    refT = renderTimed(ref, refFb, refFs, 0, 1);
    writeColorCache(refCache, refFb);
  }
  savePng(pngDir.empty() ? "" : pngDir + "/" + bs.name + "_reference.png", refFb);
  csv.row({bs.name,
           fmt(refSpp),
           "0",
           fmt(refDepth),
           "0",
           "0",
           "1",
           fmt(refT.median),
           fmt(refT.min),
           fmt(refT.runs),
           fmt(refFs.rays.traced()),
           "0",
           "100",
           "1",
           fmt(refFs.truncation.rms),
           fmt(refFs.truncation.max),
           "0",
           "0",
           "0",
           fmt(cpuMedian),
           "0",
           fmt(refFs.truncation.p95),
           "0",
           fmt(refFs.sampling.rms),
           fmt(refFs.sampling.p95),
           fmt(refFs.sampling.max),
           "",
           "",
           "",
           fmt(refFs.total.rms),
           "0",
           "0",
           fmt(refFs.samples)});
  std::printf("%s reference (%d spp, depth %d, threshold 0): %.2f s, error estimate RMS %.3g\n", bs.name.c_str(),
              refSpp, refDepth, refT.median, refFs.truncation.rms);

  struct Sampling {
    int spp;
    bool adaptive;
  };
  std::vector<Sampling> samplings = {{1, false}, {4, false}, {4, true}, {16, false}, {16, true}};
  std::vector<int> depths = {1, 2, 3, 4, 5, 6, 7, 8};
  std::vector<float> thresholds = {0.0f, 1.0f / 255, 4.0f / 255, 16.0f / 255, 64.0f / 255};
  // The truncation bound's lookahead (IntegratorSettings::truncationLookahead, truncationTolerance,
  // truncationLookaheadMax, truncationRelativeTolerance) in the sweep, to compare its calibration
  const int lookahead = a.integer("lookahead", RenderSettings().integrator.truncationLookahead);
  const float tolerance = float(a.real("tolerance", RenderSettings().integrator.truncationTolerance));
  const int lookaheadMax = a.integer("lookahead-max", RenderSettings().integrator.truncationLookaheadMax);
  const float relTolerance =
      float(a.real("relative-tolerance", RenderSettings().integrator.truncationRelativeTolerance));
  if (a.has("depth")) depths = {a.integer("depth", 5)};  // one depth only
  if (quick) {
    samplings = {{1, false}, {4, true}};
    depths = {1, 5};
    thresholds = {0.0f, 1.0f / 255};
  }
  if (progressiveOnly) {
    samplings = {{1, false}};
    depths = {5};
    thresholds = {1.0f / 255};
  }
  if (!secondary) {
    // Nothing reflects or refracts: depth and threshold cannot change the image (the kernel leaves them out)
    depths = {5};
    thresholds = {1.0f / 255};
  }
  double defaultSeconds = 0.0;
  for (const Sampling& s : samplings) {
    // Reference with the same samples but no truncation: isolates what the depth cap and threshold leave out,
    // which is what FrameStats::truncation.rms bounds
    RenderSettings tr;
    tr.samplesPerPixel = s.spp;
    tr.adaptive = s.adaptive;
    tr.integrator.maxDepth = refDepth;
    tr.integrator.contributionThreshold = 0.0f;
    FrameBuffer truncFb;
    FrameStats truncFs;
    render(bs.scene, cam, tr, w, h, truncFb);
    // Sampling estimate against the truth: this untruncated render's own estimate vs its difference to the
    // reference (same depth and threshold, many samples). Coverage over all pixels, and over the pixels whose
    // error is at least one 8-bit step (most pixels have none)
    std::size_t covered = 0, errPixels = 0, errCovered = 0;
    for (std::size_t i = 0; i < truncFb.color.size(); ++i) {
      const float d = maxChannelDifference(truncFb.color[i], refFb.color[i]);
      const bool ok = d <= truncFb.sampling[i];
      covered += ok;
      if (d >= 1.0f / 255) {
        ++errPixels;
        errCovered += ok;
      }
    }
    const double coverage = double(covered) / double(std::max<std::size_t>(1, truncFb.color.size()));
    const double coverageErr = errPixels ? double(errCovered) / double(errPixels) : 1.0;
    for (int depth : depths)
      for (float thr : thresholds) {
        RenderSettings rs;
        rs.samplesPerPixel = s.spp;
        rs.adaptive = s.adaptive;
        rs.integrator.maxDepth = depth;
        rs.integrator.contributionThreshold = thr;
        rs.integrator.truncationLookahead = lookahead;
        rs.integrator.truncationTolerance = tolerance;
        rs.integrator.truncationLookaheadMax = lookaheadMax;
        rs.integrator.truncationRelativeTolerance = relTolerance;
        bool isDefault = s.spp == 1 && !s.adaptive && depth == 5 && std::abs(thr - 1.0f / 255) < 1e-6f;
        FrameBuffer fb;
        FrameStats fs;
        Timing t = renderTimed(rs, fb, fs, warmup, reps);
        ImageError e = compareImages(fb, refFb);
        ImageError et = compareImages(fb, truncFb);
        // The truncation bound, pixel by pixel, against what the same samples at the reference depth add. Adaptive
        // sampling refines the pixels its first pass marks, and that pass depends on depth and threshold: a pixel
        // refined in one image and not in the other differs by sampling, which the bound does not cover, so only
        // pixels with the same sample count in both (hence the same samples) are checked
        std::size_t under = 0;
        for (std::size_t i = 0; i < fb.color.size(); ++i)
          under += fb.samples[i] == truncFb.samples[i] &&
                   fb.truncation[i] + 1e-5f < maxChannelDifference(fb.color[i], truncFb.color[i]);
        csv.row({bs.name,
                 fmt(s.spp),
                 fmt(int(s.adaptive)),
                 fmt(depth),
                 fmt(thr),
                 fmt(int(isDefault)),
                 "0",
                 fmt(t.median),
                 fmt(t.min),
                 fmt(t.runs),
                 fmt(fs.rays.traced()),
                 fmt(e.rmse),
                 fmt(e.psnr),
                 fmt(e.ssim),
                 fmt(fs.truncation.rms),
                 fmt(fs.truncation.max),
                 fmt(et.maxChannelRms),
                 fmt(et.maxChannelMax),
                 fmt(et.rmse),
                 fmt(cpuMedian),
                 fmt(fs.pixelsSupersampled),
                 fmt(fs.truncation.p95),
                 fmt(under),
                 fmt(fs.sampling.rms),
                 fmt(fs.sampling.p95),
                 fmt(fs.sampling.max),
                 fmt(coverage),
                 fmt(coverageErr),
                 fmt(errPixels),
                 fmt(fs.total.rms),
                 "0",
                 "0",
                 fmt(fs.samples)});
        if (isDefault) defaultSeconds = t.median;
        if (isDefault) savePng(pngDir.empty() ? "" : pngDir + "/" + bs.name + "_default.png", fb);
        std::printf(
            "%-12s spp %2d%s depth %d thr %6.4f: %8.2f ms (cpu %8.2f ms)  RMSE %.4f  PSNR %5.2f  SSIM %.4f  "
            "est %.4f trunc %.4f\n",
            bs.name.c_str(), s.spp, s.adaptive ? "a" : " ", depth, thr, t.median * 1e3, cpuMedian * 1e3, e.rmse, e.psnr,
            e.ssim, fs.truncation.rms, et.maxChannelRms);
        std::fflush(stdout);
      }
  }

  // Progressive mode: the default settings refined by the error estimate for a time budget (no target), error
  // against the reference at each budget: the curve to set against the fixed settings' Pareto front
  if (defaultSeconds > 0.0) {
    std::vector<double> factors = quick ? std::vector<double>{2.0} : std::vector<double>{1.5, 3.0, 6.0, 12.0};
    if (a.has("budgets")) {
      factors.clear();
      const std::string list = a.str("budgets");
      for (std::size_t p = 0; p < list.size();) {
        const std::size_t q = std::min(list.find(',', p), list.size());
        factors.push_back(std::stod(list.substr(p, q - p)));
        p = q + 1;
      }
    }
    for (double f : factors) {
      RenderSettings rs;
      rs.timeBudget = f * defaultSeconds;
      FrameBuffer fb;
      FrameStats fs;
      Timing t = renderTimed(rs, fb, fs, warmup, reps);
      ImageError e = compareImages(fb, refFb);
      csv.row({bs.name, "1",         "0",         "5",         fmt(1.0f / 255),   "0",
               "0",     fmt(t.median), fmt(t.min), fmt(t.runs), fmt(fs.rays.traced()), fmt(e.rmse),
               fmt(e.psnr), fmt(e.ssim), fmt(fs.truncation.rms), fmt(fs.truncation.max), "", "",
               "",      fmt(cpuMedian), "0",       fmt(fs.truncation.p95), "", fmt(fs.sampling.rms),
               fmt(fs.sampling.p95), fmt(fs.sampling.max), "", "", "", fmt(fs.total.rms),
               "1",     fmt(rs.timeBudget), fmt(fs.samples)});
      std::printf("%-12s progressive, budget %6.1f ms: %8.2f ms (cpu %8.2f ms), %d rounds, %.2f spp, RMSE %.4f, "
                  "estimate %.4f\n",
                  bs.name.c_str(), rs.timeBudget * 1e3, t.median * 1e3, cpuMedian * 1e3, fs.refinementRounds,
                  double(fs.samples) / double(w * h), e.rmse, fs.total.rms);
      std::fflush(stdout);
    }
  }
  return 0;
}

}  // namespace whitted::bench
