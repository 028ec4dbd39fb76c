#include "material.h"

#include <algorithm>
#include <cmath>

namespace whitted {

namespace {

float wrapCoord(float x, bool repeat) {
  if (!std::isfinite(x)) return 0.0f;
  if (repeat) return x - std::floor(x);
  return std::clamp(x, 0.0f, 1.0f);
}

Color4 texel(const Texture& t, int x, int y) {
  x = std::clamp(x, 0, t.width - 1);
  y = std::clamp(y, 0, t.height - 1);
  const uint8_t* p = &t.rgba[(size_t(y) * t.width + x) * 4];
  return Color4(p[0], p[1], p[2], p[3]) * (1.0f / 255.0f);
}

uint32_t fixRange(float& v, float lo, float hi, float fallback, uint32_t bit) {
  if (!std::isfinite(v)) {
    v = fallback;
    return bit;
  }
  if (v < lo || v > hi) {
    v = std::clamp(v, lo, hi);
    return bit;
  }
  return 0;
}

uint32_t fixColor(Color& c, float lo, float hi, uint32_t bit) {
  return sanitizeColor(c, lo, hi) ? bit : 0;
}

}  // namespace

bool sanitizeColor(Color& c, float lo, float hi) {
  bool fixed = false;
  for (int i = 0; i < 3; ++i) fixed |= fixRange(c[i], lo, hi, lo, 1u) != 0;
  return fixed;
}

Color4 sanitizedColor(const Color4& c) {
  Color rgb(c);
  sanitizeColor(rgb, 0.0f, 1.0f);
  const float a = std::isfinite(c.a) ? std::clamp(c.a, 0.0f, 1.0f) : 1.0f;
  return Color4(rgb, a);
}

void sanitizeColors(std::vector<Color4>& colors) {
  for (Color4& c : colors) c = sanitizedColor(c);
}

Color4 Texture::sample(float s, float t) const {
  if (width <= 0 || height <= 0 || rgba.size() < size_t(width) * height * 4) return Color4(1.0f);
  float u = wrapCoord(s, repeat) * width, v = wrapCoord(t, repeat) * height;
  if (!interpolate) return texel(*this, int(u), int(v));
  // Bilinear between texel centres
  float fu = u - 0.5f, fv = v - 0.5f;
  int x0 = int(std::floor(fu)), y0 = int(std::floor(fv));
  float ax = fu - x0, ay = fv - y0;
  auto at = [&](int x, int y) {
    if (repeat) {
      x = ((x % width) + width) % width;
      y = ((y % height) + height) % height;
    }
    return texel(*this, x, y);
  };
  return (1 - ay) * ((1 - ax) * at(x0, y0) + ax * at(x0 + 1, y0)) +
         ay * ((1 - ax) * at(x0, y0 + 1) + ax * at(x0 + 1, y0 + 1));
}

uint32_t sanitizeMaterial(Material& m) {
  uint32_t fixed = 0;
  fixed |= fixColor(m.ambientColor, 0.0f, 1e6f, 1u << 0);
  fixed |= fixColor(m.diffuseColor, 0.0f, 1e6f, 1u << 0);
  fixed |= fixColor(m.specularColor, 0.0f, 1e6f, 1u << 0);
  fixed |= fixRange(m.ambient, 0.0f, 1e6f, 0.0f, 1u << 1);
  fixed |= fixRange(m.diffuse, 0.0f, 1e6f, 0.0f, 1u << 1);
  fixed |= fixRange(m.specular, 0.0f, 1e6f, 0.0f, 1u << 1);
  fixed |= fixRange(m.specularPower, 0.0f, 1e6f, 1.0f, 1u << 2);
  fixed |= fixRange(m.opacity, 0.0f, 1.0f, 1.0f, 1u << 3);
  fixed |= fixColor(m.reflectance, 0.0f, 1.0f, 1u << 4);
  fixed |= fixColor(m.transmittance, 0.0f, 1.0f, 1u << 5);
  if (!std::isfinite(m.ior) || m.ior <= 0.0f) {
    m.ior = 1.0f;
    fixed |= 1u << 6;
  }
  fixed |= fixColor(m.absorption, 0.0f, 1e30f, 1u << 7);
  fixed |= fixColor(m.edgeColor, 0.0f, 1.0f, 1u << 0);
  fixed |= fixRange(m.edgeWidth, 0.0f, 1e6f, 0.0f, 1u << 1);

  // Energy: kr + kt <= 1 per channel. Above, scale both by 1 / max channel sum; the factor is stepped down by an
  // ulp at a time should float rounding leave the largest sum above 1 (one or two steps at most)
  const Color kr = m.reflectance, kt = m.transmittance;
  const float maxSum = maxComponent(kr + kt);
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
