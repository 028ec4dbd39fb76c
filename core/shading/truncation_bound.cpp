// The truncation bound (Sample::truncationBound): what the depth cap and the contribution threshold left out of a
// sample. buildRemainingBounds gives, once per frame, the scene-wide bound on what a ray with n further levels of
// recursion can return; cutRayBound, with IntegratorSettings::truncationLookahead, traces a cut ray to its first
// hit (and further levels where the charge is large) for a tighter one. The integrator (integrator.cpp) charges
// each cut ray with them.
#include "shading/integrator_private.h"

#include <algorithm>

namespace whitted {

void Integrator::buildRemainingBounds() {
  // What an escaping ray can see: the background behind the pixel (solid or gradient) or, bent or reflected, the
  // environment in its direction (an image's texels are <= 1, else the background colours)
  float escape = std::max(maxComponent(scene_.background),
                          scene_.gradientBackground ? maxComponent(scene_.background2) : 0.0f);
  if (scene_.environmentMap.projection != EnvironmentMap::Projection::None) escape = std::max(escape, 1.0f);
  // Volumes emit at most 1 - T in front of what a ray sees and let T of it through: at most max(1, that)
  if (volumes_) escape = std::max(escape, 1.0f);
  // Light reaching a surface: at most colour x intensity per light (distance and cone factors are <= 1)
  float lightSum = 0.0f;
  for (const Light& l : scene_.lights()) lightSum += l.intensity * maxComponent(l.color);

  // Per material, a hit returns at most a + k x (what its secondary rays return): a the local term, k the largest
  // kr + kt (Fresnel and total internal reflection move weight between them, never add any). Every material is
  // counted, visible or not: a superset only loosens the bound. The local term is opacity x the clamped sum of
  // the body colour at its share (bodyWeight / opacity, the body clamped to [0, 1]) and the highlight, so at most
  // min(opacity, bodyWeight x min(1, body) + opacity x min(1, highlight)): a hit's opacity (vertex colour and
  // texel alpha) is at most the material's, and so is its body weight; geometry colours and texels are <= 1.
  struct Term {
    float a, k;
  };
  std::vector<Term> terms;
  float aMax = 0.0f, fixedPoint = escape;
  bool diverges = false;
  for (std::size_t i = 0; i < scene_.materialCount(); ++i) {
    // A material with edges shades its edge pixels with its edge material: both count
    const Material& base = scene_.material(uint32_t(i));
    for (int variant = 0; variant < (base.edgeWidth > 0.0f ? 2 : 1); ++variant) {
      const Material m = variant ? edgeMaterial(base) : base;
      const float amb = m.ambient * std::max(1.0f, maxComponent(m.ambientColor));
      const float dif = m.diffuse * std::max(1.0f, maxComponent(m.diffuseColor));
      const float spe = m.specular * maxComponent(m.specularColor);
      const float body = m.lighting ? amb + lightSum * dif : amb + dif;
      const float highlight = m.lighting ? lightSum * spe : 0.0f;
      const float a = std::min(m.opacity, bodyWeight(m, m.opacity) * std::min(1.0f, body) +
                                              m.opacity * std::min(1.0f, highlight));
      const Term t{a, maxComponent(m.reflectance + m.transmittance)};
      terms.push_back(t);
      aMax = std::max(aMax, t.a);
      // The series B = max(escape, a + k B) has a finite fixed point unless a surface adds light (a > 0) without
      // losing weight (k >= 1): two such facing surfaces would add a at every bounce
      if (t.k < 1.0f)
        fixedPoint = std::max(fixedPoint, t.a / (1.0f - t.k));
      else if (t.a > 0.0f)
        diverges = true;
    }
  }
  seriesConverges_ = !diverges;
  if (seriesConverges_) {
    remaining_.assign(1, fixedPoint);  // bounds the infinite-depth image, so any deeper reference too
    return;
  }
  // Divergent: bound what a reference at referenceDepth_ adds, level by level (n further levels of recursion)
  referenceDepth_ = std::max(s_.maxDepth, s_.truncationReferenceDepth);
  remaining_.assign(std::size_t(referenceDepth_) + 1, 0.0f);
  remaining_[0] = std::max(escape, aMax);
  for (std::size_t n = 1; n < remaining_.size(); ++n) {
    float b = escape;
    for (const Term& t : terms) b = std::max(b, t.a + t.k * remaining_[n - 1]);
    remaining_[n] = b;
  }
}

template <bool Reflect, bool Refract>
Color Integrator::cutRayBound(const Ray& ray, int depth, int levels, int extra, const Color& weight, bool straight,
                              double pathLength, RayStats& st, PathState& ps, double* tHit, float tol) const {
  // A ray the reference itself would not trace returns nothing (see remainingBound)
  if (!seriesConverges_ && depth > referenceDepth_) return Color(0.0f);
  ++st.boundRays;
  --ps.boundRaysLeft;
  Hit hit;
  if (!scene_.intersect(ray, hit, &st.nodesVisited)) {
    // A miss returns exactly what radiance() returns for it (the straight escape's alpha is not colour)
    if (straight) return scene_.backgroundAlpha * ps.screenBackground;
    return scene_.environment(ray.dir, up_);
  }
  *tHit = hit.t;
  // A hit returns its local term plus what its own secondary rays return. Local shading without shadow rays is its
  // upper bound: a shadow ray only scales a light's terms by a transmittance in [0, 1], and the clamps and blends
  // after it are monotone. Everything else (vertex colours, textures, edges, headlight, inside ambient) is the
  // exact term radiance() computes, by the same code.
  const double pathBefore = ps.pathLength;
  ps.pathLength = pathLength;
  HitFrame f;
  frameHit(ray, hit, depth, ps, f);
  ps.pathLength = pathBefore;
  TraceShadows none{scene_};  // not called: no shadow rays
  Color bound = localTerm<false>(f, Color(0.0f), st, ps, none);
  const Material& m = f.material();
  const Color k = m.reflectance + m.transmittance;
  if (tol < 0.0f) {  // kCutRay
    // The cut ray's own tolerance: a fraction of the charge it would leave here, at most the absolute one
    const float charge = maxComponent(weight * (bound + k * remainingBound(depth + 1)));
    tol = std::min(s_.truncationTolerance, s_.truncationRelativeTolerance * charge);
    if (!(tol > 0.0f)) tol = s_.truncationTolerance;  // relative tolerance 0 (or nothing to charge)
  }
  if (shadows_ && extraLevels_ > 0 && maxComponent(weight * bound) > tol) {
    // A large charge (adaptive lookahead): the hit's shadow rays, traced without the threshold, give the local term
    // the reference computes there, never above the unshadowed one. They are bound rays, not shadow rays.
    RayStats sst;
    ExactShadows exact{scene_};
    bound = localTerm<true>(f, Color(0.0f), sst, ps, exact);
    st.boundRays += sst.shadow;
    st.nodesVisited += sst.nodesVisited;
  }
  if (levels <= 1) {
    // The secondary rays return at most the remaining bound each; total internal reflection and Fresnel move
    // weight between kr and kt per channel, never add any. The adaptive lookahead follows them instead while that
    // charge is large (the next level's charge is never above it: see buildRemainingBounds); below the absolute
    // tolerance only where a level removes at least half of the charge (truncationRelativeTolerance)
    const float remaining = remainingBound(depth + 1);
    const float levelTol = maxComponent(k) <= 0.5f ? tol : std::max(tol, s_.truncationTolerance);
    if (extra <= 0 || !(maxComponent(weight * k) * remaining > levelTol)) return bound + k * remaining;
    if (ps.boundRaysLeft <= 0) {  // the cut ray's bound rays are spent (truncationBoundRays): counted once
      if (!ps.boundRaysCapped) ++st.boundRaysCapped;
      ps.boundRaysCapped = true;
      return bound + k * remaining;
    }
    levels = 2;
    --extra;
  }
  // One more level of bound rays: the hit's secondary rays as radiance() would spawn them, each bounded in turn
  SecondaryRays sec;
  secondaryRays<Reflect, Refract>(f, sec);
  if (sec.haveReflected) {
    double t = kInfinity;
    bound += sec.kr * cutRayBound<Reflect, Refract>(sec.reflected, depth + 1, levels - 1, extra, weight * sec.kr, false,
                                                    f.pathHere, st, ps, &t, tol);
  }
  if (sec.haveRefracted) {
    double t = kInfinity;
    Color c = cutRayBound<Reflect, Refract>(sec.refracted, depth + 1, levels - 1, extra, weight * sec.kt,
                                            straight && sec.refractedStraight, f.pathHere, st, ps, &t, tol);
    if (s_.beerLambert && !f.backFace && std::isfinite(t)) absorb(c, m, t);
    bound += sec.kt * c;
  }
  return bound;
}

// The kernels that can cut secondary rays (radiance() with reflection and / or refraction)
template Color Integrator::cutRayBound<true, true>(const Ray&, int, int, int, const Color&, bool, double, RayStats&,
                                                   PathState&, double*, float) const;
template Color Integrator::cutRayBound<true, false>(const Ray&, int, int, int, const Color&, bool, double, RayStats&,
                                                    PathState&, double*, float) const;
template Color Integrator::cutRayBound<false, true>(const Ray&, int, int, int, const Color&, bool, double, RayStats&,
                                                    PathState&, double*, float) const;

}  // namespace whitted
