#include "scene/material.h"

#include <algorithm>
#include <cmath>

namespace whitted {

namespace {

uint32_t fixColor(Color& c, float lo, float hi, uint32_t bit) {
  return sanitizeColor(c, lo, hi) ? bit : 0;
}

}  // namespace

float absorptionFromAttenuation(double kept, double distance) {
  if (kept == 1.0) return 0.0f;  // keeps everything: no absorption, even over a distance of 0
  const double a = -std::log(kept) / distance;
  return float(std::isnan(a) ? a : std::min(a, double(kMaxAbsorption)));
}

void metallicReflectance(const double base[3], double metallic, double roughness, double ior, double out[3]) {
  metallic = std::clamp(metallic, 0.0, 1.0);
  roughness = std::clamp(roughness, 0.0, 1.0);
  const double f0 = std::isfinite(ior) && ior > 0.0 ? ((ior - 1.0) / (ior + 1.0)) * ((ior - 1.0) / (ior + 1.0)) : 0.04;
  for (int i = 0; i < 3; ++i) out[i] = (1.0 - roughness) * (metallic * base[i] + (1.0 - metallic) * f0);
}

bool sanitizeOpacity(float& opacity) {
  return sanitizeValue(opacity, 0.0f, 1.0f, 1.0f, 1u) != 0;
}

uint32_t sanitizeMaterial(Material& m, float* energySum) {
  uint32_t fixed = 0;
  fixed |= fixColor(m.ambientColor, 0.0f, 1e6f, 1u << 0);
  fixed |= fixColor(m.diffuseColor, 0.0f, 1e6f, 1u << 0);
  fixed |= fixColor(m.specularColor, 0.0f, 1e6f, 1u << 0);
  fixed |= sanitizeValue(m.ambient, 0.0f, 1e6f, 0.0f, 1u << 1);
  fixed |= sanitizeValue(m.diffuse, 0.0f, 1e6f, 0.0f, 1u << 1);
  fixed |= sanitizeValue(m.specular, 0.0f, 1e6f, 0.0f, 1u << 1);
  fixed |= sanitizeValue(m.specularPower, 0.0f, 1e6f, 1.0f, 1u << 2);
  if (sanitizeOpacity(m.opacity)) fixed |= 1u << 3;
  fixed |= fixColor(m.reflectance, 0.0f, 1.0f, 1u << 4);
  fixed |= fixColor(m.transmittance, 0.0f, 1.0f, 1u << 5);
  if (!std::isfinite(m.ior) || m.ior <= 0.0f) {
    m.ior = 1.0f;
    fixed |= 1u << 6;
  }
  fixed |= fixColor(m.absorption, 0.0f, kMaxAbsorption, 1u << 7);
  fixed |= fixColor(m.edgeColor, 0.0f, 1.0f, 1u << 0);
  fixed |= sanitizeValue(m.edgeWidth, 0.0f, 1e6f, 0.0f, 1u << 1);

  // Energy: kr + kt <= 1 per channel. Above, scale both by 1 / max channel sum; the factor is stepped down by an
  // ulp at a time should float rounding leave the largest sum above 1 (one or two steps at most)
  const Color kr = m.reflectance, kt = m.transmittance;
  const float maxSum = maxComponent(kr + kt);
  if (energySum) *energySum = maxSum;
  if (maxSum > 1.0f) {
    float scale = 1.0f / maxSum;
    while (maxComponent(kr * scale + kt * scale) > 1.0f) scale = std::nextafter(scale, 0.0f);
    m.reflectance = kr * scale;
    m.transmittance = kt * scale;
    fixed |= kMaterialEnergyScaled;
  }
  return fixed;
}

Material edgeMaterial(const Material& m) {
  Material e = m;
  e.ambientColor = e.diffuseColor = m.edgeColor;
  e.colorSource = ColorSource::Material;
  e.texture = -1;
  e.reflectance = Color(0.0f);
  e.transmittance = glm::min(m.transmittance, Color(1.0f - m.opacity));
  e.ior = 1.0f;
  e.absorption = Color(0.0f);
  e.edgeWidth = 0.0f;
  e.backMaterial = -1;
  return e;
}

}  // namespace whitted
