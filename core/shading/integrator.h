// Whitted integrator: VTK's local shading + shadow rays + kr * reflected + kt * refracted, recursion cut by depth
// and by contribution. A kernel is chosen per frame from the scene's features (reflection / refraction / shadow
// machinery compiled out when the scene cannot use it). The recursion and camera rays are in integrator.cpp, the
// local shading of one hit in local_shading.cpp (frameHit, localTerm) and local_shading.h (shadeLocal, the light
// loop), the truncation bound (buildRemainingBounds, cutRayBound) in truncation_bound.cpp.
#pragma once

#include "scene/scene.h"
#include "shading/light_sampling.h"

#include <cstdint>
#include <vector>

namespace whitted {

/// Tracing settings. Defaults are those of vtkWhittedPass (plugin/vtkWhittedSettings.h) except two the pass sets
/// per frame: beerLambert (on in the pass, where only materials with an attenuation colour below 1 absorb) and
/// truncationLookahead (0 in the pass unless TargetError or TimeBudget steer by the estimate). The per-camera
/// fields (headlightShading, viewFromEye, eye, pixelSize, pixelAngle) are the caller's.
struct IntegratorSettings {
  int maxDepth = 5;         ///< Secondary bounces per path (0 = local shading only). Default 5.
  bool shadows = true;      ///< Trace shadow rays. Default on.
  bool reflections = true;  ///< Trace mirror rays for kr > 0. Default on.
  bool refractions = true;  ///< Bend transmitted rays by the IOR (off: straight-through transmission). Default on.
  float contributionThreshold = 1.0f / 255.0f;  ///< Rays whose weight falls below this are not traced. Default 1/255.
  /// Exact (unpolarised) dielectric Fresnel moves part of kt to kr at interfaces with IOR != 1 while refraction and
  /// reflection are on (with reflection off nothing is moved, so no light is lost). Default off.
  bool fresnel = false;
  bool beerLambert = false;  ///< Absorb light inside transmissive objects by exp(-absorption * distance). Default off.
  bool headlightShading = false;  ///< VTK light complexity 1 (one headlight): specular = pow(N.L, power).
  /// VTK computes the specular view vector from the camera position even for parallel projection; set this (and
  /// eye) to do the same for camera rays. Default off: the view vector is minus the ray direction.
  bool viewFromEye = false;
  Vec3 eye{0.0};  ///< Camera position, used when viewFromEye is set and for edge footprints (pixelAngle).
  /// Depth of the reference the truncation bound is stated against when the untraced series cannot converge
  /// (some surface has kr + kt = 1 and a local colour, so every further bounce may add light): the bound then
  /// covers what a render at max(this, maxDepth) and threshold 0 would add. Where the series converges the bound
  /// holds against any depth (the infinite-depth image). Default 16.
  int truncationReferenceDepth = 16;
  /// Tight truncation bound: levels of bound rays per cut ray. Each secondary ray cut by the depth cap or the
  /// threshold is traced to its first hit only (a bound ray: no shadow rays) and charged what it returns on a miss,
  /// or that hit's unshadowed local term plus, at the last level, its kr + kt times the scene-wide remaining bound,
  /// else what the hit's own secondary rays return, bounded the same way one level further (up to 2^levels - 1
  /// bound rays per cut ray; more levels where that charge is large: truncationTolerance); a shadow ray cut by the
  /// threshold is traced again without it. 0: every cut ray is charged its weight times the scene-wide bound (no
  /// rays, looser). Colours are the same either way. Default 1 (the renderer uses 0 with
  /// RenderSettings::errorEstimates off, for interactive frames).
  int truncationLookahead = 1;
  /// Adaptive lookahead: past truncationLookahead levels, a bound ray's secondary ray is followed one more level
  /// (up to truncationLookaheadMax levels in all) while what it would otherwise be charged (its weight along the
  /// path times the kr + kt of its hit times the scene-wide remaining bound) is above this radiance. Each level
  /// followed only replaces a charge by a smaller one: the bound stays strict and never rises. A bound ray's hit
  /// whose unshadowed local term would be charged above this radiance traces its shadow rays (without the
  /// threshold: the reference's exact local term). Colours are the same either way. 0, a truncationLookaheadMax
  /// at most truncationLookahead, or truncationLookahead 0: fixed levels, unshadowed. Default 1/255 (8-bit step).
  float truncationTolerance = 1.0f / 255.0f;
  int truncationLookaheadMax = 16;  ///< Most levels of bound rays per cut ray with truncationTolerance. Default 16.
  /// Bound rays after which the adaptive lookahead adds no level for a cut ray. A cut ray's levels branch in two
  /// wherever a hit both reflects and refracts, so 16 levels could take 2^16 rays (a glass tube inside a mirror
  /// tube); once this many are traced, no further level is followed: the levels left are charged the scene-wide
  /// remaining bound (strict, looser), and RayStats::boundRaysCapped counts the cut rays that reached it. The
  /// branches already under way still trace their own ray each (at most truncationLookaheadMax more, plus their
  /// hits' shadow rays). Default 1024.
  int truncationBoundRays = 1024;
  /// Adaptive lookahead for small charges: a cut ray's tolerance is min(truncationTolerance, this x the charge its
  /// first bound ray would leave: weight x (unshadowed local term + kr + kt times the remaining bound)). Where a
  /// frame's truncation is made of many charges under truncationTolerance (deep depths, light behind glass), the
  /// absolute tolerance alone leaves each at its scene-wide charge, which can be several times what it bounds. The
  /// hit's shadow rays follow this tolerance everywhere; further levels only at surfaces with kr + kt <= 1/2,
  /// where a level removes at least half of what it replaces (clear glass and strong mirrors would need many
  /// levels per factor: there the absolute tolerance). 0: the absolute tolerance only. Default 1/8.
  float truncationRelativeTolerance = 1.0f / 8.0f;
  /// Pixel footprint for edges of a given width in pixels (Material::edgeWidth): one pixel spans
  /// pixelSize + pixelAngle x L world units across a ray at path length L from the camera (summed over the
  /// path's segments, so exact through plane mirrors, approximate after curved mirrors and refraction).
  /// Perspective camera: pixelAngle = the angle of one pixel at the image centre (radians), pixelSize 0;
  /// parallel: pixelSize = one pixel's world size, pixelAngle 0. Default 0: no edges are drawn. With pixelAngle,
  /// path lengths start at eye (camera rays may start on the near plane).
  double pixelSize = 0.0;
  double pixelAngle = 0.0;
  /// Camera rays traced in blocks (Integrator::traceBlock) cast their first hits' shadow rays as packets. The image
  /// and the ray counts are the same either way; off traces every shadow ray alone (tests, measurements).
  /// Default on.
  bool packets = true;
  /// Camera rays traced in blocks find their first hits as one closest-hit packet (Scene::intersectPacket), which
  /// shares each BVH node's load among the block's rays. The image and the ray counts are the same either way.
  /// Used where the shadow packets are, in scenes without transmissive surfaces: there it measured 1.00-1.09x per
  /// frame (iso60k, points100k, iso1m, tubes; data/benchmark/history.md), while in the classic scene, whose shadow
  /// rays go one by one, it measured 0.76-1.00x. Default on; off finds every first hit alone (tests, measurements).
  bool primaryPackets = true;
  /// Volumes are marched at their step x 2^volumeStepScale (Volume::march's stepScale; progressive refinement's
  /// looser levels halve it: -1, -2, ...). Default 0: each volume's own step.
  int volumeStepScale = 0;
  /// The step truncation's estimate: every ray that crosses a volume marches it again at twice the step, and the
  /// difference of the two results (colour, and transmittance times what lies behind; for shadow rays times the
  /// light's term) is added to the truncation part (Richardson's comparison: the midpoint rule's error at the step
  /// is about a third of that difference where the integrand is smooth, about all of it at a jump of the transfer
  /// function). About 1.5x the volume samples. Default on (the renderer turns it off with
  /// RenderSettings::errorEstimates off).
  bool volumeStepEstimate = true;
};

/// Ray counts of one frame (summed over threads).
struct RayStats {
  uint64_t primary = 0, shadow = 0, reflection = 0, refraction = 0;
  uint64_t savedByThreshold = 0;  ///< Secondary rays not traced because their weight was below the threshold.
  uint64_t savedByDepth = 0;      ///< Secondary rays not traced because the depth cap was reached.
  uint64_t nodesVisited = 0;
  /// Rays traced to the first hit only, to bound what a cut ray would have returned (truncationLookahead).
  uint64_t boundRays = 0;
  /// Cut rays whose bound rays reached IntegratorSettings::truncationBoundRays (charged the scene-wide bound for
  /// the levels left).
  uint64_t boundRaysCapped = 0;
  uint64_t volumeSamples = 0;  ///< Volume samples of camera and secondary rays' marches (shadow rays': not counted).
  /// Volume samples of the step truncation's estimate (IntegratorSettings::volumeStepEstimate), counted likewise.
  uint64_t volumeEstimateSamples = 0;
  /// Rays whose volume march stopped early (early ray termination: the ray's weight times the transmittance fell
  /// below IntegratorSettings::contributionThreshold); what lies behind is charged to the truncation bound.
  uint64_t volumeTerminated = 0;
  /// Safety net: volume samples that read a non-finite scalar and were taken as transparent. Zero for valid input.
  uint64_t volumeInvalidSamples = 0;
  /// Safety net: camera samples whose colour or alpha came out non-finite and were zeroed. Zero for valid input;
  /// tests assert that, so the net cannot hide a bug.
  uint64_t nonFiniteSamples = 0;
  /// Safety net: camera samples whose coverage (1 - escaped weight) fell outside [0, 1] by more than rounding and
  /// was clamped. Zero for valid input (kr + kt <= 1 bounds the escaped weight).
  uint64_t clampedAlpha = 0;
  /// Safety net: pixels whose first-hit depth fell outside [0, 1] (beyond rounding) and was clamped.
  uint64_t clampedDepth = 0;
  /// Safety net: pixels (sums of samples) with a non-finite component that was zeroed.
  uint64_t nonFinitePixels = 0;
  /// Field by field (inline: the frame loops add a sample's counts per camera sample, 4% of a frame's time as a
  /// call).
  RayStats& operator+=(const RayStats& o) {
    primary += o.primary;
    shadow += o.shadow;
    reflection += o.reflection;
    refraction += o.refraction;
    savedByThreshold += o.savedByThreshold;
    savedByDepth += o.savedByDepth;
    nodesVisited += o.nodesVisited;
    boundRays += o.boundRays;
    boundRaysCapped += o.boundRaysCapped;
    volumeSamples += o.volumeSamples;
    volumeEstimateSamples += o.volumeEstimateSamples;
    volumeTerminated += o.volumeTerminated;
    volumeInvalidSamples += o.volumeInvalidSamples;
    nonFiniteSamples += o.nonFiniteSamples;
    clampedAlpha += o.clampedAlpha;
    clampedDepth += o.clampedDepth;
    nonFinitePixels += o.nonFinitePixels;
    return *this;
  }
  /// Everything the per-sample and per-pixel safety nets caught (0 for valid input).
  uint64_t safetyNetCatches() const {
    return nonFiniteSamples + clampedAlpha + clampedDepth + nonFinitePixels + volumeInvalidSamples;
  }
  uint64_t traced() const { return primary + shadow + reflection + refraction; }
  /// Every ray that walked the scene (traced rays and bound rays): what a sample cost.
  uint64_t traversals() const { return traced() + boundRays; }
};
static_assert(sizeof(RayStats) == 17 * sizeof(uint64_t), "RayStats::operator+= adds every field");

/// Result of one camera ray.
///
/// What escaped rays see (the pixel contract, from tracer to screen):
/// - A ray that leaves the scene along its camera ray's line (a miss, or a path that only crossed surfaces
///   without bending: IOR 1 or refraction off) sees what lies *behind the pixel on screen*: the caller's
///   screen background colour times Scene::backgroundAlpha, and the rest (1 - backgroundAlpha) of its weight is
///   left to whatever is drawn behind, through alpha. The VTK pass uses backgroundAlpha 0, so VTK's own
///   background, gradient, textured background, lower layers or parallel compositing show through exactly as
///   VTK blends translucent geometry.
/// - Any other escaped ray (mirror-reflected, or refracted through a bending interface) sees the environment in
///   its direction (Scene::environment): a colour contribution, fully opaque.
struct Sample {
  Color color{0.0f};  ///< Linear RGB, premultiplied by alpha.
  /// Coverage: 1 minus the weight (mean over RGB) of straight escapes times (1 - backgroundAlpha). A miss gets
  /// backgroundAlpha, an opaque hit 1, a translucent hit (IOR 1) 1 - kt.
  float alpha = 0.0f;
  bool hit = false;
  Vec3 firstHit{0.0};       ///< World point of the first hit (for depth).
  /// How far the true first hit on the camera ray can lie from firstHit: the point's error bound plus its distance
  /// from the ray (a surface point is projected onto the surface, e.g. a tube's). The depth net counts a depth
  /// outside [0, 1] only when every point within this distance along the view direction is outside too.
  float firstHitSlack = 0.0f;
  /// Upper bound (largest channel) on the radiance the depth cap and the contribution threshold left out of
  /// color: what each cut ray could still have returned, plus light dropped by shadow rays cut by the threshold.
  float truncationBound = 0.0f;
};

/// Exact unpolarised Fresnel reflectance of a dielectric interface: eta = n_incident / n_transmitted, cosi and cost
/// the cosines of the incident and transmitted angles (Snell). Returns a value in [0, 1]; 1 at grazing incidence.
double fresnelDielectric(double cosi, double cost, double eta);

class Integrator {
 public:
  Integrator(const Scene& scene, const IntegratorSettings& settings, const Vec3& cameraUp);

  /// Traces a camera ray. screenBackground is the background colour behind this ray's pixel (the solid colour,
  /// or the vertical gradient at the pixel's row): what straight escapes see (see Sample).
  Sample trace(const Ray& ray, RayStats& stats, const Color& screenBackground) const;
  /// Traces n <= kBlock camera rays, e.g. of neighbouring pixels: out[i] is bit for bit trace(rays[i], stats[i],
  /// screenBackground[i]) and stats[i] gets the same ray counts (its nodesVisited differs). The shadow rays of
  /// the first hits toward each of the first kPacketLights lights are cast as one packet (Scene::occludedPacket),
  /// which loads each BVH node once for the block's rays; everything after the first hit is traced per ray. With
  /// IntegratorSettings::primaryPackets the first hits are found as one packet (Scene::intersectPacket). In a scene
  /// with transmissive surfaces both go one by one; with IntegratorSettings::packets off the shadow rays do, and
  /// with neither kind of packet the same as calling trace() for each ray. With misses, the rays that hit nothing
  /// have bit i set there and out[i] left unwritten: out[i] would be missSample(screenBackground[i], stats[i])
  /// (the caller can write a pixel from a miss computed once; rays traced one by one are never reported).
  void traceBlock(const Ray* rays, int n, RayStats* stats, const Color* screenBackground, Sample* out,
                  unsigned* misses = nullptr) const;
  /// trace()'s result for a camera ray that hits nothing, behind which the screen shows screenBackground.
  Sample missSample(const Color& screenBackground, RayStats& stats) const;
  static constexpr int kBlock = 4;
  static constexpr int kPacketLights = 8;

  /// Which optional mechanisms this frame's kernel contains (feature detection result after settings).
  bool usesReflection() const { return reflect_; }
  bool usesRefraction() const { return refract_; }
  bool usesShadows() const { return shadows_; }

 private:
  struct PathState;
  struct HitFrame;
  struct FirstHit;
  struct TraceShadows;
  struct CollectShadows;
  struct AnsweredShadows;
  struct ExactShadows;
  template <bool Reflect, bool Refract, bool Shadows, bool Volumes>
  Color radiance(const Ray& ray, int depth, Color weight, bool straight, RayStats& st, PathState& ps, double* tHit,
                 Vec3* firstHit, const FirstHit* pre) const;
  /// radiance() in a scene with volumes (shading/volume_march.cpp): the volumes' emission-absorption in front of
  /// the first surface hit, then the hit (or escape) through radiance() at the weight the volumes let through.
  template <bool Reflect, bool Refract, bool Shadows>
  Color throughVolumes(const Ray& ray, int depth, const Color& weight, bool straight, RayStats& st, PathState& ps,
                       double* tHit, Vec3* firstHit) const;
  /// The shading frame at a hit: surface data, oriented normals, view vector and material (radiance's first step).
  void frameHit(const Ray& ray, const Hit& hit, int depth, const PathState& ps, HitFrame& f) const;
  /// VTK's local shading: returns the body colour (ambient + diffuse terms) and writes the specular highlight to
  /// highlight (they are weighted apart: see bodyWeight). Shadow rays go through shadows (TraceShadows traces
  /// them; CollectShadows only records them, for a packet, and the colour it returns is meaningless;
  /// AnsweredShadows takes the packet's answers).
  template <bool Shadows, typename ShadowFn>
  Color shadeLocal(const SurfacePoint& sp, const Material& m, const Vec3& n, const Vec3& v, bool inside, RayStats& st,
                   Color& highlight, float& shadowCut, ShadowFn& shadows) const;
  /// A straight ray (on the camera ray's line) that hit nothing, at weight: the screen background's share.
  Color straightEscape(const Color& weight, PathState& ps) const;
  /// trace()'s start and end around the kernel call.
  void startPath(const Ray& ray, const Color& screenBackground, PathState& ps) const;
  Sample finishPath(const Color& color, double tHit, const Vec3& first, const PathState& ps, RayStats& stats) const;
  /// The local term at a hit (radiance's second step): opacity x the clamped local colour, as blended. Light cut
  /// from shadow rays by the threshold goes to ps.truncation (weighted by weight).
  template <bool Shadows, typename ShadowFn>
  Color localTerm(const HitFrame& f, const Color& weight, RayStats& st, PathState& ps, ShadowFn& shadows) const;
  /// The secondary rays radiance() spawns at a hit: the weights after total internal reflection and Fresnel.
  struct SecondaryRays {
    Color kr, kt;
    Ray reflected, refracted;
    bool haveReflected, haveRefracted;
    bool refractedStraight;  ///< The transmitted ray continues along the incoming line (no interface bend).
  };
  template <bool Reflect, bool Refract>
  void secondaryRays(const HitFrame& f, SecondaryRays& out) const;
  /// Tight truncation bound of a secondary ray cut at depth, with levels of bound rays (see
  /// IntegratorSettings::truncationLookahead): per channel, at least what it would return in the reference.
  /// Writes the hit distance to tHit (left on a miss).
  template <bool Reflect, bool Refract>
  /// weight: the cut ray's weight along its path (what its charge is multiplied by), for the adaptive lookahead;
  /// extra: levels it may still add; tolerance: its adaptive tolerance (truncationTolerance,
  /// truncationRelativeTolerance), or kCutRay for the cut ray itself (derived from its first charge).
  Color cutRayBound(const Ray& ray, int depth, int levels, int extra, const Color& weight, bool straight,
                    double pathLength, RayStats& st, PathState& ps, double* tHit, float tolerance) const;
  static constexpr float kCutRay = -1.0f;
  /// Bound on the radiance (largest channel) a secondary ray at depth childDepth could return in the reference.
  float remainingBound(int childDepth) const {
    if (seriesConverges_) return remaining_[0];
    return childDepth > referenceDepth_ ? 0.0f : remaining_[std::size_t(referenceDepth_ - childDepth)];
  }
  void buildRemainingBounds();
  /// How this integrator's rays march volumes: its step scale, and error for the step's estimate when it is on.
  VolumeStep volumeStep(float* error) const {
    return VolumeStep{s_.volumeStepScale, volumes_ && s_.volumeStepEstimate ? error : nullptr};
  }

  /// Accumulators of one camera ray's path tree.
  struct PathState {
    float truncation = 0.0f;  ///< Radiance bound of what was left out (see Sample::truncationBound).
    float escaped = 0.0f;     ///< Weight (mean over RGB) of straight escapes, times 1 - backgroundAlpha.
    Color screenBackground{0.0f};  ///< What straight escapes see (see Sample).
    double pathLength = 0.0;       ///< Length of the path up to the current ray's origin (edge footprints).
    float firstHitSlack = 0.0f;    ///< See Sample::firstHitSlack (set with the first hit).
    int boundRaysLeft = 0;  ///< The current cut ray's bound rays left (IntegratorSettings::truncationBoundRays).
    bool boundRaysCapped = false;  ///< The current cut ray reached truncationBoundRays (counted once).
  };
  using Kernel = Color (Integrator::*)(const Ray&, int, Color, bool, RayStats&, PathState&, double*, Vec3*,
                                       const FirstHit*) const;
  const Scene& scene_;
  /// The scene's lights that can add light (colour x intensity > 0), prepared once per frame.
  std::vector<PreparedLight> lights_;
  IntegratorSettings s_;
  Vec3 up_;
  bool reflect_, refract_, shadows_;
  bool volumes_ = false;  ///< The scene has volumes: the kernel marches them (Features::volumes).
  Kernel kernel_;
  /// Truncation bound: remaining_[n] bounds what a ray with n further levels of recursion returns (remaining_[0]
  /// alone, the infinite series' bound, when seriesConverges_). maxDepth 0 with a reflective or transmissive
  /// scene: the kernel has no secondary machinery, and depthZeroCut_ (max kr + kt) per hit is what was cut.
  std::vector<float> remaining_;
  bool seriesConverges_ = true;
  int referenceDepth_ = 0;
  bool cutAtDepthZero_ = false;
  int extraLevels_ = 0;  ///< Adaptive lookahead: levels a bound ray may add past truncationLookahead.
};

}  // namespace whitted
