// Private to the Integrator's source files: the light loop of VTK's local shading (Integrator::shadeLocal), the
// part of the shading of one hit (local_shading.cpp) that camera rays in blocks (Integrator::traceBlock,
// integrator.cpp) also run to record their first hits' shadow rays for a packet. Not for other callers.
// Performance note: defined in a header so that traceBlock's instance (CollectShadows: shadow rays recorded, none
// traced, no light summed) is compiled in integrator.cpp and inlined there; called out of line from
// local_shading.cpp it cost 1.1% more instructions per frame of points-small (callgrind, one thread).
#pragma once

#include "shading/integrator_private.h"

#include <algorithm>
#include <cmath>

namespace whitted {

template <bool Shadows, typename ShadowFn>
Color Integrator::shadeLocal(const SurfacePoint& sp, const Material& m, const Vec3& n, const Vec3& v, bool inside,
                             RayStats& st, Color& highlight, float& shadowCut, ShadowFn& shadows) const {
  highlight = Color(0.0f);
  // Colours as VTK's shader forms them (ambient = Ka*Ca, diffuse = Kd*Cd, specular = Ks*Cs)
  Color ca = m.ambientColor, cd = m.diffuseColor;
  if (sp.hasColor && m.colorSource != ColorSource::Material) {
    Color c(sp.color);
    if (m.colorSource != ColorSource::ScalarsDiffuse) ca = c;
    if (m.colorSource != ColorSource::ScalarsAmbient) cd = c;
  }
  Color amb = m.ambient * ca, dif = m.diffuse * cd, spe = m.specular * m.specularColor;
  if (!m.lighting) return amb + dif;
  if (inside) amb *= m.transmittance;  // ambient light reaches the inside of a transmissive object only through it

  // Leave out what cannot be seen: a surface with no diffuse and no specular term (a pure mirror or clear glass)
  // traces no shadow ray, a light of zero colour or intensity none either, and pow() runs only with a specular
  // term. The result is bit-identical: each skipped term would have added exactly 0.
  const bool wantDiffuse = maxComponent(dif) > 0.0f, wantSpecular = maxComponent(spe) > 0.0f;
  if (!wantDiffuse && !wantSpecular) return amb;
  Color diffuse(0.0f), specular(0.0f);
  for (int j = 0; j < int(lights_.size()); ++j) {
    const PreparedLight& pl = lights_[std::size_t(j)];
    const Light& light = *pl.light;
    Color lc = pl.radiance;
    LightSample ls = sampleLight(pl, sp.p);
    double att = ls.attenuation;
    double df = std::max(0.0, att * glm::dot(n, ls.toLight));
    if (!(df > 0.0)) continue;  // VTK: specular only where df > 0
    auto specularFactor = [&]() {
      if (s_.headlightShading) return std::pow(df, double(m.specularPower));
      Vec3 ld = -ls.toLight;
      Vec3 r = ld - 2.0 * glm::dot(n, ld) * n;
      // pow(0, power) is exactly 0 for power > 0: the highlight's far side costs no pow()
      const double rv = std::max(0.0, glm::dot(r, v));
      return rv > 0.0 || !(m.specularPower > 0.0f) ? att * std::pow(rv, double(m.specularPower)) : att * 0.0;
    };
    // This light's diffuse and specular terms unshadowed (what a shadow ray's truncation is charged against)
    auto unshadowed = [&]() {
      return float(df) * lc * dif + (wantSpecular ? float(specularFactor()) * lc * spe : Color(0.0f));
    };

    if constexpr (Shadows) {
      if (light.castShadows) {
        Ray sr;
        sr.origin = offsetRayOrigin(sp.p, sp.pError, sp.ng, ls.toLight);
        sr.dir = ls.toLight;
        sr.tMin = 0.0;
        // Stop just short of a point light (the light itself is not geometry)
        sr.tMax = std::isfinite(ls.distance) ? glm::length(light.position - sr.origin) * (1.0 - 1e-9) : kInfinity;
        bool cut = false;
        float stepError = 0.0f;  // the volumes' step truncation of t (with volumeStepEstimate)
        Color t = shadows(j, sr, s_.contributionThreshold, st, cut, volumeStep(&stepError));
        if constexpr (ShadowFn::kCollect) continue;
        ++st.shadow;
        if (stepError > 0.0f) {
          // What this light's diffuse and specular terms would change by with the volumes' transmittance off by
          // stepError
          shadowCut += stepError * maxComponent(unshadowed());
        }
        if (maxComponent(t) <= 0.0f) {
          // Cut by the threshold, the transmittance was below it in every channel: at most that share of this
          // light's diffuse and specular terms is missing. The tight bound traces the shadow ray again without
          // the threshold (a bound ray): exactly the transmittance share is missing, 0 if something opaque lies
          // beyond.
          if (cut) {
            const Color full = unshadowed();
            if (s_.truncationLookahead > 0) {
              ++st.boundRays;
              shadowCut += maxComponent(
                  scene_.transmittance(sr, 0.0f, &st.nodesVisited, nullptr, VolumeStep{s_.volumeStepScale}) * full);
            } else {
              shadowCut += s_.contributionThreshold * maxComponent(full);
            }
          }
          continue;
        }
        lc *= t;
      }
    }

    diffuse += float(df) * lc;
    if (wantSpecular) specular += float(specularFactor()) * lc;
  }
  highlight = spe * specular;
  return amb + dif * diffuse;
}

}  // namespace whitted
