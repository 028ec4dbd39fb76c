// Whitted integrator: VTK's local shading + shadow rays + kr * reflected + kt * refracted, recursion cut by depth
// and by contribution. A kernel is chosen per frame from the scene's features (reflection / refraction / shadow
// machinery compiled out when the scene cannot use it).
#pragma once

#include "scene.h"

#include <cstdint>

namespace whitted {

/// Tracing settings. Defaults are those of vtkWhittedPass.
struct IntegratorSettings {
  int maxDepth = 5;         ///< Secondary bounces per path (0 = local shading only). Default 5.
  bool shadows = true;      ///< Trace shadow rays. Default on.
  bool reflections = true;  ///< Trace mirror rays for kr > 0. Default on.
  bool refractions = true;  ///< Bend transmitted rays by the IOR (off: straight-through transmission). Default on.
  float contributionThreshold = 1.0f / 255.0f;  ///< Rays whose weight falls below this are not traced. Default 1/255.
  bool fresnel = false;      ///< Schlick Fresnel moves part of kt to kr at grazing angles. Default off.
  bool beerLambert = false;  ///< Absorb light inside transmissive objects by exp(-absorption * distance). Default off.
  bool headlightShading = false;  ///< VTK light complexity 1 (one headlight): specular = pow(N.L, power).
  /// VTK computes the specular view vector from the camera position even for parallel projection; set this (and
  /// eye) to do the same for camera rays. Default off: the view vector is minus the ray direction.
  bool viewFromEye = false;
  Vec3 eye{0.0};  ///< Camera position, used when viewFromEye is set.
};

/// Ray counts of one frame (summed over threads).
struct RayStats {
  uint64_t primary = 0, shadow = 0, reflection = 0, refraction = 0;
  uint64_t savedByThreshold = 0;  ///< Secondary rays not traced because their weight was below the threshold.
  uint64_t savedByDepth = 0;      ///< Secondary rays not traced because the depth cap was reached.
  uint64_t nodesVisited = 0;
  RayStats& operator+=(const RayStats& o);
  uint64_t traced() const { return primary + shadow + reflection + refraction; }
};

/// Result of one camera ray.
struct Sample {
  Color color{0.0f};  ///< Linear RGB.
  /// Coverage: 1 minus the share of the ray's weight that escaped to a background of alpha < 1 (so a miss gets
  /// the background alpha, an opaque hit 1, a translucent hit less). color is premultiplied by it.
  float alpha = 0.0f;
  bool hit = false;
  Vec3 firstHit{0.0};       ///< World point of the first hit (for depth).
  float errorBound = 0.0f;  ///< Upper bound on the radiance left out by the depth cap and the threshold.
};

class Integrator {
 public:
  Integrator(const Scene& scene, const IntegratorSettings& settings, const Vec3& cameraUp);

  /// Traces a camera ray. Misses return the environment in direction ray.dir (callers that want a screen-space
  /// background replace it).
  Sample trace(const Ray& ray, RayStats& stats) const;

  /// Which optional mechanisms this frame's kernel contains (feature detection result after settings).
  bool usesReflection() const { return reflect_; }
  bool usesRefraction() const { return refract_; }
  bool usesShadows() const { return shadows_; }

 private:
  struct PathState;
  template <bool Reflect, bool Refract, bool Shadows>
  Color radiance(const Ray& ray, int depth, Color weight, RayStats& st, PathState& ps, double* tHit,
                 Vec3* firstHit) const;
  template <bool Shadows>
  Color shadeLocal(const SurfacePoint& sp, const Material& m, const Vec3& n, const Vec3& v, bool inside,
                   RayStats& st) const;
  float remainingBound(int depth) const;

  /// Accumulators of one camera ray's path tree.
  struct PathState {
    float errorBound = 0.0f;  ///< Radiance bound of rays left out.
    float escaped = 0.0f;     ///< Weight (mean over RGB) that reached a background of alpha < 1, times 1 - alpha.
  };
  using Kernel = Color (Integrator::*)(const Ray&, int, Color, RayStats&, PathState&, double*, Vec3*) const;
  const Scene& scene_;
  IntegratorSettings s_;
  Vec3 up_;
  bool reflect_, refract_, shadows_;
  Kernel kernel_;
};

}  // namespace whitted
