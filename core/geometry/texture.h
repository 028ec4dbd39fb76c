// Textures (RGBA8 images sampled by texture coordinates: actor textures and colour maps) and the one set of
// colour sanitisers that geometry colours, materials and lights share.
#pragma once

#include "util/math.h"

#include <cstdint>
#include <vector>

namespace whitted {

/// RGBA8 texture, rows bottom to top (OpenGL/VTK order).
struct Texture {
  int width = 0, height = 0;
  std::vector<uint8_t> rgba;  ///< width*height*4 bytes.
  bool repeat = true;         ///< Repeat (true) or clamp to edge (false).
  bool interpolate = false;   ///< Bilinear (true) or nearest (false), as vtkTexture InterpolateOn/Off.
  /// Samples at (s, t) in texture coordinates; returns RGBA in [0,1].
  Color4 sample(float s, float t) const;
};

/// The one value sanitiser: a non-finite v becomes fallback, one outside [lo, hi] is clamped to it. Returns bit
/// if anything changed, else 0 (so callers can collect what they fixed in a mask).
uint32_t sanitizeValue(float& v, float lo, float hi, float fallback, uint32_t bit);
/// The one colour sanitiser: clamps each RGB component of c to [lo, hi], a non-finite one becomes lo. Returns
/// true if anything changed.
bool sanitizeColor(Color& c, float lo, float hi);
/// Geometry colours (vertex, triangle, sphere, tube colours): RGB as sanitizeColor(rgb, 0, 1), alpha clamped to
/// [0,1] with a non-finite alpha becoming 1, so no NaN can reach shading.
void sanitizeColors(std::vector<Color4>& colors);
/// One geometry colour sanitised as sanitizeColors does.
Color4 sanitizedColor(const Color4& c);

}  // namespace whitted
