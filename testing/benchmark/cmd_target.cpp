// whitted_bench target --scene NAME --size WxH: the calibration of the error estimate that TargetError steers by,
// against an independent truth. The truth is the same scene traced at --truth-factor (default 4) times the
// resolution with --truth-spp (16) samples, depth --truth-depth (16), threshold 0, box-filtered down to WxH (never
// a render with the settings under test). For each target of --targets (default 0.03,0.015,0.008) the default
// settings refine progressively one round per render() call (the same rounds as one call: RefinementState), and
// after every call the image is measured against the truth (largest channel per pixel, RMS over pixels). Per
// target: met, the reported calibrated RMS and the bound's RMS at the stop, the measured RMS there, their ratio,
// samples per pixel, the tracing seconds to the stop, and the oracle seconds (the first call of the same refinement
// whose image measured under the target); --frames-csv FILE writes every call's row. --max-seconds stops a
// refinement between calls (no TimeBudget: a resumed call with a budget plans its round from that call's own rate,
// which the progressive display fix addresses).
#include "bench_commands.h"
#include "image_metrics.h"

#include <cmath>
#include <cstdio>

namespace whitted::bench {

namespace {

// The truth: factor x the resolution, box-filtered down (premultiplied colours averaged)
FrameBuffer renderTruth(const BenchScene& bs, const Camera& cam, int w, int h, int factor, int spp, int depth) {
  RenderSettings rs;
  rs.samplesPerPixel = spp;
  rs.integrator.maxDepth = depth;
  rs.integrator.contributionThreshold = 0.0f;
  rs.errorEstimates = false;
  FrameBuffer big, out;
  render(bs.scene, cam, rs, w * factor, h * factor, big);
  out.resize(w, h);
  const float inv = 1.0f / float(factor * factor);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      Color4 sum(0.0f);
      for (int v = 0; v < factor; ++v)
        for (int u = 0; u < factor; ++u) sum += big.color[std::size_t(y * factor + v) * (w * factor) + x * factor + u];
      out.color[std::size_t(y) * w + x] = sum * inv;
      out.traced[std::size_t(y) * w + x] = 1;
    }
  return out;
}

std::vector<double> parseList(const std::string& list) {
  std::vector<double> out;
  for (std::size_t p = 0; p < list.size();) {
    const std::size_t q = std::min(list.find(',', p), list.size());
    out.push_back(std::stod(list.substr(p, q - p)));
    p = q + 1;
  }
  return out;
}

}  // namespace

int cmdTarget(const Args& a) {
  BenchScene bs;
  if (!loadScene(a, bs)) return 2;
  bs.scene.commit();
  int w = 160, h = 120;
  a.size("size", w, h);
  const int factor = a.integer("truth-factor", 4), truthSpp = a.integer("truth-spp", 16);
  const int truthDepth = a.integer("truth-depth", 16);
  const double maxSeconds = a.real("max-seconds", 60.0);
  const std::vector<double> targets = parseList(a.has("targets") ? a.str("targets") : "0.03,0.015,0.008");
  Camera cam = bs.camera.make(double(w) / h, bs.scene.bounds());
  // --truth-cache FILE: the truth's colours (raw floats) read from FILE if it holds this size, else rendered and
  // written there (nestedglass's truth takes tens of minutes)
  FrameBuffer truth;
  const std::string truthCache = a.str("truth-cache");
  if (!readColorCache(truthCache, w, h, truth)) {
    truth = renderTruth(bs, cam, w, h, factor, truthSpp, truthDepth);
    writeColorCache(truthCache, truth);
  }
  CsvWriter csv(a.str("csv"), {"scene", "width", "height", "target", "met", "measured_below", "reported_rms",
                               "bound_rms", "measured_rms", "ratio", "spp", "seconds", "oracle_seconds", "rounds",
                               "calls"});
  // --frames-csv: one row per call of each refinement (the estimate against the measured error at every frame a
  // progressive display shows, not only at the stop)
  CsvWriter frames(a.str("frames-csv"), {"scene", "target", "call", "seconds", "rounds", "spp", "reported_rms",
                                         "measured_rms", "ratio", "finished"});
  // --fixed N,N,...: fixed stratified sample counts, at the default depth and threshold and untruncated (depth
  // 16, threshold 0), with both estimates against the truth (the calibration without refinement)
  for (double spp : a.has("fixed") ? parseList(a.str("fixed")) : std::vector<double>{})
    for (bool untruncated : {false, true}) {
      RenderSettings rs;
      rs.samplesPerPixel = int(spp);
      if (untruncated) {
        rs.integrator.maxDepth = truthDepth;
        rs.integrator.contributionThreshold = 0.0f;
      }
      FrameBuffer fb;
      const FrameStats fs = render(bs.scene, cam, rs, w, h, fb);
      const double measured = compareImages(fb, truth).maxChannelRms;
      std::printf("%-12s %3d spp%s: measured %.4f, calibrated %.4f (sampling %.4f, truncation %.4f), bound %.4f\n",
                  bs.name.c_str(), int(spp), untruncated ? " untruncated" : "", measured, fs.calibrated.rms,
                  fs.calibratedSampling.rms, fs.truncation.rms, fs.total.rms);
    }
  for (double target : targets) {
    RefinementState keep;
    RenderSettings rs;
    rs.targetError = target;
    rs.refinement = &keep;
    rs.maxRefinementRounds = 1;
    FrameBuffer fb;
    FrameStats fs;
    double oracle = -1.0, measured = 0.0;
    int calls = 0;
    do {
      fs = render(bs.scene, cam, rs, w, h, fb);
      ++calls;
      measured = compareImages(fb, truth).maxChannelRms;
      if (oracle < 0.0 && measured <= target) oracle = keep.seconds;
      frames.row({bs.name, fmt(target), fmt(calls), fmt(keep.seconds), fmt(fs.refinementRounds),
                  fmt(double(keep.samples) / double(w * h)), fmt(fs.calibrated.rms), fmt(measured),
                  fmt(measured > 0.0 ? fs.calibrated.rms / measured : 0.0), fmt(int(fs.refinementFinished))});
      if (a.has("verbose"))
        std::printf("  call %d: %.3f s, %d rounds, estimate %.4f, measured %.4f, finished %d\n", calls, keep.seconds,
                    fs.refinementRounds, fs.calibrated.rms, measured, int(fs.refinementFinished));
    } while (!fs.refinementFinished && keep.seconds < maxSeconds);
    const double spp = double(keep.samples) / double(w * h);
    const double ratio = measured > 0.0 ? fs.calibrated.rms / measured : 0.0;
    csv.row({bs.name, fmt(w), fmt(h), fmt(target), fmt(int(fs.targetMet)), fmt(int(measured <= target)),
             fmt(fs.calibrated.rms), fmt(fs.total.rms), fmt(measured), fmt(ratio), fmt(spp), fmt(keep.seconds),
             oracle < 0.0 ? "" : fmt(oracle), fmt(fs.refinementRounds), fmt(calls)});
    std::printf("%-12s target %.4f: met %d, reported %.4f (bound %.4f), measured %.4f, ratio %.2f, %.1f spp, "
                "%.2f s (oracle %s s), %d rounds\n",
                bs.name.c_str(), target, int(fs.targetMet), fs.calibrated.rms, fs.total.rms, measured, ratio, spp,
                keep.seconds, oracle < 0.0 ? "never" : fmt(oracle, "%.2f").c_str(), fs.refinementRounds);
    std::fflush(stdout);
  }
  return 0;
}

}  // namespace whitted::bench
