#include "shading/light_sampling.h"

#include <algorithm>
#include <cmath>

namespace whitted {

PreparedLight prepareLight(const Light& light) {
  PreparedLight pl;
  pl.light = &light;
  pl.radiance = light.color * light.intensity;
  pl.spot = light.positional && light.coneAngle < 90.0;
  if (!light.positional || pl.spot) pl.direction = light.direction();
  if (pl.spot) pl.cosCone = std::cos(light.coneAngle * kPi / 180.0);
  return pl;
}

LightSample sampleLight(const PreparedLight& pl, const Vec3& p) {
  const Light& light = *pl.light;
  if (!light.positional) return LightSample{-pl.direction, kInfinity, 1.0};

  // Distance attenuation, clamped to at most 1 so a light never amplifies (A = min(1, 1/(a + b d + c d^2)))
  Vec3 toLight = light.position - p;
  double dist = glm::length(toLight);
  Vec3 l = dist > 0.0 ? toLight / dist : Vec3(0.0, 0.0, 1.0);
  double denom = light.attenuation.x + light.attenuation.y * dist + light.attenuation.z * dist * dist;
  double att = denom > 0.0 ? std::min(1.0, 1.0 / denom) : 1.0;

  // Spot cone: VTK treats cone angles of 90 degrees or more as an omni-directional light
  if (pl.spot) {
    double coneDot = glm::dot(-l, pl.direction);
    if (coneDot >= pl.cosCone)
      att *= std::pow(std::max(coneDot, 0.0), light.exponent);
    else
      att = 0.0;
  }
  return LightSample{l, dist, att};
}

}  // namespace whitted
