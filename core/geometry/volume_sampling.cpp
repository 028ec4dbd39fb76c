// The march of one ray segment through a volume (Volume::march) and what it reads: grid samples (Volume::sample,
// trilinear in SSE), the transfer-function table (Volume::lookup) and the macro cells of empty-space skipping
// (their look-ups: geometry/volume_cells.h).
#include "geometry/volume.h"
#include "geometry/volume_cells.h"
#include "geometry/volume_shading.h"

#include <emmintrin.h>  // SSE2: part of every x86-64 CPU (Debian 12's baseline)

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <limits>

namespace whitted {

/// What the march reads per sample, copied out of the volume so that the compiler keeps it in registers (the
/// accumulation's stores could otherwise alias it and force reloads).
struct Volume::Sampler {
  const float* s;
  std::size_t sy, sz;
  __m128 hi;         // the last point's index per axis (lane 3: 0)
  __m128 lastCell;   // the last cell's first point per axis (lane 3: 0)
  __m128 hi4[3], lastCell4[3];  // the same per axis in every lane (at4)
  bool nearest;
  const Entry* table;
  float tableMin, tableScale, tableLast;
  __m128 opaqueLo, opaqueHi;  // Volume::opaqueLo_, opaqueHi_
  __m128 gradStep;            // gradient()'s offsets per axis, n / (n - 1) points
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
        tableLast(v.tableLast_),
        opaqueLo(_mm_set1_ps(v.opaqueLo_)),
        opaqueHi(_mm_set1_ps(v.opaqueHi_)),
        gradStep(_mm_setr_ps(float(v.grid.dims[0]) / float(v.grid.dims[0] - 1),
                             float(v.grid.dims[1]) / float(v.grid.dims[1] - 1),
                             float(v.grid.dims[2]) / float(v.grid.dims[2] - 1), 0.0f)) {
    for (int a = 0; a < 3; ++a) {
      hi4[a] = _mm_set1_ps(float(v.grid.dims[a] - 1));
      lastCell4[a] = _mm_set1_ps(float(v.grid.dims[a] - 2));
    }
  }
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
    // Pairs (c[o], c[o + 1]) at the cell's four x edges o = 0, sy, sz, sz + sy (pair(): below)
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
  /// Central differences about index point p, s(p + o_a e_a) - s(p - o_a e_a) per axis a, with VTK's GPU mapper's
  /// offset o_a = n_a / (n_a - 1) points (one texel of its texture, whose texels centre on the n_a points: a
  /// gradient of a coarse grid turns with it), the reads clamped to the grid by at(), as VTK's texture reads clamp.
  Vec3f gradient(__m128 p) const {
    // Two at4() calls (the same values as at() per point): x+, x-, y+, y-, then z+, z- (twice)
    const __m128 px = _mm_shuffle_ps(p, p, _MM_SHUFFLE(0, 0, 0, 0)), py = _mm_shuffle_ps(p, p, _MM_SHUFFLE(1, 1, 1, 1)),
                 pz = _mm_shuffle_ps(p, p, _MM_SHUFFLE(2, 2, 2, 2));
    const __m128 o = gradStep, zero = _mm_setzero_ps();
    const __m128 ox = _mm_shuffle_ps(o, o, _MM_SHUFFLE(0, 0, 0, 0)), oy = _mm_shuffle_ps(o, o, _MM_SHUFFLE(1, 1, 1, 1)),
                 oz = _mm_shuffle_ps(o, o, _MM_SHUFFLE(2, 2, 2, 2));
    const __m128 plusMinus = _mm_setr_ps(1.0f, -1.0f, 1.0f, -1.0f);
    const __m128 xOff = _mm_movelh_ps(_mm_mul_ps(ox, plusMinus), zero);  // +ox -ox 0 0
    const __m128 yOff = _mm_movelh_ps(zero, _mm_mul_ps(oy, plusMinus));  // 0 0 +oy -oy
    alignas(16) float a[4], b[4];
    at4(_mm_add_ps(px, xOff), _mm_add_ps(py, yOff), pz, a);
    at4(px, py, _mm_add_ps(pz, _mm_mul_ps(oz, plusMinus)), b);
    return Vec3f(a[0] - a[1], a[2] - a[3], b[0] - b[1]);
  }
  /// at() of four points (lanes: x, y, z of point l in lane l of each) by trilinear interpolation, into out[4]:
  /// the same single-precision operations per point, so the same values; the 32 reads issued together.
  void at4(__m128 x, __m128 y, __m128 z, float out[4]) const {
    const __m128 zero = _mm_setzero_ps();
    x = _mm_min_ps(_mm_max_ps(x, zero), hi4[0]);
    y = _mm_min_ps(_mm_max_ps(y, zero), hi4[1]);
    z = _mm_min_ps(_mm_max_ps(z, zero), hi4[2]);
    const __m128i ix = _mm_cvttps_epi32(_mm_min_ps(x, lastCell4[0]));
    const __m128i iy = _mm_cvttps_epi32(_mm_min_ps(y, lastCell4[1]));
    const __m128i iz = _mm_cvttps_epi32(_mm_min_ps(z, lastCell4[2]));
    const __m128 fx = _mm_sub_ps(x, _mm_cvtepi32_ps(ix)), fy = _mm_sub_ps(y, _mm_cvtepi32_ps(iy)),
                 fz = _mm_sub_ps(z, _mm_cvtepi32_ps(iz));
    alignas(16) int32_t I[3][4];
    _mm_store_si128(reinterpret_cast<__m128i*>(I[0]), ix);
    _mm_store_si128(reinterpret_cast<__m128i*>(I[1]), iy);
    _mm_store_si128(reinterpret_cast<__m128i*>(I[2]), iz);
    const float* c[4];
    for (int l = 0; l < 4; ++l)
      c[l] = s + std::size_t(uint32_t(I[2][l])) * sz + std::size_t(uint32_t(I[1][l])) * sy + std::size_t(uint32_t(I[0][l]));
    // The x edge at offset off of the four cells: its first and second points across the four points, lerped by fx
    auto edge = [&](std::size_t off) __attribute__((always_inline)) {
      const __m128 q01 = _mm_unpacklo_ps(pair(c[0] + off), pair(c[1] + off));  // a0 a1 b0 b1
      const __m128 q23 = _mm_unpacklo_ps(pair(c[2] + off), pair(c[3] + off));
      const __m128 a = _mm_movelh_ps(q01, q23), b = _mm_movehl_ps(q23, q01);
      return _mm_add_ps(a, _mm_mul_ps(fx, _mm_sub_ps(b, a)));
    };
    const __m128 c00 = edge(0), c10 = edge(sy), c01 = edge(sz), c11 = edge(sz + sy);
    const __m128 c0 = _mm_add_ps(c00, _mm_mul_ps(fy, _mm_sub_ps(c10, c00)));
    const __m128 c1 = _mm_add_ps(c01, _mm_mul_ps(fy, _mm_sub_ps(c11, c01)));
    _mm_storeu_ps(out, _mm_add_ps(c0, _mm_mul_ps(fz, _mm_sub_ps(c1, c0))));
  }
  /// The two floats at q (one 8-byte load) in lanes 0 and 1.
  static __m128 pair(const float* q) {
    return _mm_castsi128_ps(_mm_loadl_epi64(reinterpret_cast<const __m128i*>(q)));  // (movq: no alignment needed)
  }
  /// For four scalars v: the mask of those that may have an opacity above 0 or are NaN (the others are transparent
  /// by the table: their entries and the next are 0, so is the lerp), and each one's table entry i[l] and weight
  /// f[l] (tableIndex's operations and the march's conversions, per lane).
  unsigned mayAdd4(const float v[4], int32_t i[4], float f[4]) const {
    const __m128 s4 = _mm_loadu_ps(v);
    __m128 x = _mm_mul_ps(_mm_sub_ps(s4, _mm_set1_ps(tableMin)), _mm_set1_ps(tableScale));
    x = _mm_min_ps(_mm_max_ps(x, _mm_setzero_ps()), _mm_set1_ps(tableLast));
    const __m128i xi = _mm_cvttps_epi32(x);
    _mm_storeu_si128(reinterpret_cast<__m128i*>(i), xi);
    _mm_storeu_ps(f, _mm_sub_ps(x, _mm_cvtepi32_ps(xi)));
    const __m128 inside = _mm_and_ps(_mm_cmpge_ps(x, opaqueLo), _mm_cmplt_ps(x, opaqueHi));
    return unsigned(_mm_movemask_ps(_mm_or_ps(inside, _mm_cmpunord_ps(s4, s4))));
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

namespace {

/// A full step's alpha a at 2^scale times the step: 1 - (1 - a)^(2^scale), by squaring (scale 1: a (2 - a)) or
/// by square roots (1 - sqrt(1 - a) = a / (1 + sqrt(1 - a)), without the cancellation for a small a).
inline float scaledAlpha(float a, int scale) {
  if (scale > 0) {
    for (int k = 0; k < scale; ++k) a = a * (2.0f - a);
    return a;
  }
  for (int k = 0; k < -scale; ++k) a = a / (1.0f + std::sqrt(std::max(0.0f, 1.0f - a)));
  return a;
}

}  // namespace

void Volume::march(const Ray& ray, double t0, double t1, bool emission, float stopBelow, VolumeMarch& acc,
                   const VolumeLighting& lighting, int stepScale) const {
  stepScale = std::max(stepScale, finestScale_);
  // Shading or gradient opacity read each sample's gradient: their own instance of the march (the plain one stays
  // as tight as without them); so does a scaled step
  if ((transfer.shade && emission) || !transfer.gradientOpacity.empty()) {
    const VolumeShader shader(*this, ray, lighting, emission);
    if (stepScale != 0)
      marchWith<true, true>(ray, t0, t1, emission, stopBelow, acc, &shader, stepScale);
    else
      marchWith<true, false>(ray, t0, t1, emission, stopBelow, acc, &shader, 0);
  } else if (stepScale != 0) {
    marchWith<false, true>(ray, t0, t1, emission, stopBelow, acc, nullptr, stepScale);
  } else {
    marchWith<false, false>(ray, t0, t1, emission, stopBelow, acc, nullptr, 0);
  }
}

template <bool Shaded, bool Scaled>
void Volume::marchWith(const Ray& ray, double t0, double t1, bool emission, float stopBelow, VolumeMarch& acc,
                       const VolumeShader* shader, int stepScale) const {
  const double len = glm::length(lengthMetric * ray.dir);
  if (!(t1 > t0) || !(len > 0.0)) return;
  const Vec3 o = toIndex_ * (ray.origin - grid.origin);
  const Vec3 d = toIndex_ * ray.dir;
  const double dt = (Scaled ? std::ldexp(step_, stepScale) : step_) / len;
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
  // The parameter from the entry to step k's middle: (k + 1/2) dt for a full step (in float), the middle of
  // [t0 + k dt, t1] for a step ending at t1
  auto middle = [&](int64_t k) {
    return k < fullEnd ? (float(k) + 0.5f) * dtF : float(0.5 * (t0 + double(k) * dt + t1) - t0);
  };
  // Accumulated in locals, stored once at the end
  __m128 color4 = _mm_setr_ps(acc.color.r, acc.color.g, acc.color.b, 0.0f);
  float transmittance = acc.transmittance;
  uint64_t samples = 0, invalid = 0;
  bool terminated = false;
  // Colour of the entries a, b lerped by f, the three channels at once (lane 3: opacity's, unused)
  auto lerpColor = [](const Entry& a, const Entry& b, float f) __attribute__((always_inline)) {
    static_assert(offsetof(Entry, opacity) == 3 * sizeof(float), "colour, then opacity: one 16-byte load");
    const __m128 ca = _mm_loadu_ps(&a.color.r), cb = _mm_loadu_ps(&b.color.r);
    return _mm_add_ps(ca, _mm_mul_ps(_mm_set1_ps(f), _mm_sub_ps(cb, ca)));
  };
  // The colour c of the sample at parameter m after the entry, with central differences g, lit (Shaded only)
  auto shade = [&](const Vec3f& g, float m, __m128 c) {
    alignas(16) float rgb[4];
    _mm_store_ps(rgb, c);
    const Color lit = shader->shade(g, ray.origin + (t0 + double(m)) * ray.dir, Color(rgb[0], rgb[1], rgb[2]));
    return _mm_setr_ps(lit.r, lit.g, lit.b, 0.0f);
  };
  // Adds the sample whose table entry is i, weight f (Sampler::tableIndex), at a step's middle m (parameter after
  // the entry), with alpha from the table (full) or for length h (in ray parameter units); returns false once the
  // transmittance falls below stopBelow
  auto addEntry = [&](int i, float f, bool full, double h, float m) __attribute__((always_inline)) {
    const Entry &ea = smp.table[i], &eb = smp.table[i + 1];  // (the last entry is repeated: i + 1 is in the table)
    // Opacity first (most samples of a partly transparent cell have none)
    const float opacity = ea.opacity + f * (eb.opacity - ea.opacity);
    if (opacity <= 0.0f) return true;
    // 1 - (1 - a)^(h / unitDistance), from the table for a full step; a = 1 gives log1p(-1) = -inf and alpha 1
    float alpha = full ? ea.alphaStep + f * (eb.alphaStep - ea.alphaStep)
                       : float(-std::expm1(std::log1p(-double(opacity)) * h * perUnit));
    if constexpr (Scaled) {
      if (full) alpha = scaledAlpha(alpha, stepScale);
    }
    if constexpr (Shaded) {
      // Alpha times the gradient opacity, the colour lit (shadow rays: transmittance only)
      const Vec3f g = smp.gradient(at(m));
      alpha *= shader->opacityFactor(g);
      if (emission) color4 = _mm_add_ps(color4, _mm_mul_ps(_mm_set1_ps(transmittance * alpha),
                                                           shade(g, m, lerpColor(ea, eb, f))));
    } else if (emission) {  // color += (transmittance alpha) (ea.color + f (eb.color - ea.color)), the three at once
      color4 = _mm_add_ps(color4, _mm_mul_ps(_mm_set1_ps(transmittance * alpha), lerpColor(ea, eb, f)));
    }
    transmittance *= 1.0f - alpha;
    return transmittance >= stopBelow;
  };
  // Adds scalar s sampled at a step's middle (addEntry)
  auto add = [&](float s, bool full, double h, float m) __attribute__((always_inline)) {
    ++samples;
    if (std::isnan(s)) {
      ++invalid;
      return true;
    }
    const float x = smp.tableIndex(s);
    const int i = int(x);  // (x in [0, kTableSize - 1]: an int conversion, cheaper than one to size_t)
    return addEntry(i, x - float(i), full, h, m);
  };
  // Four full steps' points at once (trilinear): x, y, z across the steps k .. k + 3
  const __m128 ex4 = _mm_set1_ps(float(entry.x)), ey4 = _mm_set1_ps(float(entry.y)), ez4 = _mm_set1_ps(float(entry.z));
  const __m128 dx4 = _mm_set1_ps(float(d.x)), dy4 = _mm_set1_ps(float(d.y)), dz4 = _mm_set1_ps(float(d.z));
  const __m128 dt4 = _mm_set1_ps(dtF), lanes = _mm_setr_ps(0.5f, 1.5f, 2.5f, 3.5f);
  const bool four = !smp.nearest;
  const CellLook look(*this, o, d, t0, dt);
  // Runs of steps sampled without looking at macro cells: without skipping, all of them; with it, the steps of a
  // run of non-empty cells (CellLook::lastInsideRun), or, after an empty cell's steps are skipped, the one step the
  // skip lands on (about at the exit)
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
    if (four) {
      for (; k + 4 <= fullStop && !terminated; k += 4) {
        // h = middle(k + l) per lane: (float(k) + l + 0.5f) dt, float(k) + l exact (k < 2^24)
        const __m128 h = _mm_mul_ps(_mm_add_ps(_mm_set1_ps(float(k)), lanes), dt4);
        alignas(16) float v[4];
        smp.at4(_mm_add_ps(ex4, _mm_mul_ps(h, dx4)), _mm_add_ps(ey4, _mm_mul_ps(h, dy4)),
                _mm_add_ps(ez4, _mm_mul_ps(h, dz4)), v);
        alignas(16) int32_t i[4];
        alignas(16) float f[4];
        const unsigned may = smp.mayAdd4(v, i, f);
        if (may == 0) {  // four transparent samples
          samples += 4;
          continue;
        }
        for (int l = 0; l < 4; ++l) {
          ++samples;
          if (!(may >> l & 1)) continue;  // transparent
          if (std::isnan(v[l])) {
            ++invalid;
            continue;
          }
          if (!addEntry(i[l], f[l], true, 0.0, (float(k) + (float(l) + 0.5f)) * dtF)) {
            terminated = true;
            break;
          }
        }
      }
      if (terminated) break;
    }
    for (; k < fullStop; ++k) {
      const float m = middle(k);
      if (!add(smp.at(at(m)), true, 0.0, m)) {
        terminated = true;
        break;
      }
    }
    // The steps ending at t1
    for (; k < runEnd && !terminated; ++k) {
      const double ta = t0 + double(k) * dt;
      if (!(t1 > ta)) continue;
      const float m = middle(k);
      if (!add(smp.at(at(m)), false, t1 - ta, m)) terminated = true;
    }
  }
  alignas(16) float rgb[4];
  _mm_store_ps(rgb, color4);
  acc.color = Color(rgb[0], rgb[1], rgb[2]);
  acc.transmittance = transmittance;
  acc.samples += samples;
  acc.invalidSamples += invalid;
  acc.terminated = acc.terminated || terminated;
}

}  // namespace whitted
