// The Integrator's private types shared by its three source files: integrator.cpp (the Whitted recursion and camera
// rays), local_shading.cpp (the shading of one hit) and truncation_bound.cpp (the bound on what the depth cap and
// the threshold cut). Not for other callers.
#pragma once

#include "shading/integrator.h"

#include <cmath>
#include <type_traits>

namespace whitted {

/// The shading frame at a hit (radiance's first step, also taken ahead for a block's first hits).
struct Integrator::HitFrame {
  SurfacePoint sp;
  Vec3 d, nf, ngf, v;  ///< Ray direction (unit); shading and geometric normals facing the ray; view vector.
  bool backFace = false;
  double pathHere = 0.0;           ///< Path length to the hit (edge footprints).
  const Material* base = nullptr;  ///< The hit's material (the back material on back faces).
  bool onEdge = false;             ///< Within an edge: edge holds the edge material.
  // Constructed only on edge pixels. Performance note: a union, not std::optional, whose storage the compiler
  // zero-fills at every hit (Material is trivially destructible, so nothing needs to end its life)
  union EdgeSlot {
    EdgeSlot() {}
    Material m;
  } edge;
  const Material& material() const { return onEdge ? edge.m : *base; }
};
static_assert(std::is_trivially_destructible_v<Material>, "HitFrame keeps an edge material in a union");

/// A camera ray's first hit and its shadow rays' answers, found ahead for a block (traceBlock).
struct Integrator::FirstHit {
  bool found = false;
  Hit hit;
  HitFrame frame;
  unsigned lights = 0;  ///< Bit j: shadow ray j recorded (ray[j]) and answered (t[j], cut[j]).
  // Performance note: the arrays in a union, left unconstructed (Ray's members have initialisers): a block would
  // otherwise write ~1 KB per camera ray before it is used
  union Slots {
    Slots() {}
    struct {
      Ray ray[kPacketLights];
      Color t[kPacketLights];
      bool cut[kPacketLights];
    } s;
  } slots;
  Ray& ray(int j) { return slots.s.ray[j]; }
  Color& t(int j) { return slots.s.t[j]; }
  bool& cut(int j) { return slots.s.cut[j]; }
  const Color& t(int j) const { return slots.s.t[j]; }
  bool cut(int j) const { return slots.s.cut[j]; }
};

/// Shadow rays answered by the packets (lights beyond those recorded traced one by one).
struct Integrator::AnsweredShadows {
  static constexpr bool kCollect = false;
  const Scene& scene;
  const FirstHit& fh;
  Color operator()(int light, const Ray& sr, float cutoff, RayStats& st, bool& cut, VolumeStep vs) const {
    if (light < kPacketLights && (fh.lights >> light & 1)) {  // (packets: scenes without volumes)
      cut = fh.cut(light);
      return fh.t(light);
    }
    return scene.transmittance(sr, cutoff, &st.nodesVisited, &cut, vs);
  }
};

/// Shadow rays traced one by one (Scene::transmittance).
struct Integrator::TraceShadows {
  static constexpr bool kCollect = false;
  const Scene& scene;
  Color operator()(int /*light*/, const Ray& sr, float cutoff, RayStats& st, bool& cut, VolumeStep vs) const {
    return scene.transmittance(sr, cutoff, &st.nodesVisited, &cut, vs);
  }
};

/// Shadow rays of a bound ray's hit, traced without the threshold: the exact transmittance the reference sees
/// (volumes at the level's step, without the step's estimate).
struct Integrator::ExactShadows {
  static constexpr bool kCollect = false;
  const Scene& scene;
  Color operator()(int /*light*/, const Ray& sr, float /*cutoff*/, RayStats& st, bool& cut, VolumeStep vs) const {
    return scene.transmittance(sr, 0.0f, &st.nodesVisited, &cut, VolumeStep{vs.scale, nullptr});
  }
};

// Beer-Lambert: what a refracted ray brings back after t units inside the medium of m. In double, and only where
// there is absorption: a path longer than float's range must give exp(-inf) = 0, and no absorption must give 1, not
// 0 x inf
inline void absorb(Color& c, const Material& m, double t) {
  for (int i = 0; i < 3; ++i)
    if (m.absorption[i] > 0.0f) c[i] *= float(std::exp(-double(m.absorption[i]) * t));
}

// Sample::firstHitSlack of a first hit at t on ray with surface point sp: sp.p's error bound, its distance from the
// ray's point at t, and that point's rounding (a few ulps of |origin| + |t dir|)
inline float firstHitSlack(const Ray& ray, double t, const SurfacePoint& sp) {
  const Vec3 onRay = ray.origin + t * ray.dir;
  const double rounding = gammaBound(3) * (glm::length(ray.origin) + std::abs(t) * glm::length(ray.dir));
  return float(glm::length(sp.pError) + glm::length(sp.p - onRay) + rounding);
}

}  // namespace whitted

/// Calls M(Reflect, Refract, Shadows) for the eight kernel variants (explicit instantiations across the files).
#define WHITTED_EACH_KERNEL(M) \
  M(false, false, false)       \
  M(false, false, true)        \
  M(false, true, false)        \
  M(false, true, true)         \
  M(true, false, false)        \
  M(true, false, true)         \
  M(true, true, false)         \
  M(true, true, true)
