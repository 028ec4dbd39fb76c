// whitted_bench frame --scene NAME --sizes WxH,...: whole frames (trace time after the BVH build, median of
// --reps runs after --warmup), at each thread count of --threads-list; --png FILE keeps the last image.
// Render settings: --spp, --adaptive, --depth, --threshold, --no-shadows, --no-packets (shadow rays traced one by one),
// --no-primary-packets (camera rays' first hits found one by one, not as closest-hit packets),
// --no-error-estimates (as interactive frames), --target-error E, --time-budget S (progressive refinement),
// --lookahead N (levels of bound rays of the truncation bound: IntegratorSettings::truncationLookahead).
#include "bench_commands.h"

#include <cstdio>

namespace whitted::bench {

int cmdFrame(const Args& a) {
  BenchScene bs;
  if (!loadScene(a, bs)) return 2;
  double t0 = now();
  bs.scene.commit();
  double commitSeconds = now() - t0;
  RenderSettings rs = settingsFrom(a);
  int reps = a.integer("reps", 5), warmup = a.integer("warmup", 1);
  std::string tag = a.str("tag", "frame");
  CsvWriter csv(a.str("csv"), {"tag",
                               "scene",
                               "width",
                               "height",
                               "spp",
                               "adaptive",
                               "depth",
                               "threshold",
                               "shadows",
                               "threads",
                               "commit_seconds",
                               "seconds_median",
                               "seconds_min",
                               "seconds_max",
                               "runs",
                               "rays",
                               "mrays",
                               "error_estimate_rms",
                               "primitives",
                               "cpu_seconds_median",
                               "pixels_supersampled",
                               "volume_samples"});
  SceneStats st = bs.scene.stats();
  std::size_t prims = st.triangles + st.spheres + st.tubes;
  for (const std::string& sz : a.list("sizes", "800x600")) {
    int w = 0, h = 0;
    if (std::sscanf(sz.c_str(), "%dx%d", &w, &h) != 2) continue;
    Camera cam = bs.camera.make(double(w) / h, bs.scene.bounds());
    for (int threads : threadList(a)) {
      rs.threads = threads;
      FrameBuffer fb;
      const TimedFrames timed = timeFrames(bs.scene, cam, rs, w, h, warmup, reps, fb);
      const Timing &t = timed.wall, &tc = timed.cpu;
      const FrameStats& fs = timed.stats;
      csv.row({tag,
               bs.name,
               fmt(w),
               fmt(h),
               fmt(rs.samplesPerPixel),
               fmt(int(rs.adaptive)),
               fmt(rs.integrator.maxDepth),
               fmt(rs.integrator.contributionThreshold),
               fmt(int(rs.integrator.shadows)),
               fmt(threads),
               fmt(commitSeconds),
               fmt(t.median),
               fmt(t.min),
               fmt(t.max),
               fmt(t.runs),
               fmt(fs.rays.traced()),
               fmt(fs.rays.traced() / t.median * 1e-6),
               fmt(fs.total.rms),
               fmt(prims),
               fmt(tc.median),
               fmt(fs.pixelsSupersampled),
               fmt(fs.rays.volumeSamples)});
      std::printf(
          "%-10s %-12s %4dx%-4d %d thr: trace %9.2f ms (min %.2f, max %.2f), cpu %.2f ms, commit %.1f ms, "
          "%.2f Mrays/s%s%s\n",
          tag.c_str(), bs.name.c_str(), w, h, threads, t.median * 1e3, t.min * 1e3, t.max * 1e3, tc.median * 1e3,
          commitSeconds * 1e3, fs.rays.traced() / t.median * 1e-6,
          rs.adaptive
              ? (", supersampled " + std::to_string(fs.pixelsSupersampled) + " of " + std::to_string(w * h) + " pixels")
                    .c_str()
              : "",
          fs.rays.volumeSamples ? (", " + std::to_string(fs.rays.volumeSamples) + " volume samples").c_str() : "");
      std::fflush(stdout);
      if (a.has("png")) savePng(a.str("png"), fb);
    }
  }
  return 0;
}

}  // namespace whitted::bench
