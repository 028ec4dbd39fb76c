// Sample positions inside a pixel, in pixel units (pixel (px, py) covers [px, px + 1) x [py, py + 1)): a
// deterministic function of (pixel, sample index), so an image is the same for any thread count and tile order.
#pragma once

#include "util/math.h"  // Vec2, hashFloat

#include <cmath>
#include <cstdint>

namespace whitted {

/// Position of sample s of n of pixel (px, py): the centre for one sample, else jittered strata of a grid of
/// ceil(sqrt(n)) columns.
inline Vec2 stratifiedSamplePos(int px, int py, int s, int n) {
  if (n == 1) return Vec2(px + 0.5, py + 0.5);
  int nx = int(std::ceil(std::sqrt(double(n))));
  int ny = (n + nx - 1) / nx;
  int cx = s % nx, cy = s / nx;
  double jx = hashFloat(uint32_t(px), uint32_t(py), uint32_t(s), 0u);
  double jy = hashFloat(uint32_t(px), uint32_t(py), uint32_t(s), 1u);
  return Vec2(px + (cx + jx) / nx, py + (cy + jy) / ny);
}

/// Which half (0 or 1) sample s of a pixel whose first strata samples form a stratified grid is summed into for the
/// calibrated sampling estimate (image/error_estimate.h): the grid's cells as a checkerboard (so each half spreads
/// over the whole pixel), then the samples of the sequence alternately.
inline int sampleHalf(int s, int strata) {
  if (s >= strata) return (s - strata) & 1;
  if (strata == 1) return 0;
  const int nx = int(std::ceil(std::sqrt(double(strata))));
  return ((s % nx) + (s / nx)) & 1;
}

/// Position of a pixel's k-th sample after its stratified grid (progressive refinement): the 2D R2
/// low-discrepancy sequence (Roberts), rotated per pixel (Cranley-Patterson), so that every prefix of the extra
/// samples covers the pixel evenly.
inline Vec2 sequenceSamplePos(int px, int py, int k) {
  constexpr double a1 = 0.7548776662466927, a2 = 0.5698402909980532;  // 1/g, 1/g^2 for g^3 = g + 1
  const double x = hashFloat(uint32_t(px), uint32_t(py), 0x52325232u, 2u) + a1 * k;
  const double y = hashFloat(uint32_t(px), uint32_t(py), 0x52325232u, 3u) + a2 * k;
  return Vec2(px + (x - std::floor(x)), py + (y - std::floor(y)));
}

}  // namespace whitted
