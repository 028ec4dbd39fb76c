#include "light.h"

#include <algorithm>

namespace whitted {

Vec3 Light::direction() const {
  Vec3 d = focalPoint - position;
  double len = glm::length(d);
  return len > 0.0 && std::isfinite(len) ? d / len : Vec3(0.0, 0.0, -1.0);
}

LightSample sampleLight(const Light& light, const Vec3& p) {
  if (!light.positional) return LightSample{-light.direction(), kInfinity, 1.0};

  // Distance attenuation, clamped to at most 1 so a light never amplifies (A = min(1, 1/(a + b d + c d^2)))
  Vec3 toLight = light.position - p;
  double dist = glm::length(toLight);
  Vec3 l = dist > 0.0 ? toLight / dist : Vec3(0.0, 0.0, 1.0);
  double denom = light.attenuation.x + light.attenuation.y * dist + light.attenuation.z * dist * dist;
  double att = denom > 0.0 ? std::min(1.0, 1.0 / denom) : 1.0;

  // Spot cone: VTK treats cone angles of 90 degrees or more as an omni-directional light
  if (light.coneAngle < 90.0) {
    double coneDot = glm::dot(-l, light.direction());
    if (coneDot >= std::cos(light.coneAngle * kPi / 180.0))
      att *= std::pow(std::max(coneDot, 0.0), light.exponent);
    else
      att = 0.0;
  }
  return LightSample{l, dist, att};
}

}  // namespace whitted
