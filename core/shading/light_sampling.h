// How shading samples a light: the per-frame part of a light (PreparedLight) and VTK's attenuation and spot cone
// at a lit point (sampleLight).
#pragma once

#include "scene/light.h"

namespace whitted {

/// Light arriving at a point: unit direction toward the light, distance (infinite for directional), and the
/// scalar attenuation (distance and spot) VTK applies.
struct LightSample {
  Vec3 toLight;
  double distance;
  double attenuation;
};

/// What shading needs of a light that does not depend on the lit point, computed once per frame (the light's
/// direction, the cosine of its cone, its colour times intensity) so that a hit costs no square root, division or
/// cosine beyond the point's own.
struct PreparedLight {
  const Light* light = nullptr;
  Color radiance{0.0f};   ///< color * intensity.
  Vec3 direction{0.0};    ///< light->direction() (directional lights and spots).
  double cosCone = -1.0;  ///< cos(coneAngle) of a spot light.
  bool spot = false;      ///< Positional with coneAngle < 90 degrees.
};
PreparedLight prepareLight(const Light& light);

/// Evaluates VTK's attenuation and spot cone for point p.
LightSample sampleLight(const PreparedLight& light, const Vec3& p);
inline LightSample sampleLight(const Light& light, const Vec3& p) {
  return sampleLight(prepareLight(light), p);
}

}  // namespace whitted
