// The march of one ray segment through a volume (Volume::march) and what it reads: grid samples (Volume::sample,
// trilinear in SSE), the transfer-function table (Volume::lookup) and the macro cells of empty-space skipping.
#include "geometry/volume.h"

#include <emmintrin.h>  // SSE2: part of every x86-64 CPU (Debian 12's baseline)

#include <algorithm>
#include <cmath>
#include <limits>

namespace whitted {

/// A march's macro-cell look-ups: the cell of a sample point and how far the march can go before it may leave that
/// cell. Per axis the ray's exit from cell c is at c A + B steps after t0 (the far plane (c + 1) K for d > 0, c K for
/// d < 0, in index space; none from the last cell the ray moves toward, nor for d = 0): one product and one sum per
/// axis instead of a division.
struct Volume::CellLook {
  const Volume& v;
  double A[3], B[3];
  int noExit[3];  // the cell with no exit plane on the axis (-1 for d = 0: the exit is infinitely far from any cell)
  __m128 lastCell;  // the last macro cell per axis
  CellLook(const Volume& vol, const Vec3& o, const Vec3& d, double t0, double dt)
      : v(vol),
        lastCell(_mm_setr_ps(float(vol.macroDims_[0] - 1), float(vol.macroDims_[1] - 1), float(vol.macroDims_[2] - 1),
                             0.0f)) {
    for (int a = 0; a < 3; ++a) {
      const int last = v.macroDims_[a] - 1;
      if (d[a] > 0.0) {
        A[a] = kMacroCell / d[a] / dt;
        B[a] = ((kMacroCell - o[a]) / d[a] - t0) / dt;
        noExit[a] = last;
      } else if (d[a] < 0.0) {
        A[a] = kMacroCell / d[a] / dt;
        B[a] = (-o[a] / d[a] - t0) / dt;
        noExit[a] = 0;
      } else {
        A[a] = 0.0;
        B[a] = kInfinity;
        noExit[a] = -1;
      }
    }
  }
  /// The macro cell of index point p (x, y, z in lanes 0..2; clamped to the grid's cells, as the sampler clamps
  /// the point; x / 8 is exact) as an index into the cell arrays, and in cell[3].
  std::size_t cellOf(__m128 p, int cell[3]) const {
    const __m128 q = _mm_min_ps(_mm_max_ps(_mm_mul_ps(p, _mm_set1_ps(1.0f / kMacroCell)), _mm_setzero_ps()), lastCell);
    alignas(16) int32_t c[4];
    _mm_store_si128(reinterpret_cast<__m128i*>(c), _mm_cvttps_epi32(q));
    cell[0] = c[0], cell[1] = c[1], cell[2] = c[2];
    return (std::size_t(c[2]) * std::size_t(v.macroDims_[1]) + std::size_t(c[1])) * std::size_t(v.macroDims_[0]) +
           std::size_t(c[0]);
  }
  /// For step k0, whose sample point lies in cell (index c in the cell arrays): the step before the first whose
  /// middle may lie past the ray's exit from the cell (at least k0 + 1, at most 2^60), negated when the cell is
  /// empty. The steps between have their middles inside by more than a step (far more than the rounding of the exit
  /// and of the float sample points).
  int64_t lastInside(const int cell[3], int64_t k0, std::size_t c) const {
    const int64_t k = lastInsideStep(cell, k0);
    return v.macroEmpty_[c] ? -k : k;
  }
  int64_t lastInsideStep(const int cell[3], int64_t k0) const {
    // (A NaN exit, 0 x inf or inf - inf, comes from a direction component so small that the plane lies beyond any
    // step: std::min keeps u)
    double u = kInfinity;
    for (int a = 0; a < 3; ++a)
      if (cell[a] != noExit[a]) u = std::min(u, double(cell[a]) * A[a] + B[a]);
    // ceil(u - 1/2) - 1 without the libm call (the conversion truncates)
    const double x = u - 0.5;
    if (!(x > double(k0 + 1))) return k0 + 1;
    if (!(x < 0x1p60)) return int64_t(1) << 60;
    int64_t k = int64_t(x);
    k += double(k) < x;
    return std::max(k - 1, k0 + 1);
  }
};

/// What the march reads per sample, copied out of the volume so that the compiler keeps it in registers (the
/// accumulation's stores could otherwise alias it and force reloads).
struct Volume::Sampler {
  const float* s;
  std::size_t sy, sz;
  __m128 hi;         // the last point's index per axis (lane 3: 0)
  __m128 lastCell;   // the last cell's first point per axis (lane 3: 0)
  bool nearest;
  const Entry* table;
  float tableMin, tableScale, tableLast;
  explicit Sampler(const Volume& v)
      : s(v.grid.scalars.data()),
        sy(std::size_t(v.grid.dims[0])),
        sz(std::size_t(v.grid.dims[0]) * std::size_t(v.grid.dims[1])),
        hi(_mm_setr_ps(float(v.grid.dims[0] - 1), float(v.grid.dims[1] - 1), float(v.grid.dims[2] - 1), 0.0f)),
        lastCell(_mm_setr_ps(float(v.grid.dims[0] - 2), float(v.grid.dims[1] - 2), float(v.grid.dims[2] - 2), 0.0f)),
        nearest(v.interpolation == VolumeInterpolation::Nearest),
        table(v.table_.data()),
        tableMin(v.tableMin_),
        tableScale(v.tableScale_),
        tableLast(v.tableLast_) {}
  /// The scalar at index point p (x, y, z in lanes 0..2, lane 3 0), clamped to the grid's points [0, n - 1] (NaN ->
  /// 0). Trilinear: the three axes' weights at once, the four x lerps at once, then the two y lerps (the same
  /// single-precision operations, in the same order, as one lerp at a time).
  float at(__m128 p) const {
    p = _mm_min_ps(_mm_max_ps(p, _mm_setzero_ps()), hi);  // (max returns its second operand for a NaN lane)
    if (nearest) {
      alignas(16) int32_t n[4];
      _mm_store_si128(reinterpret_cast<__m128i*>(n), _mm_cvttps_epi32(_mm_add_ps(p, _mm_set1_ps(0.5f))));
      return s[std::size_t(n[2]) * sz + std::size_t(n[1]) * sy + std::size_t(n[0])];
    }
    // The cell's first point (the last cell for a point on the far face: floor(min(p, n - 2)) = min(floor(p),
    // n - 2)) and the weights
    const __m128i i = _mm_cvttps_epi32(_mm_min_ps(p, lastCell));
    const __m128 f = _mm_sub_ps(p, _mm_cvtepi32_ps(i));
    const std::size_t ix = std::size_t(uint32_t(_mm_cvtsi128_si32(i)));
    const std::size_t iy = std::size_t(uint32_t(_mm_cvtsi128_si32(_mm_shuffle_epi32(i, _MM_SHUFFLE(1, 1, 1, 1)))));
    const std::size_t iz = std::size_t(uint32_t(_mm_cvtsi128_si32(_mm_shuffle_epi32(i, _MM_SHUFFLE(2, 2, 2, 2)))));
    const float* c = s + iz * sz + iy * sy + ix;
    // Pairs (c[o], c[o + 1]) at the cell's four x edges o = 0, sy, sz, sz + sy
    auto pair = [](const float* q) { return _mm_castpd_ps(_mm_load_sd(reinterpret_cast<const double*>(q))); };
    const __m128 e01 = _mm_unpacklo_ps(pair(c), pair(c + sy));            // c0 csy c1 csy1
    const __m128 e23 = _mm_unpacklo_ps(pair(c + sz), pair(c + sz + sy));  // csz cszy csz1 cszy1
    const __m128 a = _mm_movelh_ps(e01, e23), b = _mm_movehl_ps(e23, e01);
    const __m128 x = _mm_add_ps(a, _mm_mul_ps(_mm_shuffle_ps(f, f, _MM_SHUFFLE(0, 0, 0, 0)), _mm_sub_ps(b, a)));
    // x = c00 c10 c01 c11: lerp (c00, c01) toward (c10, c11) by fy, then the two by fz
    const __m128 y0 = _mm_shuffle_ps(x, x, _MM_SHUFFLE(2, 0, 2, 0)), y1 = _mm_shuffle_ps(x, x, _MM_SHUFFLE(3, 1, 3, 1));
    const __m128 y = _mm_add_ps(y0, _mm_mul_ps(_mm_shuffle_ps(f, f, _MM_SHUFFLE(1, 1, 1, 1)), _mm_sub_ps(y1, y0)));
    const float c0 = _mm_cvtss_f32(y), c1 = _mm_cvtss_f32(_mm_shuffle_ps(y, y, _MM_SHUFFLE(1, 1, 1, 1)));
    return c0 + _mm_cvtss_f32(_mm_shuffle_ps(f, f, _MM_SHUFFLE(2, 2, 2, 2))) * (c1 - c0);
  }
  /// The fractional table entry index of scalar v, clamped to [0, tableLast] (NaN, an overflowed v - tableMin
  /// times 0, gives 0).
  float tableIndex(float v) const {
    float x = (v - tableMin) * tableScale;
    x = x > 0.0f ? x : 0.0f;  // (maxss and minss, branch-free; NaN -> 0 at the first)
    return x < tableLast ? x : tableLast;
  }
};

Volume::Entry Volume::lookup(float s) const {
  const float x = Sampler(*this).tableIndex(s);
  const std::size_t i = std::size_t(x);
  const float f = x - float(i);
  const Entry &a = table_[i], &b = table_[i + 1];  // (the table's last entry is repeated once)
  return Entry{a.color + f * (b.color - a.color), a.opacity + f * (b.opacity - a.opacity),
               a.alphaStep + f * (b.alphaStep - a.alphaStep)};
}

float Volume::sample(const Vec3& index) const {
  return Sampler(*this).at(_mm_setr_ps(float(index.x), float(index.y), float(index.z), 0.0f));
}

void Volume::march(const Ray& ray, double t0, double t1, bool emission, float stopBelow, VolumeMarch& acc) const {
  const double len = glm::length(lengthMetric * ray.dir);
  if (!(t1 > t0) || !(len > 0.0)) return;
  const Vec3 o = toIndex_ * (ray.origin - grid.origin);
  const Vec3 d = toIndex_ * ray.dir;
  const double dt = step_ / len;
  const double count = std::ceil((t1 - t0) / dt);
  if (!(count >= 1.0)) return;
  const int64_t steps = int64_t(std::min(count, 2.0 * kMaxSteps));
  const double perUnit = len / transfer.unitDistance;
  const bool skip = skipEmptySpace && !macroEmpty_.empty();
  const Sampler smp(*this);
  // Step k spans [t0 + k dt, t0 + (k + 1) dt] while that ends by t1 and is not the last (a full step: the table's
  // alpha); fullness falls with k, so the full steps are [0, fullEnd) and the rest (one, or two where rounding
  // ends the step before the last at t1) end at t1
  int64_t fullEnd = steps - 1;
  while (fullEnd > 0 && !(t0 + double(fullEnd - 1) * dt + dt <= t1)) --fullEnd;
  // Sample points in single precision: the segment's entry point in index space, plus the direction times the
  // parameter from the entry to the step's middle (each rounded once, the full steps' middles (k + 1/2) dt in
  // float: within a few float ulps of the grid's extent, 1e-5 voxels on a 256^3 grid, like the float march of VTK's
  // GPU mapper)
  const Vec3 entry = o + t0 * d;
  const __m128 e = _mm_setr_ps(float(entry.x), float(entry.y), float(entry.z), 0.0f);
  const __m128 dF = _mm_setr_ps(float(d.x), float(d.y), float(d.z), 0.0f);
  auto at = [&](float h) { return _mm_add_ps(e, _mm_mul_ps(_mm_set1_ps(h), dF)); };  // the point h after the entry
  const float dtF = float(dt);
  // Accumulated in locals, stored once at the end
  Color color = acc.color;
  float transmittance = acc.transmittance;
  uint64_t samples = 0, invalid = 0;
  bool terminated = false;
  // Adds the sample at index point p of a step with alpha from the table (full) or for length h (in ray
  // parameter units); returns false once the transmittance falls below stopBelow
  auto add = [&](__m128 p, bool full, double h) __attribute__((always_inline)) {
    const float s = smp.at(p);
    ++samples;
    if (std::isnan(s)) {
      ++invalid;
      return true;
    }
    // The table entry: opacity first (most samples of a partly transparent cell have none)
    const float x = smp.tableIndex(s);
    const int i = int(x);  // (x in [0, kTableSize - 1]: an int conversion, cheaper than one to size_t)
    const float f = x - float(i);
    const Entry &ea = smp.table[i], &eb = smp.table[i + 1];  // (the last entry is repeated: i + 1 is in the table)
    const float opacity = ea.opacity + f * (eb.opacity - ea.opacity);
    if (opacity <= 0.0f) return true;
    // 1 - (1 - a)^(h / unitDistance), from the table for a full step; a = 1 gives log1p(-1) = -inf and alpha 1
    const float alpha = full ? ea.alphaStep + f * (eb.alphaStep - ea.alphaStep)
                             : float(-std::expm1(std::log1p(-double(opacity)) * h * perUnit));
    if (emission) color += (transmittance * alpha) * (ea.color + f * (eb.color - ea.color));
    transmittance *= 1.0f - alpha;
    return transmittance >= stopBelow;
  };
  const CellLook look(*this, o, d, t0, dt);
  // Runs of steps sampled without looking at macro cells: without skipping, all of them; with it, a non-empty
  // cell's steps up to the first that may lie outside it (CellLook::lastInside: steps before lie inside by more
  // than a step), or, after an empty cell's steps are skipped, the one step the skip lands on (about at the exit)
  // The parameter from the entry to step k's middle
  auto middle = [&](int64_t k) {
    return k < fullEnd ? (float(k) + 0.5f) * dtF : float(0.5 * (t0 + double(k) * dt + t1) - t0);
  };
  for (int64_t k = 0; k < steps && !terminated;) {
    int64_t runEnd = steps;
    if (skip) {
      int cell[3];
      const int64_t exit = look.lastInside(cell, k, look.cellOf(at(middle(k)), cell));
      if (exit < 0) {
        // An empty cell: no sample in it adds anything. The step landed on may lie in it or in the next cell: it
        // is sampled unless the cell its point lies in is empty too (exact: the sampler reads that point from that
        // cell's points), and the march looks again at the step after it
        k = -exit;
        if (k < steps && macroEmpty_[look.cellOf(at(middle(k)), cell)]) {
          ++k;
          continue;
        }
        runEnd = k + 1;
      } else {
        runEnd = exit;
      }
      runEnd = std::min(runEnd, steps);
    }
    // The run's full steps: the tight loop
    const int64_t fullStop = std::min(runEnd, fullEnd);
    for (; k < fullStop; ++k) {
      const float h = (float(k) + 0.5f) * dtF;
      if (!add(at(h), true, 0.0)) {
        terminated = true;
        break;
      }
    }
    // The steps ending at t1
    for (; k < runEnd && !terminated; ++k) {
      const double ta = t0 + double(k) * dt;
      if (!(t1 > ta)) continue;
      const float h = float(0.5 * (ta + t1) - t0);
      if (!add(at(h), false, t1 - ta)) terminated = true;
    }
  }
  acc.color = color;
  acc.transmittance = transmittance;
  acc.samples += samples;
  acc.invalidSamples += invalid;
  acc.terminated = acc.terminated || terminated;
}

}  // namespace whitted
