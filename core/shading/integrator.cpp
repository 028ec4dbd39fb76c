// The Whitted recursion: the kernels (radiance: a hit's local term plus kr x reflected + kt x refracted, cut by depth
// and by contribution), the secondary rays with Fresnel and total internal reflection, and camera rays one by one or
// in blocks whose first hits and shadow rays go as packets. The shading of one hit is in local_shading.cpp and .h.
#include "shading/local_shading.h"

#include <algorithm>

namespace whitted {

Integrator::Integrator(const Scene& scene, const IntegratorSettings& settings, const Vec3& cameraUp)
    : scene_(scene), s_(settings), up_(cameraUp) {
  // A light of zero colour or intensity adds nothing (and traces no shadow ray): left out here
  for (const Light& l : scene.lights()) {
    PreparedLight pl = prepareLight(l);
    if (maxComponent(pl.radiance) > 0.0f) lights_.push_back(pl);
  }
  s_.maxDepth = std::max(0, s_.maxDepth);
  extraLevels_ = s_.truncationLookahead > 0 && s_.truncationTolerance > 0.0f
                     ? std::max(0, s_.truncationLookaheadMax - s_.truncationLookahead)
                     : 0;
  if (!(s_.contributionThreshold >= 0.0f)) s_.contributionThreshold = 0.0f;
  const Features& f = scene.features();
  // Leave out what the scene cannot use: each flag removes a whole mechanism from the compiled kernel
  refract_ = f.transmissive && s_.maxDepth > 0;
  reflect_ = s_.reflections && s_.maxDepth > 0 && (f.reflective || (f.transmissive && s_.refractions));
  shadows_ = s_.shadows && f.shadowLights;
  volumes_ = f.volumes;
  static constexpr Kernel table[16] = {
      &Integrator::radiance<false, false, false, false>, &Integrator::radiance<false, false, true, false>,
      &Integrator::radiance<false, true, false, false>,  &Integrator::radiance<false, true, true, false>,
      &Integrator::radiance<true, false, false, false>,  &Integrator::radiance<true, false, true, false>,
      &Integrator::radiance<true, true, false, false>,   &Integrator::radiance<true, true, true, false>,
      &Integrator::radiance<false, false, false, true>,  &Integrator::radiance<false, false, true, true>,
      &Integrator::radiance<false, true, false, true>,   &Integrator::radiance<false, true, true, true>,
      &Integrator::radiance<true, false, false, true>,   &Integrator::radiance<true, false, true, true>,
      &Integrator::radiance<true, true, false, true>,    &Integrator::radiance<true, true, true, true>};
  kernel_ = table[(volumes_ ? 8 : 0) | (reflect_ ? 4 : 0) | (refract_ ? 2 : 0) | (shadows_ ? 1 : 0)];
  // maxDepth 0 leaves the secondary machinery out, yet the reference would trace it: each hit's kr + kt is cut
  cutAtDepthZero_ = s_.maxDepth == 0 && (f.transmissive || (s_.reflections && f.reflective));
  s_.truncationReferenceDepth = std::max(0, s_.truncationReferenceDepth);
  buildRemainingBounds();
}

/// Shadow rays only recorded (the first kPacketLights lights), for a packet.
struct Integrator::CollectShadows {
  static constexpr bool kCollect = true;
  FirstHit& fh;
  Color operator()(int light, const Ray& sr, float, RayStats&, bool&, VolumeStep) const {
    if (light < kPacketLights) {
      fh.ray(light) = sr;
      fh.lights |= 1u << light;
    }
    return Color(1.0f);
  }
};

void Integrator::startPath(const Ray& ray, const Color& screenBackground, PathState& ps) const {
  ps.screenBackground = screenBackground;
  // Edge footprints grow with the distance from the eye; camera rays may start on the near plane
  if (s_.pixelAngle > 0.0) ps.pathLength = glm::length(ray.origin - s_.eye);
}

Sample Integrator::trace(const Ray& ray, RayStats& stats, const Color& screenBackground) const {
  ++stats.primary;
  double tHit = kInfinity;
  Vec3 first(0.0);
  PathState ps;
  startPath(ray, screenBackground, ps);
  const Color c = (this->*kernel_)(ray, 0, Color(1.0f), true, stats, ps, &tHit, &first, nullptr);
  return finishPath(c, tHit, first, ps, stats);
}

void Integrator::traceBlock(const Ray* rays, int n, RayStats* stats, const Color* screenBackground, Sample* out,
                            unsigned* misses) const {
  if (misses) *misses = 0;
  // Scenes with transmissive surfaces trace single shadow rays: there a packet's blocked rays go again through
  // transmittance() (Scene::occludedPacket), which made the classic scene's frame 6% slower
  // (and closest-hit packets for the first hits without shadow packets beside them measured 0.76-1.00x there)
  const bool shadowPackets = s_.packets && shadows_ && !scene_.features().transmissive;
  const bool primaryPackets = s_.primaryPackets && !scene_.features().transmissive;
  // Volumes: every camera ray marches them before its first hit is shaded (throughVolumes), one by one
  if ((!shadowPackets && !primaryPackets) || n < 2 || volumes_) {
    for (int i = 0; i < n; ++i) out[i] = trace(rays[i], stats[i], screenBackground[i]);
    return;
  }
  // First hits (one packet, or ray by ray) and their shadow rays (recorded by shadeLocal's own gating, so the same
  // rays trace() casts)
  FirstHit fh[kBlock];
  PathState ps[kBlock];
  unsigned found = 0;
  if (primaryPackets) {
    Hit hits[kBlock];
    found = scene_.intersectPacket(rays, (1u << n) - 1u, hits, &stats[0].nodesVisited);
    for (int i = 0; i < n; ++i) fh[i].hit = hits[i];
  }
  for (int i = 0; i < n; ++i) {
    ++stats[i].primary;
    startPath(rays[i], screenBackground[i], ps[i]);
    if (primaryPackets)
      fh[i].found = found >> i & 1;
    else
      fh[i].found = scene_.intersect(rays[i], fh[i].hit, &stats[i].nodesVisited);
    if (!fh[i].found) continue;
    HitFrame& f = fh[i].frame;
    frameHit(rays[i], fh[i].hit, 0, ps[i], f);
    if (!shadows_) continue;
    const Material& m = f.material();
    const bool inside = f.backFace && maxComponent(m.transmittance) > 0.0f;
    Color highlight;
    float shadowCut = 0.0f;
    CollectShadows collect{fh[i]};
    shadeLocal<true>(f.sp, m, f.nf, f.v, inside, stats[i], highlight, shadowCut, collect);
  }
  // Per light, the block's shadow rays as one packet; rays the packet cannot answer bit for bit are traced alone
  for (int j = 0; j < std::min(kPacketLights, int(lights_.size())); ++j) {
    unsigned active = 0;
    Ray packet[kBlock];
    for (int i = 0; i < n; ++i)
      if (fh[i].lights >> j & 1) {
        packet[i] = fh[i].ray(j);
        active |= 1u << i;
      }
    if (active == 0) continue;
    unsigned blocked = 0, single = active;
    if (shadowPackets && (active & (active - 1)))
      single = scene_.occludedPacket(packet, active, blocked, &stats[0].nodesVisited);
    for (unsigned m = active; m; m &= m - 1) {
      const int i = __builtin_ctz(m);
      fh[i].cut(j) = false;
      if (single >> i & 1)
        fh[i].t(j) = scene_.transmittance(packet[i], s_.contributionThreshold, &stats[i].nodesVisited, &fh[i].cut(j));
      else
        fh[i].t(j) = Color(blocked >> i & 1 ? 0.0f : 1.0f);
    }
  }
  // Shading and everything after the first hit, per ray; a camera ray that hit nothing is the kernel's straight
  // escape at weight 1 (missSample: the same operations, without the kernel's call)
  for (int i = 0; i < n; ++i) {
    if (!fh[i].found) {
      if (misses)
        *misses |= 1u << i;
      else
        out[i] = missSample(screenBackground[i], stats[i]);
      continue;
    }
    double tHit = kInfinity;
    Vec3 first(0.0);
    const Color c = (this->*kernel_)(rays[i], 0, Color(1.0f), true, stats[i], ps[i], &tHit, &first, &fh[i]);
    out[i] = finishPath(c, tHit, first, ps[i], stats[i]);
  }
}

Sample Integrator::missSample(const Color& screenBackground, RayStats& stats) const {
  PathState ps;
  ps.screenBackground = screenBackground;  // (startPath's pathLength is for hits only)
  const Color c = straightEscape(Color(1.0f), ps);
  return finishPath(c, kInfinity, Vec3(0.0), ps, stats);
}

Color Integrator::straightEscape(const Color& weight, PathState& ps) const {
  // Along the camera ray's line: what lies behind the pixel on screen. The background contributes in proportion to
  // its alpha; the rest is left to what is drawn behind, through the pixel's alpha.
  float a = scene_.backgroundAlpha;
  ps.escaped += (weight.x + weight.y + weight.z) / 3.0f * (1.0f - a);
  return a * ps.screenBackground;
}

Sample Integrator::finishPath(const Color& color, double tHit, const Vec3& first, const PathState& ps,
                              RayStats& stats) const {
  Sample out;
  out.color = color;
  out.hit = std::isfinite(tHit);
  out.firstHit = first;
  out.firstHitSlack = ps.firstHitSlack;
  out.truncationBound = ps.truncation;

  // Safety nets, counted so that tests can assert they caught nothing: coverage outside [0, 1] (beyond rounding)
  // and non-finite values never reach a pixel
  float alpha = 1.0f - ps.escaped;
  if (alpha < -1e-5f || alpha > 1.0f + 1e-5f) ++stats.clampedAlpha;
  out.alpha = std::clamp(alpha, 0.0f, 1.0f);
  bool finite = std::isfinite(alpha);
  for (int i = 0; i < 3; ++i)
    if (!std::isfinite(out.color[i])) {
      out.color[i] = 0.0f;
      finite = false;
    }
  if (!finite) {
    out.alpha = std::isfinite(alpha) ? out.alpha : 1.0f;
    ++stats.nonFiniteSamples;
  }
  return out;
}

double fresnelDielectric(double cosi, double cost, double eta) {
  // eta = n_incident / n_transmitted; cosines of the incident and transmitted angles (both >= 0)
  const double rs = (eta * cosi - cost) / (eta * cosi + cost);
  const double rp = (eta * cost - cosi) / (eta * cost + cosi);
  const double f = 0.5 * (rs * rs + rp * rp);
  return std::isfinite(f) ? std::clamp(f, 0.0, 1.0) : 1.0;  // 0/0 only at exactly grazing incidence: reflects
}

template <bool Reflect, bool Refract>
void Integrator::secondaryRays(const HitFrame& f, SecondaryRays& out) const {
  const Material& m = f.material();
  const SurfacePoint& sp = f.sp;
  const Vec3 &d = f.d, &nf = f.nf, &ngf = f.ngf;
  Color& kr = out.kr;
  Color& kt = out.kt;
  kr = m.reflectance;
  kt = m.transmittance;
  out.haveReflected = out.haveRefracted = out.refractedStraight = false;

  if constexpr (Refract) {
    if (maxComponent(kt) > 0.0f) {
      Vec3 tdir = d;
      out.refractedStraight = true;
      if (s_.refractions && m.ior != 1.0f) {
        // Snell's law; entering vs exiting from the geometric normal
        bool entering = !f.backFace;
        double eta = entering ? 1.0 / m.ior : double(m.ior);
        Vec3 n = glm::dot(nf, ngf) > 0.0 ? nf : ngf;
        double cosi = std::min(1.0, std::max(0.0, -glm::dot(d, n)));
        double sin2t = eta * eta * (1.0 - cosi * cosi);
        out.refractedStraight = false;
        if (sin2t >= 1.0) {
          kr += kt;  // total internal reflection: the refracted share goes to the reflected ray
          kt = Color(0.0f);
        } else {
          double cost = std::sqrt(1.0 - sin2t);
          tdir = eta * d + (eta * cosi - cost) * n;
          if (glm::dot(tdir, ngf) >= 0.0) tdir = eta * d + (eta * glm::dot(-d, ngf) - cost) * ngf;
          if constexpr (Reflect) {
            if (s_.fresnel) {
              // Exact unpolarised dielectric Fresnel reflectance: 0 without an interface (IOR 1, not reached
              // here), ((n-1)/(n+1))^2 at normal incidence, 1 at grazing. Only with a reflected ray to take the
              // share: with reflections off, nothing is moved and nothing is lost.
              float fr = float(fresnelDielectric(cosi, cost, eta));
              kr += kt * fr;
              kt *= 1.0f - fr;
            }
          }
        }
      }
      if (maxComponent(kt) > 0.0f) {
        out.refracted.dir = out.refractedStraight ? d : glm::normalize(tdir);
        out.refracted.origin = offsetRayOrigin(sp.p, sp.pError, sp.ng, out.refracted.dir);
        out.haveRefracted = true;
      }
    }
  }
  if constexpr (Reflect) {
    if (maxComponent(kr) > 0.0f) {
      Vec3& r = out.reflected.dir;
      r = glm::normalize(d - 2.0 * glm::dot(d, nf) * nf);
      if (glm::dot(r, ngf) <= 0.0) r = glm::normalize(d - 2.0 * glm::dot(d, ngf) * ngf);
      out.reflected.origin = offsetRayOrigin(sp.p, sp.pError, sp.ng, r);
      out.haveReflected = true;
    }
  }
}

// The instances the truncation bound (truncation_bound.cpp) calls: the secondary rays of every kernel that can cut
// them
template void Integrator::secondaryRays<true, true>(const HitFrame&, SecondaryRays&) const;
template void Integrator::secondaryRays<true, false>(const HitFrame&, SecondaryRays&) const;
template void Integrator::secondaryRays<false, true>(const HitFrame&, SecondaryRays&) const;

template <bool Reflect, bool Refract, bool Shadows, bool Volumes>
Color Integrator::radiance(const Ray& ray, int depth, Color weight, bool straight, RayStats& st, PathState& ps,
                           double* tHit, Vec3* firstHit, const FirstHit* pre) const {
  if constexpr (Volumes) {
    if (!pre) return throughVolumes<Reflect, Refract, Shadows>(ray, depth, weight, straight, st, ps, tHit, firstHit);
  }
  Hit hit;
  if (pre ? !pre->found : !scene_.intersect(ray, hit, &st.nodesVisited)) {
    if (straight) return straightEscape(weight, ps);
    // Reflected or bent: the environment in the ray's direction, an opaque colour contribution
    return scene_.environment(ray.dir, up_);
  }
  HitFrame own;
  if (pre) hit = pre->hit;
  else frameHit(ray, hit, depth, ps, own);
  const HitFrame& f = pre ? pre->frame : own;
  if (tHit) *tHit = hit.t;
  if (firstHit) {
    *firstHit = f.sp.p;
    ps.firstHitSlack = firstHitSlack(ray, hit.t, f.sp);
  }
  const Material& m = f.material();

  Color result;
  if (pre) {
    AnsweredShadows answered{scene_, *pre};
    result = localTerm<Shadows>(f, weight, st, ps, answered);
  } else {
    TraceShadows traced{scene_};
    result = localTerm<Shadows>(f, weight, st, ps, traced);
  }
  if constexpr (!Reflect && !Refract) {
    if (cutAtDepthZero_) {
      const Color k = s_.reflections ? m.reflectance + m.transmittance : m.transmittance;
      ps.truncation += maxComponent(weight * k) * remainingBound(1);
    }
  }

  if constexpr (Reflect || Refract) {
    const bool backFace = f.backFace;
    const double pathHere = f.pathHere;
    SecondaryRays sec;
    secondaryRays<Reflect, Refract>(f, sec);
    auto spawn = [&](const Ray& r, const Color& k, uint64_t& counter, bool refractedRay) {
      Color w = weight * k;
      float wmax = maxComponent(w);
      if (wmax <= 0.0f) return;
      const bool rayStraight = straight && refractedRay && sec.refractedStraight;
      const bool cutByDepth = depth >= s_.maxDepth;
      if (cutByDepth || wmax < s_.contributionThreshold) {
        ++(cutByDepth ? st.savedByDepth : st.savedByThreshold);
        if (s_.truncationLookahead <= 0) {
          ps.truncation += wmax * remainingBound(depth + 1);
          return;
        }
        double t = kInfinity;
        ps.boundRaysLeft = s_.truncationBoundRays;
        ps.boundRaysCapped = false;
        Color bound = cutRayBound<Reflect, Refract>(r, depth + 1, s_.truncationLookahead, extraLevels_, w, rayStraight,
                                                    pathHere, st, ps, &t, kCutRay);
        // Bound rays find the first hit only; volumes on the way emit at most 1 - T and let T of the rest through
        if constexpr (Volumes) bound = glm::max(bound, Color(1.0f));
        if (refractedRay && s_.beerLambert && !backFace && std::isfinite(t)) absorb(bound, m, t);
        ps.truncation += maxComponent(w * bound);
        return;
      }
      ++counter;
      double t = kInfinity;
      const double pathBefore = ps.pathLength;
      ps.pathLength = pathHere;
      Color c =
          radiance<Reflect, Refract, Shadows, Volumes>(r, depth + 1, w, rayStraight, st, ps, &t, nullptr, nullptr);
      ps.pathLength = pathBefore;
      if (refractedRay && s_.beerLambert && !backFace && std::isfinite(t)) absorb(c, m, t);
      result += k * c;
    };

    if (sec.haveReflected) spawn(sec.reflected, sec.kr, st.reflection, false);
    if (sec.haveRefracted) spawn(sec.refracted, sec.kt, st.refraction, true);
  }
  return result;
}

// The kernels throughVolumes (volume_march.cpp) calls with its own first hit
#define WHITTED_VOLUME_KERNEL(R, F, S)                                                                            \
  template Color Integrator::radiance<R, F, S, true>(const Ray&, int, Color, bool, RayStats&, PathState&, double*, \
                                                     Vec3*, const FirstHit*) const;
WHITTED_EACH_KERNEL(WHITTED_VOLUME_KERNEL)
#undef WHITTED_VOLUME_KERNEL

}  // namespace whitted
