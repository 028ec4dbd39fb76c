// whitted_bench rays --scene NAME --size WxH: Mrays/s of primary, shadow and incoherent rays, ours and Embree's
// (default mode and RTC_SCENE_FLAG_ROBUST), at each thread count of --threads-list; hit agreement with each.
// --dump-mismatches N prints the rays where the engines disagree and re-tests both triangles in long double.
#include "bench_commands.h"
#include "bench_trace.h"

#include <algorithm>
#include <cstdio>
#include <memory>

namespace whitted::bench {

namespace {

/// One engine of the comparison: ours or an Embree scene (default or robust mode).
struct Engine {
  std::string name;  ///< CSV "engine" column: whitted, embree, embree-robust
#ifdef WHITTED_HAVE_EMBREE
  RTCScene scene = nullptr;  ///< Embree scene (null for ours)
#else
  const void* scene = nullptr;
#endif
  RayResults results;
  std::vector<double> wall, cpu;
};

/// Prints ray i of a batch where ours and an anchor disagree, re-testing both triangles with our intersector and
/// with long-double Moeller-Trumbore on the exact (double) ray.
void dumpMismatch(const BenchScene& bs, const RayBatch& b, std::size_t i, const char* what, const Engine& ours,
                  const Engine& anchor) {
  const Ray& r = b.rays[i];
  const RayResults &o = ours.results, &e = anchor.results;
  std::fprintf(stderr,
               "  %s %s ray %zu (%s): o (%.9g %.9g %.9g) d (%.9g %.9g %.9g) t [%.3g, %.3g]: ours %s g%u p%u t %.9g, "
               "anchor %s g%u p%u t %.9g\n",
               b.kind.c_str(), what, i, anchor.name.c_str(), r.origin.x, r.origin.y, r.origin.z, r.dir.x, r.dir.y,
               r.dir.z, r.tMin, r.tMax, o.hit[i] ? "hit" : "miss", o.geom[i], o.prim[i], double(o.t[i]),
               e.hit[i] ? "hit" : "miss", e.geom[i], e.prim[i], double(e.t[i]));
  auto probe = [&](const char* who, bool hit, uint32_t g, uint32_t prim) {
    if (!hit || g >= bs.scene.instanceCount() ||
        bs.scene.objectType(bs.scene.instanceObject(g)) != GeometryType::Triangles)
      return;
    const TriangleMesh& m = bs.scene.mesh(bs.scene.instanceObject(g));
    const glm::uvec3 tri = m.triangles[prim];
    Vec3 p0 = m.positions[tri.x], p1 = m.positions[tri.y], p2 = m.positions[tri.z];
    auto h = intersectTriangle(r, p0, p1, p2);
    // Moeller-Trumbore in long double on the double ray (the float-rounded origin Embree saw differs by an ulp)
    using LD = long double;
    LD e1[3], e2[3], pv[3], tv[3], qv[3], d[3] = {r.dir.x, r.dir.y, r.dir.z};
    for (int k = 0; k < 3; ++k) {
      e1[k] = LD(p1[k]) - LD(p0[k]);
      e2[k] = LD(p2[k]) - LD(p0[k]);
      tv[k] = LD(r.origin[k]) - LD(p0[k]);
    }
    auto cross = [](const LD* x, const LD* y, LD* out) {
      out[0] = x[1] * y[2] - x[2] * y[1];
      out[1] = x[2] * y[0] - x[0] * y[2];
      out[2] = x[0] * y[1] - x[1] * y[0];
    };
    auto dot = [](const LD* x, const LD* y) { return x[0] * y[0] + x[1] * y[1] + x[2] * y[2]; };
    cross(d, e2, pv);
    LD det = dot(e1, pv), u = dot(tv, pv) / det;
    cross(tv, e1, qv);
    LD v = dot(d, qv) / det, t = dot(e2, qv) / det;
    std::fprintf(stderr,
                 "    %s's triangle: our test %s (t %.9g); long double: t %.9Lg, barycentrics %.3Lg %.3Lg %.3Lg\n", who,
                 h ? "hit" : "miss", h ? h->t : 0.0, t, 1.0L - u - v, u, v);
  };
  if (b.occlusion) {
    // Any-hit queries report no primitive: find the closest ones both engines see along the shadow ray
    Hit h;
    bool oh = bs.scene.intersect(r, h);
    probe("whitted closest", oh, h.instance, h.prim);
#ifdef WHITTED_HAVE_EMBREE
    RTCIntersectContext ctx;
    rtcInitIntersectContext(&ctx);
    RTCRayHit rh;
    toEmbree(r, rh.ray);
    rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
    rtcIntersect1(anchor.scene, &ctx, &rh);
    std::fprintf(stderr, "    anchor closest: t %.9g\n", double(rh.ray.tfar));
    probe("anchor closest", rh.hit.geomID != RTC_INVALID_GEOMETRY_ID, rh.hit.geomID, rh.hit.primID);
#endif
  } else {
    probe("whitted", o.hit[i], o.geom[i], o.prim[i]);
    probe("anchor", e.hit[i], e.geom[i], e.prim[i]);
  }
}

/// Hit/miss, primitive and distance agreement of an anchor with ours over a batch; one CSV row.
void agreement(const Args& a, const BenchScene& bs, const RayBatch& b, const Engine& ours, const Engine& anchor,
               CsvWriter& csv) {
  std::size_t n = b.rays.size(), hitMis = 0, primMis = 0, primMisSameT = 0, ho = 0, he = 0;
  int dump = a.integer("dump-mismatches", 0);
  const RayResults &o = ours.results, &e = anchor.results;
  std::vector<double> rel;
  for (std::size_t i = 0; i < n; ++i) {
    ho += o.hit[i];
    he += e.hit[i];
    if (o.hit[i] != e.hit[i]) {
      ++hitMis;
      if (dump-- > 0) dumpMismatch(bs, b, i, "hit/miss", ours, anchor);
      continue;
    }
    if (b.occlusion || !o.hit[i]) continue;
    double re = std::abs(double(o.t[i]) - double(e.t[i])) / std::max(1e-30, std::abs(double(o.t[i])));
    rel.push_back(re);
    if (o.geom[i] != e.geom[i] || o.prim[i] != e.prim[i]) {
      ++primMis;
      if (re < 1e-4)
        ++primMisSameT;  // a tie at a shared edge or vertex: both answers are right
      else if (dump-- > 0)
        dumpMismatch(bs, b, i, "primitive", ours, anchor);
    }
  }
  std::sort(rel.begin(), rel.end());
  double relMax = rel.empty() ? 0.0 : rel.back();
  double relP = rel.empty() ? 0.0 : rel[std::min(rel.size() - 1, std::size_t(0.999 * double(rel.size())))];
  csv.row({bs.name, b.kind, anchor.name, fmt(n), fmt(ho), fmt(he), fmt(hitMis), fmt(primMis), fmt(primMisSameT),
           fmt(relMax), fmt(relP)});
  std::printf("%-12s %-11s agreement with %s: %zu of %zu rays differ in hit/miss, %zu in primitive (%zu ties)\n",
              bs.name.c_str(), b.kind.c_str(), anchor.name.c_str(), hitMis, n, primMis, primMisSameT);
}

}  // namespace

int cmdRays(const Args& a) {
  BenchScene bs;
  if (!loadScene(a, bs)) return 2;
  int w = 512, h = 384;
  a.size("size", w, h);
  int reps = a.integer("reps", 5), warmup = a.integer("warmup", 1);
  bool useEmbree = kHaveEmbree && !a.has("no-embree");
  // Opaque copy of every material: the ray benchmark compares pure closest-hit and any-hit queries
  for (uint32_t m = 0; m < bs.scene.materialCount(); ++m) bs.scene.material(m).transmittance = Color(0.0f);
  bs.scene.commit();
  Camera cam = bs.camera.make(double(w) / h, bs.scene.bounds());
  std::vector<RayBatch> batches = makeRays(bs.scene, cam, w, h);

  CsvWriter csv(a.str("csv"),
                {"scene", "kind", "engine", "threads", "rays", "hits", "seconds_median", "seconds_min", "seconds_max",
                 "runs", "mrays_median", "nodes_per_ray", "cpu_seconds_median", "mrays_per_cpu_second"});
  CsvWriter agree(a.str("agreement-csv"),
                  {"scene", "kind", "anchor", "rays", "hits_ours", "hits_embree", "hit_mismatch", "prim_mismatch",
                   "prim_mismatch_same_t", "t_rel_err_max", "t_rel_err_p999"});
  // Ours, then Embree in its default mode and in robust mode (same device, build quality medium, same rays)
  std::vector<Engine> engines(1);
  engines[0].name = "whitted";
#ifdef WHITTED_HAVE_EMBREE
  std::unique_ptr<EmbreeDevice> device;
  std::vector<std::unique_ptr<EmbreeScene>> anchors;
  if (useEmbree) {
    device = std::make_unique<EmbreeDevice>(0);
    for (auto [flags, name] : {std::pair{RTC_SCENE_FLAG_NONE, "embree"}, {RTC_SCENE_FLAG_ROBUST, "embree-robust"}}) {
      anchors.push_back(std::make_unique<EmbreeScene>(*device, bs.scene, RTC_BUILD_QUALITY_MEDIUM, flags));
      anchors.back()->commit();
      engines.push_back({name, anchors.back()->get(), {}, {}, {}});
    }
  }
#endif
  for (const RayBatch& b : batches) {
    std::size_t n = b.rays.size();
    for (Engine& e : engines) e.results.resize(n);
#ifdef WHITTED_HAVE_EMBREE
    std::vector<RTCRay> erays = toEmbree(b.rays);
#endif
    // BVH nodes visited per ray (untimed pass): traversal work independent of the machine
    uint64_t nodes = 0;
    for (const Ray& r : b.rays) {
      Hit hit;
      if (b.occlusion)
        bs.scene.transmittance(r, 1.0f / 255.0f, &nodes);
      else
        bs.scene.intersect(r, hit, &nodes);
    }
    double nodesPerRay = n ? double(nodes) / double(n) : 0.0;
    for (int threads : threadList(a)) {
      // The engines alternate run by run, so a load change on the machine hits every median alike
      for (Engine& e : engines) e.wall.clear(), e.cpu.clear();
      for (int r = 0; r < warmup + std::max(1, reps); ++r) {
        for (Engine& e : engines) {
          double cpu = 0.0, wall = 0.0;
          if (!e.scene) wall = traceOurs(bs.scene, b, threads, e.results, &cpu);
#ifdef WHITTED_HAVE_EMBREE
          else
            wall = traceEmbree(e.scene, erays, b.occlusion, b.packets, threads, e.results, &cpu);
#endif
          if (r >= warmup) {
            e.wall.push_back(wall);
            e.cpu.push_back(cpu);
          }
        }
      }
      const double ourMedian = summarize(engines[0].wall).median;
      for (const Engine& e : engines) {
        Timing t = summarize(e.wall), tc = summarize(e.cpu);
        std::size_t hits = std::count(e.results.hit.begin(), e.results.hit.end(), uint8_t(1));
        csv.row({bs.name, b.kind, e.name, fmt(threads), fmt(n), fmt(hits), fmt(t.median), fmt(t.min), fmt(t.max),
                 fmt(t.runs), fmt(n / t.median * 1e-6), e.scene ? "" : fmt(nodesPerRay), fmt(tc.median),
                 fmt(n / tc.median * 1e-6)});
        std::printf("%-12s %-11s %-13s %d thr: %8.3f Mrays/s (%zu rays, %zu hits)  ours/this %.3f\n",
                    bs.name.c_str(), b.kind.c_str(), e.name.c_str(), threads, n / t.median * 1e-6, n, hits,
                    t.median / ourMedian);
      }
      std::fflush(stdout);
    }
    for (std::size_t k = 1; k < engines.size(); ++k) agreement(a, bs, b, engines[0], engines[k], agree);
  }
  return 0;
}

}  // namespace whitted::bench
