// whitted_bench steps --scene NAME [--size WxH] [--steps 4,2,1,0.5,0.25] [--reference-step 0.0625] [--reps N]
// [--threads-list T] [--csv FILE]: the volume step study (issue 29). Every volume of the scene is traced at each
// sample distance (world units, Volume::sampleDistance) and compared with the same frame at the reference step
// (far finer: the march is second order in the step, VolumeStep.*), with the frame time: error against step and
// against time. Rows: scene, size, threads, step, seconds (median, CPU), volume samples, rmse, max levels; and the
// step's error estimate (IntegratorSettings::volumeStepEstimate, in one more frame: its truncation part minus the
// same frame's without it, RMS over pixels) beside the measured error in the same units (largest channel per pixel,
// RMS over pixels).
#include "bench_commands.h"
#include "image_metrics.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>

namespace whitted::bench {

namespace {

/// Sets every volume of scene to sample distance step (copies of the volumes: prepared again at the commit).
void setStep(Scene& scene, double step) {
  for (uint32_t id = 0; id < scene.volumeCount(); ++id) {
    Volume v = scene.volume(id);
    v.sampleDistance = step;
    scene.setVolume(id, std::move(v));
  }
  scene.commit();
}

}  // namespace

int cmdSteps(const Args& a) {
  BenchScene bs;
  if (!loadScene(a, bs)) return 2;
  if (bs.scene.volumeCount() == 0) {
    std::fprintf(stderr, "whitted_bench steps: scene %s has no volume\n", bs.name.c_str());
    return 2;
  }
  int w = 256, h = 192;
  a.size("size", w, h);
  const int reps = a.integer("reps", 3), warmup = a.integer("warmup", 1);
  const double refStep = a.real("reference-step", 0.0625);
  RenderSettings rs = settingsFrom(a);
  CsvWriter csv(a.str("csv"), {"scene", "width", "height", "threads", "step", "reference_step", "seconds_median",
                               "cpu_seconds_median", "volume_samples", "rmse", "max_levels", "max_channel_rms",
                               "step_estimate_rms"});
  const Camera cam = bs.camera.make(double(w) / h, bs.scene.bounds());
  for (int threads : threadList(a)) {
    rs.threads = threads;
    FrameBuffer ref;
    setStep(bs.scene, refStep);
    render(bs.scene, cam, rs, w, h, ref);
    for (const std::string& st : a.list("steps", "4,2,1,0.5,0.25")) {
      const double step = std::atof(st.c_str());
      if (!(step > 0.0)) continue;
      setStep(bs.scene, step);
      FrameBuffer fb;
      const TimedFrames timed = timeFrames(bs.scene, cam, rs, w, h, warmup, reps, fb);
      const Timing& t = timed.wall;
      const FrameStats& fs = timed.stats;
      const ImageError e = compareImages(fb, ref);
      // The step's estimate: the truncation part with it minus without it (the same samples)
      RenderSettings with = rs, without = rs;
      with.integrator.volumeStepEstimate = true;
      without.integrator.volumeStepEstimate = false;
      with.errorEstimates = without.errorEstimates = true;
      FrameBuffer fbWith, fbWithout;
      render(bs.scene, cam, with, w, h, fbWith);
      render(bs.scene, cam, without, w, h, fbWithout);
      double part2 = 0.0;
      for (std::size_t i = 0; i < fbWith.truncation.size(); ++i) {
        const double part = double(fbWith.truncation[i]) - double(fbWithout.truncation[i]);
        part2 += part * part;
      }
      const double estimate = std::sqrt(part2 / double(std::max<std::size_t>(1, fbWith.truncation.size())));
      csv.row({bs.name, fmt(w), fmt(h), fmt(threads), fmt(step), fmt(refStep), fmt(t.median),
               fmt(timed.cpu.median), fmt(fs.rays.volumeSamples), fmt(e.rmse), fmt(e.maxLevels),
               fmt(e.maxChannelRms), fmt(estimate)});
      std::printf("steps      %-12s %4dx%-4d %d thr: step %-7g %9.2f ms, %llu volume samples, rmse %.3g (max %d "
                  "levels) against step %g; largest channel RMS %.3g, the step's estimate %.3g\n",
                  bs.name.c_str(), w, h, threads, step, t.median * 1e3, (unsigned long long)fs.rays.volumeSamples,
                  e.rmse, e.maxLevels, refStep, e.maxChannelRms, estimate);
      std::fflush(stdout);
    }
  }
  return 0;
}

}  // namespace whitted::bench
