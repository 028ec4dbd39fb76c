#include "light.h"

#include <algorithm>

namespace whitted {

Vec3 Light::direction() const {
  Vec3 d = focalPoint - position;
  double len = glm::length(d);
  return len > 0.0 && std::isfinite(len) ? d / len : Vec3(0.0, 0.0, -1.0);
}

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

bool sanitizeLight(Light& l) {
  bool bad = sanitizeColor(l.color, 0.0f, 1e6f);
  if (!std::isfinite(l.intensity) || l.intensity < 0.0f || l.intensity > 1e6f) {
    l.intensity = std::isfinite(l.intensity) ? std::clamp(l.intensity, 0.0f, 1e6f) : 0.0f;
    bad = true;
  }
  if (!isFinite(l.position) || !isFinite(l.focalPoint) || !isFinite(l.attenuation) || !std::isfinite(l.coneAngle) ||
      !std::isfinite(l.exponent)) {
    l.intensity = 0.0f;  // cannot be placed: switched off
    bad = true;
  }
  if (l.attenuation.x < 0.0 || l.attenuation.y < 0.0 || l.attenuation.z < 0.0) {
    l.attenuation = glm::max(l.attenuation, Vec3(0.0));
    bad = true;
  }
  // vtkLight's own range (SetExponent clamps to [0, 128]): a negative spot exponent would make the cone factor
  // infinite (pow(cos, -e))
  if (l.exponent < 0.0 || l.exponent > 128.0) {
    l.exponent = std::clamp(l.exponent, 0.0, 128.0);
    bad = true;
  }
  return bad;
}

}  // namespace whitted
