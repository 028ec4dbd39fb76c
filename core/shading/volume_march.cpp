// Volumes in the Whitted recursion: every ray of a scene with volumes (camera, reflected, refracted) first finds its
// surface hit, then accumulates the emission-absorption of the volumes in front of it (Scene::marchVolumes, front to
// back), and sees the hit, or its escape, at the weight the volumes let through. Shadow rays multiply the volumes'
// transmittance in Scene::transmittance. Scenes without volumes run kernels without any of this (Features::volumes).
#include "shading/integrator_private.h"

#include <algorithm>

namespace whitted {

template <bool Reflect, bool Refract, bool Shadows>
Color Integrator::throughVolumes(const Ray& ray, int depth, const Color& weight, bool straight, RayStats& st,
                                 PathState& ps, double* tHit, Vec3* firstHit) const {
  // The first surface hit bounds the march: surfaces inside a volume hide what lies behind them
  FirstHit fh;
  fh.found = scene_.intersect(ray, fh.hit, &st.nodesVisited);
  fh.lights = 0;  // shadow rays traced by radiance (through Scene::transmittance, volumes included)
  if (fh.found) frameHit(ray, fh.hit, depth, ps, fh.frame);

  // Early ray termination where what the ray could still add falls below the contribution threshold, as for cut
  // secondary rays
  const float wmax = maxComponent(weight);
  const float stopBelow = wmax > 0.0f ? s_.contributionThreshold / wmax : 0.0f;
  const double tEnd = fh.found ? fh.hit.t : ray.tMax;
  VolumeMarch vm;
  scene_.marchVolumes(ray, tEnd, true, stopBelow, vm, s_.volumeStepScale);
  st.volumeSamples += vm.samples;
  st.volumeInvalidSamples += vm.invalidSamples;
  const float T = vm.transmittance;
  // The step truncation's estimate (IntegratorSettings::volumeStepEstimate): the same march at twice the step,
  // composited over what lies behind as the march is (below)
  VolumeMarch coarse;
  const bool estimate = s_.volumeStepEstimate && vm.samples > 0;
  if (estimate) {
    scene_.marchVolumes(ray, tEnd, true, stopBelow, coarse, s_.volumeStepScale, true);
    st.volumeEstimateSamples += coarse.samples;
  }
  const Color dC = coarse.color - vm.color;
  const float dT = coarse.transmittance - T;
  if (vm.terminated) {
    // Left out: the rest of the volumes (colours at most 1) and what lies behind them, at most T x the bound on a
    // ray at this depth
    ++st.volumeTerminated;
    // (the estimate: the colours' difference and the transmittances' times what lies behind, which is at most
    // the bound: the larger of the two ends of that range)
    const float bound = std::max(1.0f, remainingBound(depth));
    ps.truncation += wmax * T * bound;
    if (estimate) ps.truncation += wmax * maxComponent(glm::max(glm::abs(dC), glm::abs(dC + dT * bound)));
    if (fh.found) {
      if (tHit) *tHit = fh.hit.t;
      if (firstHit) {
        *firstHit = fh.frame.sp.p;
        ps.firstHitSlack = firstHitSlack(ray, fh.hit.t, fh.frame.sp);
      }
    }
    return vm.color;
  }
  const Color behind =
      radiance<Reflect, Refract, Shadows, true>(ray, depth, weight * T, straight, st, ps, tHit, firstHit, &fh);
  if (estimate) ps.truncation += wmax * maxComponent(glm::abs(dC + dT * behind));
  return vm.color + T * behind;
}

#define WHITTED_THROUGH_VOLUMES(R, F, S)                                                                            \
  template Color Integrator::throughVolumes<R, F, S>(const Ray&, int, const Color&, bool, RayStats&, PathState&, \
                                                     double*, Vec3*) const;
WHITTED_EACH_KERNEL(WHITTED_THROUGH_VOLUMES)
#undef WHITTED_THROUGH_VOLUMES

}  // namespace whitted
