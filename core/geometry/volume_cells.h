// The march's macro-cell look-ups (Volume::CellLook): which cell a sample point lies in, and how many steps the
// march may take before it may leave that cell or a run of non-empty ones. Private to geometry/volume_sampling.cpp
// (the march of Volume::march), apart from it only for its length.
#pragma once

#include "geometry/volume.h"

#include <emmintrin.h>  // SSE2: part of every x86-64 CPU (Debian 12's baseline)

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>

namespace whitted {

/// A march's macro-cell look-ups: the cell of a sample point and how far the march can go before it may leave that
/// cell. Per axis the ray's exit from cell c is at c A + B steps after t0 (the far plane (c + 1) K for d > 0, c K for
/// d < 0, in index space; none from the last cell the ray moves toward, nor for d = 0): one product and one sum per
/// axis instead of a division.
struct Volume::CellLook {
  const Volume& v;
  double A[3], B[3];
  int noExit[3];    // the cell with no exit plane on the axis (-1 for d = 0: the exit is infinitely far from any cell)
  __m128 lastCell;  // the last macro cell per axis
  CellLook(const Volume& vol, const Vec3& o, const Vec3& d, double t0, double dt)
      : v(vol),
        lastCell(_mm_setr_ps(float(vol.macroDims_[0] - 1), float(vol.macroDims_[1] - 1), float(vol.macroDims_[2] - 1),
                             0.0f)) {
    for (int a = 0; a < 3; ++a) {
      // Toward +x the far plane of cell c is (c + 1) K, toward -x it is c K
      const double A0 = kMacroCell / d[a] / dt;
      const double B0 = d[a] > 0.0 ? ((kMacroCell - o[a]) / d[a] - t0) / dt : (-o[a] / d[a] - t0) / dt;
      if (d[a] != 0.0 && std::isfinite(A0) && std::isfinite(B0)) {
        A[a] = A0;
        B[a] = B0;
        noExit[a] = d[a] > 0.0 ? v.macroDims_[a] - 1 : 0;
      } else {
        // Parallel to the axis's planes (or NaN), or so nearly that a step moves the point by less than 1e-300
        // voxels (no float sample point ever moves along it): no exit
        A[a] = 0.0;
        B[a] = kInfinity;
        noExit[a] = -1;
      }
    }
  }
  /// The macro cell of index point p (x, y, z in lanes 0..2; clamped to the grid's cells, as the sampler clamps
  /// the point; x / kMacroCell is exact) as an index into the cell arrays, and in cell[3].
  std::size_t cellOf(__m128 p, int cell[3]) const {
    const __m128 q = _mm_min_ps(_mm_max_ps(_mm_mul_ps(p, _mm_set1_ps(1.0f / kMacroCell)), _mm_setzero_ps()), lastCell);
    alignas(16) int32_t c[4];
    _mm_store_si128(reinterpret_cast<__m128i*>(c), _mm_cvttps_epi32(q));
    cell[0] = c[0], cell[1] = c[1], cell[2] = c[2];
    return (std::size_t(c[2]) * std::size_t(v.macroDims_[1]) + std::size_t(c[1])) * std::size_t(v.macroDims_[0]) +
           std::size_t(c[0]);
  }
  /// For step k0, whose sample point lies in cell (index c in the cell arrays): an empty cell gives the step before
  /// the first whose middle may lie past the ray's exit from the cell (at least k0 + 1, at most 2^60), negated; the
  /// steps between have their middles inside by more than a step (far more than the rounding of the exit and of
  /// the float sample points), so they can be skipped. A non-empty cell gives the end of the run of steps to sample
  /// before looking again (lastInsideRun).
  int64_t lastInside(const int cell[3], int64_t k0, std::size_t c) const {
    return v.macroEmpty_[c] ? -lastInsideStep(cell, k0) : lastInsideRun(cell, k0);
  }
  int64_t lastInsideStep(const int cell[3], int64_t k0) const {
    double u = kInfinity;
    for (int a = 0; a < 3; ++a) u = std::min(u, exitOf(cell, a));
    return stepBefore(u, k0);
  }
  static constexpr int kRunCells = 8;  ///< At most this many cells after the first per run (lastInsideRun).
  /// From non-empty cell at step k0: the step before the first whose middle may lie past the ray's exit from the
  /// last cell of the run of non-empty cells it crosses from there (at most kRunCells more: a ray may end before;
  /// cells in the order of their exits along the ray, one axis at a time). Every step up to there is sampled; the
  /// order needs no exactness at edges and corners, since it only decides where the march looks again (a step in a
  /// cell it missed adds nothing if that cell is empty).
  int64_t lastInsideRun(const int cell[3], int64_t k0) const {
    // Branch-free per cell (the axis of the nearest exit changes from cell to cell unpredictably), in scalars
    int cx = cell[0], cy = cell[1], cz = cell[2];
    double ux = exitOf(cell, 0), uy = exitOf(cell, 1), uz = exitOf(cell, 2);
    const int sx = A[0] > 0.0 ? 1 : -1, sy = A[1] > 0.0 ? 1 : -1, sz = A[2] > 0.0 ? 1 : -1;
    const std::size_t nx = std::size_t(v.macroDims_[0]), nxy = nx * std::size_t(v.macroDims_[1]);
    for (int n = 0;; ++n) {
      const bool yFirst = uy < ux;
      const double nearXY = yFirst ? uy : ux;
      const bool z = uz < nearXY;
      const double u = z ? uz : nearXY;
      // The last cell on every axis the ray moves along, or as far as one look goes (a ray may end before)
      if (!(u < kInfinity) || n == kRunCells) return stepBefore(u, k0);
      const bool x = !z && !yFirst, y = !z && yFirst;
      cx += x ? sx : 0;
      cy += y ? sy : 0;
      cz += z ? sz : 0;
      if (v.macroEmpty_[std::size_t(cz) * nxy + std::size_t(cy) * nx + std::size_t(cx)]) return stepBefore(u, k0);
      const double ex = cx != noExit[0] ? double(cx) * A[0] + B[0] : kInfinity;
      const double ey = cy != noExit[1] ? double(cy) * A[1] + B[1] : kInfinity;
      const double ez = cz != noExit[2] ? double(cz) * A[2] + B[2] : kInfinity;
      ux = x ? ex : ux;
      uy = y ? ey : uy;
      uz = z ? ez : uz;
    }
  }
  /// The ray's exit from cell c across axis a, in steps after t0: +inf when the ray does not leave it that way.
  double exitOf(const int c[3], int a) const { return c[a] != noExit[a] ? double(c[a]) * A[a] + B[a] : kInfinity; }
  /// ceil(u - 1/2) - 1 (the step before the first whose middle may lie past u), at least k0 + 1, at most 2^60
  /// (without the libm call: the conversion truncates).
  static int64_t stepBefore(double u, int64_t k0) {
    const double x = u - 0.5;
    if (!(x > double(k0 + 1))) return k0 + 1;
    if (!(x < 0x1p60)) return int64_t(1) << 60;
    int64_t k = int64_t(x);
    k += double(k) < x;
    return std::max(k - 1, k0 + 1);
  }
};

}  // namespace whitted
