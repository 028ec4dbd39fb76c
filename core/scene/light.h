// Lights as in vtkLight, in world coordinates (what the scene holds; how shading samples them: shading/light_sampling.h).
#pragma once

#include "geometry/texture.h"
#include "util/math.h"

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

/// Sanitises a light in place so no input can produce a NaN pixel: colour and intensity clamped to [0, 1e6]
/// (non-finite: 0), a light with a non-finite position, focal point, attenuation, cone angle or exponent switched
/// off (intensity 0), negative attenuation coefficients raised to 0, the spot exponent clamped to vtkLight's
/// [0, 128]. Returns true if anything was fixed.
bool sanitizeLight(Light& light);

}  // namespace whitted
