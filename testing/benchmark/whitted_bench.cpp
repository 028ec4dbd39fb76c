// whitted_bench: the measuring half of the benchmark (run_benchmark.py drives it and writes the report).
//
//   whitted_bench info   --scene NAME                        camera, light, material as JSON (for the VTK script)
//   whitted_bench rays   --scene NAME --size WxH             Mrays/s of primary / shadow / incoherent rays, ours
//                                                            and Embree's, 1 and all threads; hit agreement
//   whitted_bench build  --scene NAME                        BVH build time and memory, ours and Embree's
//                                                            (low / medium / high quality, 1 and all threads)
//   whitted_bench frame  --scene NAME --sizes WxH,...        whole frames; --threads-list 1,2 for scaling
//   whitted_bench update --scene NAME                        re-render cost after camera / transform / mesh edits
//   whitted_bench error  --scene NAME --size WxH             error against a high-quality reference vs run time
//                                                            (--budget S: slow settings get fewer timed runs)
//   whitted_bench mesh   --scene NAME --out file.whtmesh     writes a scene's first mesh (tests, debugging)
//
// Common options: --data DIR1,DIR2 (where wavelet_*.whtmesh live), --csv FILE (rows are appended), --reps N
// (timed runs, median reported), --warmup N (untimed runs first), --png-dir DIR.
#include "bench_common.h"
#include "bench_embree.h"
#include "bench_scenes.h"
#include "image.h"
#include "image_metrics.h"
#include "renderer.h"

#include <glm/gtc/matrix_transform.hpp>

#include <cinttypes>
#include <cmath>
#include <cstdio>
#include <memory>
#include <string>
#include <vector>

using namespace whitted;
using namespace whitted::bench;

namespace {

#ifdef WHITTED_HAVE_EMBREE
constexpr bool kHaveEmbree = true;
#else
constexpr bool kHaveEmbree = false;
#endif

int allThreads() {
  return hardwareThreads();
}

std::vector<int> threadList(const Args& a) {
  std::vector<int> t;
  for (const std::string& s : a.list("threads-list", "1,0")) {
    int n = std::atoi(s.c_str());
    t.push_back(n <= 0 ? allThreads() : n);
  }
  std::sort(t.begin(), t.end());
  t.erase(std::unique(t.begin(), t.end()), t.end());
  return t;
}

bool loadScene(const Args& a, BenchScene& bs) {
  std::string err;
  std::vector<std::string> dirs = a.list("data", ".");
  if (!buildBenchScene(a.str("scene", "classic"), dirs, bs, err)) {
    std::fprintf(stderr, "whitted_bench: %s\n", err.c_str());
    return false;
  }
  return true;
}

std::string jsonVec(const Vec3& v) {
  char b[128];
  std::snprintf(b, sizeof b, "[%.9g, %.9g, %.9g]", v.x, v.y, v.z);
  return b;
}
std::string jsonColor(const Color& c) {
  return jsonVec(Vec3(c));
}

// info --------------------------------------------------------------------------------------------------------

int cmdInfo(const Args& a) {
  BenchScene bs;
  if (!loadScene(a, bs)) return 2;
  bs.scene.commit();
  SceneStats st = bs.scene.stats();
  const Material& m = bs.mainMaterial;
  std::printf("{\n  \"scene\": \"%s\",\n  \"description\": \"%s\",\n", bs.name.c_str(), bs.description.c_str());
  std::printf("  \"triangles\": %zu, \"spheres\": %zu, \"capsules\": %zu,\n", st.triangles, st.spheres, st.capsules);
  std::printf("  \"camera\": {\"eye\": %s, \"focal\": %s, \"up\": %s, \"viewAngle\": %.9g},\n",
              jsonVec(bs.camera.eye).c_str(), jsonVec(bs.camera.focal).c_str(), jsonVec(bs.camera.up).c_str(),
              bs.camera.viewAngle);
  std::printf("  \"background\": %s,\n  \"lights\": [", jsonColor(bs.scene.background).c_str());
  for (std::size_t i = 0; i < bs.scene.lights().size(); ++i) {
    const Light& l = bs.scene.lights()[i];
    std::printf(
        "%s{\"positional\": %s, \"position\": %s, \"focalPoint\": %s, \"color\": %s, \"intensity\": %g, "
        "\"coneAngle\": %g, \"castShadows\": %s}",
        i ? ", " : "", l.positional ? "true" : "false", jsonVec(l.position).c_str(), jsonVec(l.focalPoint).c_str(),
        jsonColor(l.color).c_str(), l.intensity, l.coneAngle, l.castShadows ? "true" : "false");
  }
  std::printf(
      "],\n  \"material\": {\"diffuseColor\": %s, \"ambient\": %g, \"diffuse\": %g, \"specular\": %g, "
      "\"specularPower\": %g},\n",
      jsonColor(m.diffuseColor).c_str(), m.ambient, m.diffuse, m.specular, m.specularPower);
  Bounds3 b = bs.scene.bounds();
#ifdef WHITTED_HAVE_EMBREE
  const char* embreeVersion = RTC_VERSION_STRING;
#else
  const char* embreeVersion = "";
#endif
  std::printf(
      "  \"bounds\": [%s, %s],\n  \"hardwareThreads\": %d,\n  \"embree\": %s,\n  \"embreeVersion\": \"%s\",\n"
      "  \"compiler\": \"%s\"\n}\n",
      jsonVec(b.lo).c_str(), jsonVec(b.hi).c_str(), allThreads(), kHaveEmbree ? "true" : "false", embreeVersion,
#if defined(__clang__)
      "clang " __clang_version__
#elif defined(__GNUC__)
      "gcc " __VERSION__
#else
      "unknown"
#endif
  );
  return 0;
}

// mesh --------------------------------------------------------------------------------------------------------

int cmdMesh(const Args& a) {
  BenchScene bs;
  if (!loadScene(a, bs)) return 2;
  for (uint32_t o = 0; o < bs.scene.objectCount(); ++o)
    if (bs.scene.objectType(o) == GeometryType::Triangles)
      return writeMeshFile(a.str("out", "mesh.whtmesh"), bs.scene.mesh(o)) ? 0 : 1;
  std::fprintf(stderr, "scene has no triangle mesh\n");
  return 1;
}

// rays --------------------------------------------------------------------------------------------------------

/// A batch of rays of one kind, in our (double) form; Embree gets the same values rounded to float.
struct RayBatch {
  std::string kind;        ///< primary, shadow, incoherent
  bool occlusion = false;  ///< any-hit query (shadow rays)
  std::vector<Ray> rays;
};

/// What one engine reported for each ray of a batch.
struct RayResults {
  std::vector<uint8_t> hit;
  std::vector<uint32_t> geom, prim;
  std::vector<float> t;
  void resize(std::size_t n) {
    hit.assign(n, 0);
    geom.assign(n, 0);
    prim.assign(n, 0);
    t.assign(n, 0.0f);
  }
};

double traceOurs(const Scene& scene, const RayBatch& b, int threads, RayResults& out, double* cpu = nullptr) {
  return parallelFor(
      b.rays.size(), threads,
      [&](std::size_t lo, std::size_t hi, int) {
        for (std::size_t i = lo; i < hi; ++i) {
          if (b.occlusion) {
            // Opaque materials (the ray benchmark sets kt = 0), so transmittance is a pure any-hit query
            Color tr = scene.transmittance(b.rays[i], 1.0f / 255.0f);
            out.hit[i] = maxComponent(tr) <= 0.0f;
          } else {
            Hit h;
            bool found = scene.intersect(b.rays[i], h);
            out.hit[i] = found;
            out.geom[i] = h.instance;
            out.prim[i] = h.prim;
            out.t[i] = float(h.t);
          }
        }
      },
      cpu);
}

#ifdef WHITTED_HAVE_EMBREE
void toEmbree(const Ray& r, RTCRay& e) {
  e.org_x = float(r.origin.x);
  e.org_y = float(r.origin.y);
  e.org_z = float(r.origin.z);
  e.dir_x = float(r.dir.x);
  e.dir_y = float(r.dir.y);
  e.dir_z = float(r.dir.z);
  e.tnear = float(r.tMin);
  e.tfar = std::isfinite(r.tMax) ? float(r.tMax) : std::numeric_limits<float>::infinity();
  e.time = 0.0f;
  e.mask = 0xFFFFFFFFu;
  e.id = 0;
  e.flags = 0;
}

double traceEmbree(RTCScene scene, const std::vector<RTCRay>& rays, bool occlusion, int threads, RayResults& out,
                   double* cpu = nullptr) {
  return parallelFor(
      rays.size(), threads,
      [&](std::size_t lo, std::size_t hi, int) {
        RTCIntersectContext ctx;
        rtcInitIntersectContext(&ctx);
        for (std::size_t i = lo; i < hi; ++i) {
          if (occlusion) {
            RTCRay r = rays[i];
            rtcOccluded1(scene, &ctx, &r);
            out.hit[i] = r.tfar < 0.0f;
          } else {
            RTCRayHit rh;
            rh.ray = rays[i];
            rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
            rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
            rtcIntersect1(scene, &ctx, &rh);
            out.hit[i] = rh.hit.geomID != RTC_INVALID_GEOMETRY_ID;
            out.geom[i] = rh.hit.geomID;
            out.prim[i] = rh.hit.primID;
            out.t[i] = rh.ray.tfar;
          }
        }
      },
      cpu);
}
#endif

/// Primary rays through pixel centres, then shadow rays to the first light and incoherent rays (uniform random
/// directions on the hemisphere facing the viewer) from every primary hit. All secondary rays start at our
/// robust offset origin with tMin = epsilon (1e-5 x scene diagonal) so Embree's float traversal does not re-hit
/// the surface it leaves; both engines get exactly these rays.
std::vector<RayBatch> makeRays(const Scene& scene, const Camera& cam, int w, int h) {
  std::vector<RayBatch> out(3);
  out[0].kind = "primary";
  out[1].kind = "shadow";
  out[1].occlusion = true;
  out[2].kind = "incoherent";
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) out[0].rays.push_back(cam.rayPixel(x + 0.5, y + 0.5, w, h));
  const double eps = 1e-5 * scene.bounds().diagonal();
  const Light* light = scene.lights().empty() ? nullptr : &scene.lights()[0];
  uint32_t index = 0;
  for (const Ray& r : out[0].rays) {
    Hit hit;
    ++index;
    if (!scene.intersect(r, hit)) continue;
    SurfacePoint sp = scene.surface(r, hit);
    Vec3 d = glm::normalize(r.dir);
    Vec3 nf = glm::dot(sp.ng, d) > 0.0 ? -sp.ng : sp.ng;
    if (light) {
      Ray s;
      Vec3 toL = light->positional ? light->position - sp.p : -light->direction();
      s.dir = glm::normalize(toL);
      s.origin = offsetRayOrigin(sp.p, sp.pError, sp.ng, s.dir);
      s.tMin = eps;
      s.tMax = light->positional ? glm::length(light->position - s.origin) * (1.0 - 1e-9) : kInfinity;
      out[1].rays.push_back(s);
    }
    double z = 1.0 - 2.0 * hashFloat(index, 91u), phi = 2.0 * kPi * hashFloat(index, 92u);
    double rr = std::sqrt(std::max(0.0, 1.0 - z * z));
    Vec3 dir(rr * std::cos(phi), rr * std::sin(phi), z);
    if (glm::dot(dir, nf) < 0.0) dir = -dir;
    Ray q;
    q.dir = dir;
    q.origin = offsetRayOrigin(sp.p, sp.pError, sp.ng, dir);
    q.tMin = eps;
    q.tMax = kInfinity;
    out[2].rays.push_back(q);
  }
  return out;
}

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
  CsvWriter agree(a.str("agreement-csv"), {"scene", "kind", "rays", "hits_ours", "hits_embree", "hit_mismatch",
                                           "prim_mismatch", "prim_mismatch_same_t", "t_rel_err_max", "t_rel_err_p999"});
#ifdef WHITTED_HAVE_EMBREE
  std::unique_ptr<EmbreeDevice> device;
  std::unique_ptr<EmbreeScene> escene;
  if (useEmbree) {
    device = std::make_unique<EmbreeDevice>(0);
    escene = std::make_unique<EmbreeScene>(*device, bs.scene);
    escene->commit();
  }
#endif
  for (const RayBatch& b : batches) {
    std::size_t n = b.rays.size();
    RayResults ours, theirs;
    ours.resize(n);
    theirs.resize(n);
#ifdef WHITTED_HAVE_EMBREE
    std::vector<RTCRay> erays(n);
    for (std::size_t i = 0; i < n; ++i) toEmbree(b.rays[i], erays[i]);
#endif
    // BVH nodes visited per ray (untimed pass): traversal work independent of the machine
    uint64_t nodes = 0;
    for (const Ray& r : b.rays) {
      Hit h;
      if (b.occlusion)
        bs.scene.transmittance(r, 1.0f / 255.0f, &nodes);
      else
        bs.scene.intersect(r, h, &nodes);
    }
    double nodesPerRay = n ? double(nodes) / double(n) : 0.0;
    for (int threads : threadList(a)) {
      // Ours and Embree alternate run by run, so a load change on the machine hits both medians alike
      std::vector<double> tOurs, tEmbree, cOurs, cEmbree;
      for (int r = 0; r < warmup + std::max(1, reps); ++r) {
        double co = 0.0, ce = 0.0;
        double to = traceOurs(bs.scene, b, threads, ours, &co);
        double te = 0.0;
#ifdef WHITTED_HAVE_EMBREE
        if (useEmbree) te = traceEmbree(escene->get(), erays, b.occlusion, threads, theirs, &ce);
#endif
        if (r >= warmup) {
          tOurs.push_back(to);
          tEmbree.push_back(te);
          cOurs.push_back(co);
          cEmbree.push_back(ce);
        }
      }
      Timing t = summarize(tOurs), tc = summarize(cOurs);
      std::size_t hits = std::count(ours.hit.begin(), ours.hit.end(), uint8_t(1));
      csv.row({bs.name, b.kind, "whitted", fmt(threads), fmt(n), fmt(hits), fmt(t.median), fmt(t.min), fmt(t.max),
               fmt(t.runs), fmt(n / t.median * 1e-6), fmt(nodesPerRay), fmt(tc.median), fmt(n / tc.median * 1e-6)});
      std::printf("%-12s %-11s whitted %d thr: %8.3f Mrays/s (%zu rays, %zu hits, %.0f nodes/ray)\n", bs.name.c_str(),
                  b.kind.c_str(), threads, n / t.median * 1e-6, n, hits, nodesPerRay);
      if (useEmbree) {
        Timing te = summarize(tEmbree), tec = summarize(cEmbree);
        std::size_t eh = std::count(theirs.hit.begin(), theirs.hit.end(), uint8_t(1));
        csv.row({bs.name, b.kind, "embree", fmt(threads), fmt(n), fmt(eh), fmt(te.median), fmt(te.min), fmt(te.max),
                 fmt(te.runs), fmt(n / te.median * 1e-6), "", fmt(tec.median), fmt(n / tec.median * 1e-6)});
        std::printf("%-12s %-11s embree  %d thr: %8.3f Mrays/s (%zu hits)  ours/embree %.3f\n", bs.name.c_str(),
                    b.kind.c_str(), threads, n / te.median * 1e-6, eh, te.median / t.median);
      }
      std::fflush(stdout);
    }
    if (!useEmbree) continue;
    // Agreement: hit/miss, and for closest hits the primitive and the distance
    std::size_t hitMis = 0, primMis = 0, primMisSameT = 0, ho = 0, he = 0;
    int dump = a.integer("dump-mismatches", 0);
    auto show = [&](std::size_t i, const char* what) {
      if (dump-- <= 0) return;
      const Ray& r = b.rays[i];
      std::fprintf(stderr,
                   "  %s %s ray %zu: o (%.9g %.9g %.9g) d (%.9g %.9g %.9g) t [%.3g, %.3g]: ours %s g%u p%u t %.9g, "
                   "embree %s g%u p%u t %.9g\n",
                   b.kind.c_str(), what, i, r.origin.x, r.origin.y, r.origin.z, r.dir.x, r.dir.y, r.dir.z, r.tMin,
                   r.tMax, ours.hit[i] ? "hit" : "miss", ours.geom[i], ours.prim[i], double(ours.t[i]),
                   theirs.hit[i] ? "hit" : "miss", theirs.geom[i], theirs.prim[i], double(theirs.t[i]));
      // Re-test both reported triangles with our intersector and with long-double barycentrics of the exact ray
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
        auto cross = [](const LD* x, const LD* y, LD* o) {
          o[0] = x[1] * y[2] - x[2] * y[1];
          o[1] = x[2] * y[0] - x[0] * y[2];
          o[2] = x[0] * y[1] - x[1] * y[0];
        };
        auto dot = [](const LD* x, const LD* y) { return x[0] * y[0] + x[1] * y[1] + x[2] * y[2]; };
        cross(d, e2, pv);
        LD det = dot(e1, pv), u = dot(tv, pv) / det;
        cross(tv, e1, qv);
        LD v = dot(d, qv) / det, t = dot(e2, qv) / det;
        std::fprintf(stderr,
                     "    %s's triangle: our test %s (t %.9g); long double: t %.9Lg, barycentrics %.3Lg %.3Lg %.3Lg\n",
                     who, h ? "hit" : "miss", h ? h->t : 0.0, t, 1.0L - u - v, u, v);
      };
      if (b.occlusion) {
        // Any-hit queries report no primitive: find the closest ones both engines see along the shadow ray
        Hit h;
        bool oh = bs.scene.intersect(r, h);
        probe("whitted closest", oh, h.instance, h.prim);
#ifdef WHITTED_HAVE_EMBREE
        if (useEmbree) {
          RTCIntersectContext ctx;
          rtcInitIntersectContext(&ctx);
          RTCRayHit rh;
          toEmbree(r, rh.ray);
          rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
          rtcIntersect1(escene->get(), &ctx, &rh);
          std::fprintf(stderr, "    embree closest: t %.9g\n", double(rh.ray.tfar));
          probe("embree closest", rh.hit.geomID != RTC_INVALID_GEOMETRY_ID, rh.hit.geomID, rh.hit.primID);
        }
#endif
      } else {
        probe("whitted", ours.hit[i], ours.geom[i], ours.prim[i]);
        probe("embree", theirs.hit[i], theirs.geom[i], theirs.prim[i]);
      }
    };
    std::vector<double> rel;
    for (std::size_t i = 0; i < n; ++i) {
      ho += ours.hit[i];
      he += theirs.hit[i];
      if (ours.hit[i] != theirs.hit[i]) {
        ++hitMis;
        show(i, "hit/miss");
        continue;
      }
      if (b.occlusion || !ours.hit[i]) continue;
      double re = std::abs(double(ours.t[i]) - double(theirs.t[i])) / std::max(1e-30, std::abs(double(ours.t[i])));
      rel.push_back(re);
      if (ours.geom[i] != theirs.geom[i] || ours.prim[i] != theirs.prim[i]) {
        ++primMis;
        if (re < 1e-4)
          ++primMisSameT;  // a tie at a shared edge or vertex: both answers are right
        else
          show(i, "primitive");
      }
    }
    std::sort(rel.begin(), rel.end());
    double relMax = rel.empty() ? 0.0 : rel.back();
    double relP = rel.empty() ? 0.0 : rel[std::min(rel.size() - 1, std::size_t(0.999 * double(rel.size())))];
    agree.row({bs.name, b.kind, fmt(n), fmt(ho), fmt(he), fmt(hitMis), fmt(primMis), fmt(primMisSameT), fmt(relMax),
               fmt(relP)});
    std::printf("%-12s %-11s agreement: %zu of %zu rays differ in hit/miss, %zu in primitive (%zu of them ties)\n",
                bs.name.c_str(), b.kind.c_str(), hitMis, n, primMis, primMisSameT);
  }
  return 0;
}

// build -------------------------------------------------------------------------------------------------------

int cmdBuild(const Args& a) {
  BenchScene bs;
  if (!loadScene(a, bs)) return 2;
  int reps = a.integer("reps", 3), warmup = a.integer("warmup", 1);
  bool useEmbree = kHaveEmbree && !a.has("no-embree");
  (void)useEmbree;  // used only with WHITTED_HAVE_EMBREE
  int tw = 512, th = 512;
  a.size("trace-size", tw, th);
  CsvWriter csv(a.str("csv"),
                {"scene", "primitives", "engine", "variant", "threads", "seconds_median", "seconds_min", "runs",
                 "mprims_per_s", "bytes_per_prim", "peak_bytes_per_prim", "primary_mrays", "cpu_seconds_median"});
  bs.scene.commit();
  SceneStats st0 = bs.scene.stats();
  std::size_t prims = st0.triangles + st0.spheres + st0.capsules;
  Camera cam = bs.camera.make(double(tw) / th, bs.scene.bounds());
  RayBatch primary;
  primary.kind = "primary";
  for (int y = 0; y < th; ++y)
    for (int x = 0; x < tw; ++x) primary.rays.push_back(cam.rayPixel(x + 0.5, y + 0.5, tw, th));
  RayResults res;
  res.resize(primary.rays.size());
  auto oursTrace = [&](const Scene& s) {
    Timing t = timeRepeated(1, 3, [&] { return traceOurs(s, primary, allThreads(), res); });
    return primary.rays.size() / t.median * 1e-6;
  };

  // Ours, as the renderer sees it: Scene::commit of freshly set geometry (validity checks, boxes, binned SAH
  // build, leaf-order copies of the triangles). The core decides its own build threads (no setting): the row
  // is labelled with the hardware thread count.
  {
    std::vector<double> times, cpu;
    CommitStats cst;
    for (int r = 0; r < warmup + reps; ++r) {
      for (uint32_t o = 0; o < bs.scene.objectCount(); ++o) {
        switch (bs.scene.objectType(o)) {
          case GeometryType::Triangles:
            bs.scene.setMesh(o, TriangleMesh(bs.scene.mesh(o)));
            break;
          case GeometryType::Spheres:
            bs.scene.setSpheres(o, SphereSet(bs.scene.spheres(o)));
            break;
          case GeometryType::Capsules:
            bs.scene.setCapsules(o, CapsuleSet(bs.scene.capsules(o)));
            break;
        }
      }
      double t0 = now(), c0 = processCpuNow();
      cst = bs.scene.commit();
      double t = now() - t0;
      if (r >= warmup) {
        times.push_back(t);
        cpu.push_back(processCpuNow() - c0);
      }
    }
    Timing t = summarize(times);
    SceneStats st = bs.scene.stats();
    // Acceleration-structure bytes: nodes + index arrays + the leaf-ordered triangle copy (12 B per triangle)
    double bytes = double(st.bvhBytes + st.triangles * sizeof(glm::uvec3));
    csv.row({bs.name, fmt(prims), "whitted", "Scene::commit", fmt(allThreads()), fmt(t.median), fmt(t.min), fmt(t.runs),
             fmt(prims / t.median * 1e-6), fmt(bytes / prims), fmt(bytes / prims), fmt(oursTrace(bs.scene)),
             fmt(summarize(cpu).median)});
    std::printf("%-10s whitted commit      %d thr: %8.1f ms  %7.2f Mprims/s  %6.1f B/prim  (%zu nodes)\n",
                bs.name.c_str(), allThreads(), t.median * 1e3, prims / t.median * 1e-6, bytes / prims, st.bvhNodes);
  }

  // Ours, the BVH builder alone on precomputed boxes of the largest object
  {
    uint32_t big = 0;
    std::size_t bigN = 0;
    for (uint32_t o = 0; o < bs.scene.objectCount(); ++o)
      if (bs.scene.objectType(o) == GeometryType::Triangles && bs.scene.mesh(o).triangles.size() > bigN) {
        big = o;
        bigN = bs.scene.mesh(o).triangles.size();
      }
    if (bigN >= 1000) {  // only meaningful for a real mesh (not a floor quad)
      const TriangleMesh& m = bs.scene.mesh(big);
      std::vector<Bounds3> boxes(bigN);
      std::vector<Vec3> cents(bigN);
      for (std::size_t i = 0; i < bigN; ++i) {
        Bounds3 b;
        for (int k = 0; k < 3; ++k) b.extend(m.positions[m.triangles[i][k]]);
        boxes[i] = b;
        cents[i] = b.center();
      }
      Bvh bvh;
      std::vector<double> cpu;
      Timing t = timeRepeated(warmup, reps, [&] {
        double t0 = now(), c0 = processCpuNow();
        bvh.build(boxes, cents);
        cpu.push_back(processCpuNow() - c0);
        return now() - t0;
      });
      cpu.erase(cpu.begin(), cpu.begin() + std::min<std::ptrdiff_t>(warmup, std::ptrdiff_t(cpu.size()) - 1));
      double bytes = double(bvh.memoryBytes());
      csv.row({bs.name, fmt(bigN), "whitted", "Bvh::build", fmt(allThreads()), fmt(t.median), fmt(t.min), fmt(t.runs),
               fmt(bigN / t.median * 1e-6), fmt(bytes / bigN), fmt(bytes / bigN), "", fmt(summarize(cpu).median)});
      std::printf("%-10s whitted Bvh::build  %d thr: %8.1f ms  %7.2f Mprims/s  %6.1f B/prim  depth %d\n",
                  bs.name.c_str(), allThreads(), t.median * 1e3, bigN / t.median * 1e-6, bytes / bigN, bvh.depth());
    }
  }

#ifdef WHITTED_HAVE_EMBREE
  if (useEmbree) {
    const std::pair<RTCBuildQuality, const char*> qualities[] = {
        {RTC_BUILD_QUALITY_LOW, "low"}, {RTC_BUILD_QUALITY_MEDIUM, "medium"}, {RTC_BUILD_QUALITY_HIGH, "high"}};
    for (int threads : threadList(a)) {
      EmbreeDevice dev(threads);
      for (auto [q, qname] : qualities) {
        std::vector<double> times, cpu;
        long long bytes = 0, peak = 0;
        double mrays = 0.0;
        for (int r = 0; r < warmup + reps; ++r) {
          EmbreeScene es(dev, bs.scene, q);
          double t = es.commit();
          if (r >= warmup) {
            times.push_back(t);
            cpu.push_back(es.commitCpuSeconds());
          }
          bytes = es.buildBytes();
          peak = es.buildPeakBytes();
          if (r == warmup + reps - 1 && threads == allThreads()) {
            std::vector<RTCRay> er(primary.rays.size());
            for (std::size_t i = 0; i < er.size(); ++i) toEmbree(primary.rays[i], er[i]);
            Timing tt = timeRepeated(1, 3, [&] { return traceEmbree(es.get(), er, false, allThreads(), res); });
            mrays = er.size() / tt.median * 1e-6;
          }
        }
        Timing t = summarize(times);
        csv.row({bs.name, fmt(prims), "embree", qname, fmt(threads), fmt(t.median), fmt(t.min), fmt(t.runs),
                 fmt(prims / t.median * 1e-6), fmt(double(bytes) / prims), fmt(double(peak) / prims),
                 mrays > 0.0 ? fmt(mrays) : std::string(), fmt(summarize(cpu).median)});
        std::printf("%-10s embree  %-10s %d thr: %8.1f ms  %7.2f Mprims/s  %6.1f B/prim (peak %.1f)\n", bs.name.c_str(),
                    qname, threads, t.median * 1e3, prims / t.median * 1e-6, double(bytes) / prims,
                    double(peak) / prims);
      }
    }
  }
#endif
  return 0;
}

// frame -------------------------------------------------------------------------------------------------------

RenderSettings settingsFrom(const Args& a) {
  RenderSettings rs;
  rs.samplesPerPixel = a.integer("spp", 1);
  rs.adaptive = a.has("adaptive");
  rs.integrator.maxDepth = a.integer("depth", 5);
  rs.integrator.contributionThreshold = float(a.real("threshold", 1.0 / 255.0));
  rs.integrator.shadows = !a.has("no-shadows");
  return rs;
}

void savePng(const std::string& path, const FrameBuffer& fb) {
  if (!path.empty() && !writePng(path, fb.width, fb.height, toRgba8(fb)))
    std::fprintf(stderr, "cannot write %s\n", path.c_str());
}

int cmdFrame(const Args& a) {
  BenchScene bs;
  if (!loadScene(a, bs)) return 2;
  double t0 = now();
  CommitStats cst = bs.scene.commit();
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
                               "pixels_supersampled"});
  SceneStats st = bs.scene.stats();
  std::size_t prims = st.triangles + st.spheres + st.capsules;
  for (const std::string& sz : a.list("sizes", "800x600")) {
    int w = 0, h = 0;
    if (std::sscanf(sz.c_str(), "%dx%d", &w, &h) != 2) continue;
    Camera cam = bs.camera.make(double(w) / h, bs.scene.bounds());
    for (int threads : threadList(a)) {
      rs.threads = threads;
      FrameBuffer fb;
      FrameStats fs;
      std::vector<double> cpu;
      Timing t = timeRepeated(warmup, reps, [&] {
        double c0 = processCpuNow();
        fs = render(bs.scene, cam, rs, w, h, fb);
        cpu.push_back(processCpuNow() - c0);
        return fs.secondsTrace;
      });
      cpu.erase(cpu.begin(), cpu.begin() + std::min<std::ptrdiff_t>(warmup, std::ptrdiff_t(cpu.size()) - 1));
      Timing tc = summarize(cpu);
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
               fmt(fs.errorEstimateRms),
               fmt(prims),
               fmt(tc.median),
               fmt(fs.pixelsSupersampled)});
      std::printf(
          "%-10s %-12s %4dx%-4d %d thr: trace %9.2f ms (min %.2f, max %.2f), cpu %.2f ms, commit %.1f ms, "
          "%.2f Mrays/s%s\n",
          tag.c_str(), bs.name.c_str(), w, h, threads, t.median * 1e3, t.min * 1e3, t.max * 1e3, tc.median * 1e3,
          commitSeconds * 1e3, fs.rays.traced() / t.median * 1e-6,
          rs.adaptive
              ? (", supersampled " + std::to_string(fs.pixelsSupersampled) + " of " + std::to_string(w * h) + " pixels")
                    .c_str()
              : "");
      std::fflush(stdout);
      if (a.has("png")) savePng(a.str("png"), fb);
    }
  }
  (void)cst;
  return 0;
}

// update ------------------------------------------------------------------------------------------------------

int cmdUpdate(const Args& a) {
  // The main scene plus a ring of small glyph actors (UV-sphere meshes), as a ParaView pipeline with several
  // representations would give
  BenchScene bs;
  if (!loadScene(a, bs)) return 2;
  int w = 800, h = 600;
  a.size("size", w, h);
  int reps = a.integer("reps", 5), warmup = a.integer("warmup", 1);
  int glyphs = a.integer("actors", 8);
  bs.scene.commit();
  Bounds3 b0 = bs.scene.bounds();
  double rad = 0.06 * b0.diagonal();
  Material gm;
  gm.diffuseColor = gm.ambientColor = Color(0.3f, 0.6f, 0.9f);
  gm.ambient = 0.1f;
  gm.diffuse = 0.8f;
  gm.specular = 0.3f;
  gm.specularPower = 20.0f;
  uint32_t gmat = bs.scene.addMaterial(gm);
  std::vector<uint32_t> glyphInstances, glyphObjects;
  for (int i = 0; i < glyphs; ++i) {
    double ang = 2.0 * kPi * i / glyphs;
    Vec3 c = b0.center() + 0.45 * b0.diagonal() * Vec3(std::cos(ang), 0.0, std::sin(ang));
    TriangleMesh m = makeSphereMesh(Vec3(0.0), rad, 128, 64);  // ~16k triangles each
    roundToFloat(m);
    uint32_t o = bs.scene.addMesh(std::move(m));
    glyphObjects.push_back(o);
    glyphInstances.push_back(bs.scene.addInstance(o, glm::translate(Mat4(1.0), c), gmat));
  }
  // Remember what the adapter would have to hand over again without caching
  Scene original = bs.scene;
  auto resetObject = [&](uint32_t o) {
    switch (original.objectType(o)) {
      case GeometryType::Triangles:
        bs.scene.setMesh(o, TriangleMesh(original.mesh(o)));
        break;
      case GeometryType::Spheres:
        bs.scene.setSpheres(o, SphereSet(original.spheres(o)));
        break;
      case GeometryType::Capsules:
        bs.scene.setCapsules(o, CapsuleSet(original.capsules(o)));
        break;
    }
  };

  double tc0 = now();
  bs.scene.commit();
  double firstCommit = now() - tc0;
  SceneStats st = bs.scene.stats();
  RenderSettings rs;
  CameraSpec spec = bs.camera;
  Camera cam = spec.make(double(w) / h, bs.scene.bounds());
  FrameBuffer fb;

  CsvWriter csv(a.str("csv"), {"scene", "case", "triangles", "instances", "width", "height", "commit_seconds",
                               "trace_seconds", "total_seconds", "prepare_seconds", "objects_rebuilt",
                               "top_level_rebuilt", "runs", "commit_cpu_seconds", "trace_cpu_seconds"});
  auto measure = [&](const char* name, auto&& edit) {
    std::vector<double> commitT, traceT, prepT, commitC, traceC;
    CommitStats last;
    for (int r = 0; r < warmup + reps; ++r) {
      double p0 = now();
      edit(r);  // change the scene (untimed part: what the adapter hands over)
      double p1 = now(), cpu1 = processCpuNow();
      last = bs.scene.commit();
      double c1 = now(), cpu2 = processCpuNow();
      FrameStats fs = render(bs.scene, cam, rs, w, h, fb);
      double cpu3 = processCpuNow();
      if (r >= warmup) {
        prepT.push_back(p1 - p0);
        commitT.push_back(c1 - p1);
        traceT.push_back(fs.secondsTrace);
        commitC.push_back(cpu2 - cpu1);
        traceC.push_back(cpu3 - cpu2);
      }
    }
    Timing tc = summarize(commitT), tt = summarize(traceT), tp = summarize(prepT);
    csv.row({bs.name, name, fmt(st.triangles), fmt(bs.scene.instanceCount()), fmt(w), fmt(h), fmt(tc.median),
             fmt(tt.median), fmt(tc.median + tt.median), fmt(tp.median), fmt(last.objectsRebuilt),
             fmt(int(last.topLevelRebuilt)), fmt(tc.runs), fmt(summarize(commitC).median),
             fmt(summarize(traceC).median)});
    std::printf("%-26s commit %9.2f ms  trace %8.2f ms  total %9.2f ms  (%d objects rebuilt, top level %s)\n", name,
                tc.median * 1e3, tt.median * 1e3, (tc.median + tt.median) * 1e3, last.objectsRebuilt,
                last.topLevelRebuilt ? "rebuilt" : "kept");
    std::fflush(stdout);
  };

  std::printf("%s + %d glyph actors: %zu triangles, %zu instances, first commit %.1f ms\n", bs.name.c_str(), glyphs,
              st.triangles, bs.scene.instanceCount(), firstCommit * 1e3);
  measure("no change (re-render)", [&](int) {});
  measure("camera move", [&](int r) {
    CameraSpec s = spec;
    double ang = 0.02 * (r + 1);
    Vec3 off = s.eye - s.focal;
    s.eye = s.focal +
            Vec3(std::cos(ang) * off.x - std::sin(ang) * off.z, off.y, std::sin(ang) * off.x + std::cos(ang) * off.z);
    cam = s.make(double(w) / h, bs.scene.bounds());
  });
  cam = spec.make(double(w) / h, bs.scene.bounds());
  measure("material change",
          [&](int r) { bs.scene.material(gmat).diffuseColor = Color(0.3f + 0.01f * r, 0.6f, 0.9f); });
  measure("move one actor", [&](int r) {
    double ang = 2.0 * kPi * 0 / glyphs;
    Vec3 c = b0.center() + 0.45 * b0.diagonal() * Vec3(std::cos(ang), 0.0, std::sin(ang));
    bs.scene.setInstanceTransform(glyphInstances[0], glm::translate(Mat4(1.0), c + Vec3(0.0, 0.01 * rad * r, 0.0)));
  });
  measure("setMesh small actor (16k)", [&](int) { resetObject(glyphObjects[0]); });
  measure("setMesh main actor", [&](int) { resetObject(0); });
  measure("full rebuild (no caching)", [&](int) {
    for (uint32_t o = 0; o < bs.scene.objectCount(); ++o) resetObject(o);
  });
  return 0;
}

// error -------------------------------------------------------------------------------------------------------

int cmdError(const Args& a) {
  BenchScene bs;
  if (!loadScene(a, bs)) return 2;
  bs.scene.commit();
  int w = 320, h = 240;
  a.size("size", w, h);
  int reps = a.integer("reps", 3), warmup = a.integer("warmup", 1);
  int refSpp = a.integer("ref-spp", 64), refDepth = a.integer("ref-depth", 16);
  bool quick = a.has("quick");
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
                               "pixels_supersampled"});
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
  Timing refT = renderTimed(ref, refFb, refFs, 0, 1);
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
           fmt(refFs.errorEstimateRms),
           fmt(refFs.errorEstimateMax),
           "0",
           "0",
           "0",
           fmt(cpuMedian),
           "0"});
  std::printf("%s reference (%d spp, depth %d, threshold 0): %.2f s, error estimate RMS %.3g\n", bs.name.c_str(),
              refSpp, refDepth, refT.median, refFs.errorEstimateRms);

  struct Sampling {
    int spp;
    bool adaptive;
  };
  std::vector<Sampling> samplings = {{1, false}, {4, false}, {4, true}, {16, false}, {16, true}};
  std::vector<int> depths = {1, 2, 3, 4, 5, 6, 7, 8};
  std::vector<float> thresholds = {0.0f, 1.0f / 255, 4.0f / 255, 16.0f / 255, 64.0f / 255};
  if (quick) {
    samplings = {{1, false}, {4, true}};
    depths = {1, 5};
    thresholds = {0.0f, 1.0f / 255};
  }
  if (!secondary) {
    // Nothing reflects or refracts: depth and threshold cannot change the image (the kernel leaves them out)
    depths = {5};
    thresholds = {1.0f / 255};
  }
  for (const Sampling& s : samplings) {
    // Reference with the same samples but no truncation: isolates what the depth cap and threshold leave out,
    // which is what FrameStats::errorEstimateRms bounds
    RenderSettings tr;
    tr.samplesPerPixel = s.spp;
    tr.adaptive = s.adaptive;
    tr.integrator.maxDepth = refDepth;
    tr.integrator.contributionThreshold = 0.0f;
    FrameBuffer truncFb;
    FrameStats truncFs;
    render(bs.scene, cam, tr, w, h, truncFb);
    for (int depth : depths)
      for (float thr : thresholds) {
        RenderSettings rs;
        rs.samplesPerPixel = s.spp;
        rs.adaptive = s.adaptive;
        rs.integrator.maxDepth = depth;
        rs.integrator.contributionThreshold = thr;
        bool isDefault = s.spp == 1 && !s.adaptive && depth == 5 && std::abs(thr - 1.0f / 255) < 1e-6f;
        FrameBuffer fb;
        FrameStats fs;
        Timing t = renderTimed(rs, fb, fs, warmup, reps);
        ImageError e = compareImages(fb, refFb);
        ImageError et = compareImages(fb, truncFb);
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
                 fmt(fs.errorEstimateRms),
                 fmt(fs.errorEstimateMax),
                 fmt(et.maxChannelRms),
                 fmt(et.maxChannelMax),
                 fmt(et.rmse),
                 fmt(cpuMedian),
                 fmt(fs.pixelsSupersampled)});
        if (isDefault) savePng(pngDir.empty() ? "" : pngDir + "/" + bs.name + "_default.png", fb);
        std::printf(
            "%-12s spp %2d%s depth %d thr %6.4f: %8.2f ms (cpu %8.2f ms)  RMSE %.4f  PSNR %5.2f  SSIM %.4f  "
            "est %.4f trunc %.4f\n",
            bs.name.c_str(), s.spp, s.adaptive ? "a" : " ", depth, thr, t.median * 1e3, cpuMedian * 1e3, e.rmse, e.psnr,
            e.ssim, fs.errorEstimateRms, et.maxChannelRms);
        std::fflush(stdout);
      }
  }
  return 0;
}

void usage() {
  std::fprintf(stderr,
               "usage: whitted_bench info|rays|build|frame|update|error|mesh --scene NAME [options]\n"
               "scenes:");
  for (const std::string& n : benchSceneNames()) std::fprintf(stderr, " %s", n.c_str());
  std::fprintf(stderr, "\nEmbree anchor: %s\n", kHaveEmbree ? "compiled in" : "not available");
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 2) {
    usage();
    return 2;
  }
  std::string cmd = argv[1];
  Args a(argc, argv, 2);
  if (cmd == "info") return cmdInfo(a);
  if (cmd == "rays") return cmdRays(a);
  if (cmd == "build") return cmdBuild(a);
  if (cmd == "frame") return cmdFrame(a);
  if (cmd == "update") return cmdUpdate(a);
  if (cmd == "error") return cmdError(a);
  if (cmd == "mesh") return cmdMesh(a);
  usage();
  return 2;
}
