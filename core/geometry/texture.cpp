#include "geometry/texture.h"

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

}  // namespace

uint32_t sanitizeValue(float& v, float lo, float hi, float fallback, uint32_t bit) {
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

bool sanitizeColor(Color& c, float lo, float hi) {
  bool fixed = false;
  for (int i = 0; i < 3; ++i) fixed |= sanitizeValue(c[i], lo, hi, lo, 1u) != 0;
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

}  // namespace whitted
