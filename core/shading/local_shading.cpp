// Local shading of one hit (VTK's Phong/Blinn shading, as its shaders compute it): the hit's shading frame
// (oriented normals, view vector, back and edge materials) and the local term as VTK blends it (opacity, texture,
// clamping, the body share of the energy rule) around the light loop with its shadow rays (shadeLocal, in
// local_shading.h). The Whitted recursion around it (reflection, refraction, the kernels, camera rays in blocks) is
// in integrator.cpp.
#include "shading/local_shading.h"

#include <algorithm>
#include <new>

namespace whitted {

void Integrator::frameHit(const Ray& ray, const Hit& hit, int depth, const PathState& ps, HitFrame& f) const {
  f.sp = scene_.surface(ray, hit);
  const SurfacePoint& sp = f.sp;

  // Orient normals toward the incoming ray (VTK flips normals of back faces)
  f.d = glm::normalize(ray.dir);
  f.backFace = glm::dot(sp.ng, f.d) > 0.0;
  f.nf = f.backFace ? -sp.ns : sp.ns;
  f.ngf = f.backFace ? -sp.ng : sp.ng;
  f.v = (depth == 0 && s_.viewFromEye) ? glm::normalize(s_.eye - sp.p) : -f.d;

  // The material: the back material on back faces (VTK's BackfaceProperty), the edge material within half the
  // edge width of a drawn edge (lit as VTK lights lines over a surface: facing the viewer)
  const Material* mp = &scene_.material(sp.material);
  if (f.backFace && mp->backMaterial >= 0) mp = &scene_.material(uint32_t(mp->backMaterial));
  f.base = mp;
  f.onEdge = false;
  f.pathHere = scene_.features().edges ? ps.pathLength + hit.t * glm::length(ray.dir) : 0.0;
  if (scene_.features().edges && mp->edgeWidth > 0.0f) {
    const double halfWidth = 0.5 * double(mp->edgeWidth) * (s_.pixelSize + s_.pixelAngle * f.pathHere);
    if (halfWidth > 0.0 && scene_.edgeDistance(ray, hit, sp.p) <= halfWidth) {
      new (&f.edge.m) Material(edgeMaterial(*mp));
      f.onEdge = true;
      f.nf = f.v;
    }
  }
}

template <bool Shadows, typename ShadowFn>
Color Integrator::localTerm(const HitFrame& f, const Color& weight, RayStats& st, PathState& ps,
                            ShadowFn& shadows) const {
  const SurfacePoint& sp = f.sp;
  const Material& m = f.material();
  // Local shading, weighted by opacity as VTK blends it
  float opacity = m.opacity * (sp.hasColor && m.colorSource != ColorSource::Material ? sp.color.a : 1.0f);
  // Inside-ness is a property of the material, not of the kernel: an opaque back face keeps its ambient term
  // whether or not the scene holds a transmissive actor elsewhere
  const bool inside = f.backFace && maxComponent(m.transmittance) > 0.0f;
  Color highlight;
  float shadowCut = 0.0f;
  const Color body = shadeLocal<Shadows>(sp, m, f.nf, f.v, inside, st, highlight, shadowCut, shadows);
  // Light the threshold cut from shadow rays: clamping, the body share and the texture factor (<= 1) can only
  // shrink it
  if (shadowCut > 0.0f) ps.truncation += maxComponent(weight) * opacity * shadowCut;
  Color texel(1.0f);
  if (scene_.features().textures && m.texture >= 0 && sp.hasUV) {
    Color4 tc = scene_.texture(uint32_t(m.texture)).sample(sp.uv.x, sp.uv.y);
    texel = Color(tc);
    opacity *= tc.a;
  }
  // The energy rule (bodyWeight): the body colour keeps the share of the opacity that reflection and transmission
  // leave, the highlight the whole opacity. VTK's shader writes each surface's colour clamped to [0, 1] before
  // blending it: so does the local term here, so a translucent surface over a highlight blends as VTK's image
  // does, and a body share applies to the body colour as VTK would write it (clamped: an over-lit body cannot
  // exceed its share). bodyShare is exactly 1 for VTK's translucency (x / x): that case computes VTK's blend.
  const Color zero(0.0f), one(1.0f);
  const float bw = bodyWeight(m, opacity);
  const float bodyShare = bw < opacity ? bw / opacity : 1.0f;
  Color local = bodyShare == 1.0f ? (body + highlight) * texel
                                  : bodyShare * glm::clamp(body * texel, zero, one) + highlight * texel;
  return opacity * glm::clamp(local, zero, one);
}

// The instances the integrator's kernels (integrator.cpp: a hit traced by radiance() or answered by a block's
// packets) and the truncation bound (truncation_bound.cpp: a bound ray's hit, unshadowed or with exact shadow rays)
// call
template Color Integrator::localTerm<false>(const HitFrame&, const Color&, RayStats&, PathState&, TraceShadows&) const;
template Color Integrator::localTerm<true>(const HitFrame&, const Color&, RayStats&, PathState&, TraceShadows&) const;
template Color Integrator::localTerm<false>(const HitFrame&, const Color&, RayStats&, PathState&,
                                            AnsweredShadows&) const;
template Color Integrator::localTerm<true>(const HitFrame&, const Color&, RayStats&, PathState&,
                                           AnsweredShadows&) const;
template Color Integrator::localTerm<true>(const HitFrame&, const Color&, RayStats&, PathState&, ExactShadows&) const;

}  // namespace whitted
