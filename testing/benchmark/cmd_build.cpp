// whitted_bench build --scene NAME: BVH build time and memory, ours (Scene::commit of fresh geometry with the SAH
// builder and with the fast (Morton) builder, and the SAH builder alone on precomputed boxes) and Embree's (low /
// medium / high quality), at each thread count of
// --threads-list. Equal threads on both sides: Embree gets a device with that many threads; our builder, which
// picks its own threads, runs confined to that many cores (CpuLimit). Both sides alternate run by run; the
// primary-ray speed each build gives is measured with all threads. --fast-only: only the fast commit and Embree
// low (quick A/B runs of the fast build and profiles of it).
#include "bench_commands.h"
#include "bench_trace.h"

#include <cstdio>
#include <memory>

namespace whitted::bench {

namespace {

/// Timings of one build variant at one thread count.
struct BuildRuns {
  std::string engine, variant;
  std::size_t prims = 0;
  std::vector<double> wall, cpu;
  double bytes = 0.0, peakBytes = 0.0;  ///< acceleration structure bytes (and peak during the build)
  double primaryMrays = 0.0;            ///< 0 = not measured
};

}  // namespace

int cmdBuild(const Args& a) {
  BenchScene bs;
  if (!loadScene(a, bs)) return 2;
  int reps = a.integer("reps", 3), warmup = a.integer("warmup", 1);
  bool useEmbree = kHaveEmbree && !a.has("no-embree");
  const bool fastOnly = a.has("fast-only");
  (void)useEmbree;  // used only with WHITTED_HAVE_EMBREE
  int tw = 512, th = 512;
  a.size("trace-size", tw, th);
  CsvWriter csv(a.str("csv"),
                {"scene", "primitives", "engine", "variant", "threads", "seconds_median", "seconds_min", "runs",
                 "mprims_per_s", "bytes_per_prim", "peak_bytes_per_prim", "primary_mrays", "cpu_seconds_median"});
  bs.scene.commit();
  SceneStats st0 = bs.scene.stats();
  const std::size_t prims = st0.triangles + st0.spheres + st0.tubes;
  const int allThreads = hardwareThreads();
  RayBatch primary = primaryRays(bs.camera.make(double(tw) / th, bs.scene.bounds()), tw, th);
  RayResults res;
  res.resize(primary.rays.size());
  auto mrays = [&](double seconds) { return primary.rays.size() / seconds * 1e-6; };

  // The builder alone runs on precomputed boxes of the largest mesh (only meaningful for a real mesh)
  uint32_t big = 0;
  std::size_t bigN = 0;
  for (uint32_t o = 0; o < bs.scene.objectCount(); ++o)
    if (bs.scene.objectType(o) == GeometryType::Triangles && bs.scene.mesh(o).triangles.size() > bigN) {
      big = o;
      bigN = bs.scene.mesh(o).triangles.size();
    }
  std::vector<Bounds3> boxes;
  std::vector<Vec3> cents;
  if (bigN >= 1000) {
    const TriangleMesh& m = bs.scene.mesh(big);
    for (const glm::uvec3& t : m.triangles) {
      Bounds3 b;
      for (int k = 0; k < 3; ++k) b.extend(m.positions[t[k]]);
      boxes.push_back(b);
      cents.push_back(b.center());
    }
  }

  for (int threads : threadList(a)) {
    const bool last = threads == threadList(a).back();
    // Scene::commit of freshly set geometry, with either builder (the scene's replaced-geometry builder)
    BuildRuns commitRuns[2] = {{"whitted", "Scene::commit SAH", prims, {}, {}, 0.0, 0.0, 0.0},
                               {"whitted", "Scene::commit fast", prims, {}, {}, 0.0, 0.0, 0.0}};
    const BvhBuildQuality commitQuality[2] = {BvhBuildQuality::Sah, BvhBuildQuality::Fast};
    BuildRuns bvhRuns{"whitted", "Bvh::build", bigN, {}, {}, 0.0, 0.0, 0.0};
    std::vector<BuildRuns> embreeRuns;
#ifdef WHITTED_HAVE_EMBREE
    const std::pair<RTCBuildQuality, const char*> qualities[] = {
        {RTC_BUILD_QUALITY_LOW, "low"}, {RTC_BUILD_QUALITY_MEDIUM, "medium"}, {RTC_BUILD_QUALITY_HIGH, "high"}};
    std::unique_ptr<EmbreeDevice> dev;
    if (useEmbree) {
      dev = std::make_unique<EmbreeDevice>(threads);
      for (auto [q, name] : qualities)
        if (!fastOnly || q == RTC_BUILD_QUALITY_LOW) embreeRuns.push_back({"embree", name, prims, {}, {}, 0.0, 0.0, 0.0});
    }
#endif
    Bvh bvh;
    for (int r = 0; r < warmup + reps; ++r) {
      const bool timed = r >= warmup, final = r == warmup + reps - 1;
      // Ours, as the renderer sees it: validity checks, boxes, SAH or Morton build, leaf-order copies
      for (int q = fastOnly ? 1 : 0; q < 2; ++q) {
        bs.scene.setReplacedBuildQuality(commitQuality[q]);
        for (uint32_t o = 0; o < bs.scene.objectCount(); ++o) setObjectFrom(bs.scene, o, bs.scene);
        {
          CpuLimit cores(threads);
          double t0 = now(), c0 = processCpuNow();
          bs.scene.commit();
          double t = now() - t0, c = processCpuNow() - c0;
          if (timed) commitRuns[q].wall.push_back(t), commitRuns[q].cpu.push_back(c);
        }
        // Acceleration-structure bytes: nodes + index arrays + the leaf-ordered triangle copy (12 B per triangle)
        if (final) {
          const SceneStats st = bs.scene.stats();
          commitRuns[q].bytes = commitRuns[q].peakBytes = double(st.bvhBytes + st.triangles * sizeof(glm::uvec3));
        }
        // The primary-ray speed each builder's tree gives (all threads), once
        if (final && last)
          commitRuns[q].primaryMrays =
              mrays(timeRepeated(1, 3, [&] { return traceOurs(bs.scene, primary, allThreads, res); }).median);
      }
      if (!boxes.empty() && !fastOnly) {
        CpuLimit cores(threads);
        double t0 = now(), c0 = processCpuNow();
        bvh.build(boxes, cents);
        double t = now() - t0, c = processCpuNow() - c0;
        if (timed) bvhRuns.wall.push_back(t), bvhRuns.cpu.push_back(c);
      }
#ifdef WHITTED_HAVE_EMBREE
      for (std::size_t k = 0; k < embreeRuns.size(); ++k) {
        BuildRuns& er = embreeRuns[k];
        EmbreeScene es(*dev, bs.scene, qualities[k].first);
        {
          CpuLimit cores(threads);
          double t = es.commit();
          if (timed) er.wall.push_back(t), er.cpu.push_back(es.commitCpuSeconds());
        }
        er.bytes = double(es.buildBytes());
        er.peakBytes = double(es.buildPeakBytes());
        if (final && last) {
          std::vector<RTCRay> rays = toEmbree(primary.rays);
          Timing tt = timeRepeated(1, 3, [&] { return traceEmbree(es.get(), rays, false, false, allThreads, res); });
          er.primaryMrays = mrays(tt.median);
        }
      }
#endif
    }
    bvhRuns.bytes = bvhRuns.peakBytes = double(bvh.memoryBytes());
    bs.scene.setReplacedBuildQuality(BvhBuildQuality::Fast);

    std::vector<BuildRuns> rows;
    if (!fastOnly) rows.push_back(commitRuns[0]);
    rows.push_back(commitRuns[1]);
    if (!boxes.empty() && !fastOnly) rows.push_back(bvhRuns);
    rows.insert(rows.end(), embreeRuns.begin(), embreeRuns.end());
    for (const BuildRuns& b : rows) {
      Timing t = summarize(b.wall), tc = summarize(b.cpu);
      double n = double(b.prims);
      csv.row({bs.name, fmt(b.prims), b.engine, b.variant, fmt(threads), fmt(t.median), fmt(t.min), fmt(t.runs),
               fmt(n / t.median * 1e-6), fmt(b.bytes / n), fmt(b.peakBytes / n),
               b.primaryMrays > 0.0 ? fmt(b.primaryMrays) : std::string(), fmt(tc.median)});
      std::printf("%-10s %-7s %-13s %d thr: %8.1f ms (cpu %8.1f ms)  %7.2f Mprims/s  %6.1f B/prim (peak %.1f)\n",
                  bs.name.c_str(), b.engine.c_str(), b.variant.c_str(), threads, t.median * 1e3, tc.median * 1e3,
                  n / t.median * 1e-6, b.bytes / n, b.peakBytes / n);
    }
    std::fflush(stdout);
  }
  return 0;
}

}  // namespace whitted::bench
