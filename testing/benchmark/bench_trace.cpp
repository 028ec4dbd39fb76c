#include "bench_trace.h"

#include "bench_common.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace whitted::bench {

void RayResults::resize(std::size_t n) {
  hit.assign(n, 0);
  geom.assign(n, 0);
  prim.assign(n, 0);
  t.assign(n, 0.0f);
}

RayBatch primaryRays(const Camera& cam, int w, int h) {
  RayBatch b;
  b.kind = "primary";
  b.rays.reserve(std::size_t(w) * std::size_t(h));
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) b.rays.push_back(cam.rayPixel(x + 0.5, y + 0.5, w, h));
  return b;
}

std::vector<RayBatch> makeRays(const Scene& scene, const Camera& cam, int w, int h) {
  std::vector<RayBatch> out(3);
  out[0] = primaryRays(cam, w, h);
  // The camera rays again, as packets of 4 pixels of a row (what Integrator::traceBlock traces at 1 spp)
  RayBatch primary4 = out[0];
  primary4.kind = "primary4";
  primary4.packets = true;
  out[1].kind = "shadow";
  out[1].occlusion = true;
  out[2].kind = "incoherent";
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
  // The shadow rays again, as packets of four rays of consecutive hits (what Integrator::traceBlock casts)
  RayBatch packets = out[1];
  packets.kind = "shadow4";
  packets.packets = true;
  out.insert(out.begin() + 2, std::move(packets));
  out.insert(out.begin() + 1, std::move(primary4));
  return out;
}

double traceOurs(const Scene& scene, const RayBatch& b, int threads, RayResults& out, double* cpu) {
  return parallelFor(
      b.rays.size(), threads,
      [&](std::size_t lo, std::size_t hi, int) {
        if (b.packets && !b.occlusion) {
          for (std::size_t i = lo; i < hi; i += 4) {
            const int n = int(std::min<std::size_t>(4, hi - i));
            Hit h[4];
            const unsigned found = scene.intersectPacket(&b.rays[i], (1u << n) - 1u, h);
            for (int k = 0; k < n; ++k) {
              const std::size_t j = i + std::size_t(k);
              out.hit[j] = found >> k & 1;
              out.geom[j] = h[k].instance;
              out.prim[j] = h[k].prim;
              out.t[j] = float(h[k].t);
            }
          }
          return;
        }
        if (b.packets) {
          for (std::size_t i = lo; i < hi; i += 4) {
            const int n = int(std::min<std::size_t>(4, hi - i));
            unsigned blocked = 0;
            // Opaque materials: no ray falls back to transmittance()
            scene.occludedPacket(&b.rays[i], (1u << n) - 1u, blocked);
            for (int k = 0; k < n; ++k) out.hit[i + std::size_t(k)] = blocked >> k & 1;
          }
          return;
        }
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

std::vector<RTCRay> toEmbree(const std::vector<Ray>& rays) {
  std::vector<RTCRay> e(rays.size());
  for (std::size_t i = 0; i < rays.size(); ++i) toEmbree(rays[i], e[i]);
  return e;
}

double traceEmbree(RTCScene scene, const std::vector<RTCRay>& rays, bool occlusion, bool packets, int threads,
                   RayResults& out, double* cpu) {
  return parallelFor(
      rays.size(), threads,
      [&](std::size_t lo, std::size_t hi, int) {
        RTCIntersectContext ctx;
        rtcInitIntersectContext(&ctx);
        if (packets) {
          for (std::size_t i = lo; i < hi; i += 4) {
            const int n = int(std::min<std::size_t>(4, hi - i));
            alignas(16) int valid[4] = {0, 0, 0, 0};
            alignas(16) RTCRay4 r;
            for (int k = 0; k < 4; ++k) {
              const RTCRay& e = rays[i + std::size_t(std::min(k, n - 1))];
              valid[k] = k < n ? -1 : 0;
              r.org_x[k] = e.org_x, r.org_y[k] = e.org_y, r.org_z[k] = e.org_z;
              r.dir_x[k] = e.dir_x, r.dir_y[k] = e.dir_y, r.dir_z[k] = e.dir_z;
              r.tnear[k] = e.tnear, r.tfar[k] = e.tfar, r.time[k] = e.time;
              r.mask[k] = e.mask, r.id[k] = e.id, r.flags[k] = e.flags;
            }
            if (occlusion) {
              rtcOccluded4(valid, scene, &ctx, &r);
              for (int k = 0; k < n; ++k) out.hit[i + std::size_t(k)] = r.tfar[k] < 0.0f;
            } else {
              alignas(16) RTCRayHit4 rh;
              rh.ray = r;
              for (int k = 0; k < 4; ++k) {
                rh.hit.geomID[k] = RTC_INVALID_GEOMETRY_ID;
                rh.hit.instID[0][k] = RTC_INVALID_GEOMETRY_ID;
              }
              rtcIntersect4(valid, scene, &ctx, &rh);
              for (int k = 0; k < n; ++k) {
                const std::size_t j = i + std::size_t(k);
                out.hit[j] = rh.hit.geomID[k] != RTC_INVALID_GEOMETRY_ID;
                out.geom[j] = rh.hit.geomID[k];
                out.prim[j] = rh.hit.primID[k];
                out.t[j] = rh.ray.tfar[k];
              }
            }
          }
          return;
        }
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

}  // namespace whitted::bench
