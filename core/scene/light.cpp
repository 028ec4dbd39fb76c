#include "scene/light.h"

#include <algorithm>
#include <cmath>

namespace whitted {

Vec3 Light::direction() const {
  Vec3 d = focalPoint - position;
  double len = glm::length(d);
  return len > 0.0 && std::isfinite(len) ? d / len : Vec3(0.0, 0.0, -1.0);
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
