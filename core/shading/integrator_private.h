// The Integrator's private types shared by its two source files: integrator.cpp (tracing and shading) and
// truncation_bound.cpp (the bound on what the depth cap and the threshold cut). Not for other callers.
#pragma once

#include "shading/integrator.h"

#include <cmath>

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

/// Shadow rays traced one by one (Scene::transmittance).
struct Integrator::TraceShadows {
  static constexpr bool kCollect = false;
  const Scene& scene;
  Color operator()(int /*light*/, const Ray& sr, float cutoff, RayStats& st, bool& cut) const {
    return scene.transmittance(sr, cutoff, &st.nodesVisited, &cut);
  }
};

/// Shadow rays of a bound ray's hit, traced without the threshold: the exact transmittance the reference sees.
struct Integrator::ExactShadows {
  static constexpr bool kCollect = false;
  const Scene& scene;
  Color operator()(int /*light*/, const Ray& sr, float /*cutoff*/, RayStats& st, bool& cut) const {
    return scene.transmittance(sr, 0.0f, &st.nodesVisited, &cut);
  }
};

// Beer-Lambert: what a refracted ray brings back after t units inside the medium of m. In double, and only where
// there is absorption: a path longer than float's range must give exp(-inf) = 0, and no absorption must give 1, not
// 0 x inf
inline void absorb(Color& c, const Material& m, double t) {
  for (int i = 0; i < 3; ++i)
    if (m.absorption[i] > 0.0f) c[i] *= float(std::exp(-double(m.absorption[i]) * t));
}

}  // namespace whitted
