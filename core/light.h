// Lights as in vtkLight, in world coordinates.
#pragma once

#include "material.h"
#include "math.h"

namespace whitted {

/// A light. Directional lights shine from position toward focalPoint; positional lights sit at position and are
/// spot lights when coneAngle < 90 degrees (VTK's rule), aimed at focalPoint.
struct Light {
  bool positional = false;          ///< vtkLight Positional. Default false (directional).
  Vec3 position{0.0, 0.0, 1.0};     ///< World position (vtkLight GetTransformedPosition).
  Vec3 focalPoint{0.0};             ///< World focal point (vtkLight GetTransformedFocalPoint).
  Color color{1.0f};                ///< vtkLight DiffuseColor. Default white.
  float intensity = 1.0f;           ///< vtkLight Intensity. Default 1.
  Vec3 attenuation{1.0, 0.0, 0.0};  ///< Constant, linear, quadratic attenuation (positional only). Default (1,0,0).
  double coneAngle = 30.0;          ///< Half-angle of the spot cone in degrees; >= 90 means not a spot. Default 30.
  double exponent = 1.0;            ///< Spot exponent. Default 1.
  bool castShadows = true;          ///< Whether shadow rays are traced toward this light. Default true.

  /// Direction the light travels (unit), from position toward focal point.
  Vec3 direction() const;
};

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

/// Sanitises a light in place so no input can produce a NaN pixel: colour and intensity clamped to [0, 1e6]
/// (non-finite: 0), a light with a non-finite position, focal point, attenuation, cone angle or exponent switched
/// off (intensity 0), negative attenuation coefficients raised to 0, the spot exponent clamped to vtkLight's
/// [0, 128]. Returns true if anything was fixed.
bool sanitizeLight(Light& light);

}  // namespace whitted
