// Single-precision boxes for the BVH builders and refit (private to accel/*.cpp): Box4 (x y z in SSE lanes), the
// outward rounding of double boxes to float (node boxes stay conservative for any double ray), and writing a box
// into a wide node's child slot.
#pragma once

#include "accel/bvh_node.h"
#include "util/math.h"

#include <emmintrin.h>

#include <cmath>
#include <cstdint>
#include <limits>

namespace whitted::bvh_detail {

constexpr float kInf = std::numeric_limits<float>::infinity();

// Node bounds are stored as floats stepped one ulp outward (always, not only when rounding went inward), so a
// ray grazing a face with a tiny slope still enters the node: roundDown(x) is the largest float below x, roundUp(x)
// the smallest above. Both are monotonic, so the rounded union of boxes equals the union of the rounded boxes:
// primitives are rounded once and all unions are taken in float.

inline __m128 select(__m128 mask, __m128 a, __m128 b) {
  return _mm_or_ps(_mm_and_ps(mask, a), _mm_andnot_ps(mask, b));
}

/// The next float toward -infinity, per lane (NaN and -infinity stay, zero goes to -denorm_min).
inline __m128 nextDown4(__m128 f) {
  const __m128 zero = _mm_setzero_ps();
  const __m128i pos = _mm_castps_si128(_mm_cmpgt_ps(f, zero));
  const __m128i neg = _mm_castps_si128(_mm_andnot_ps(_mm_cmpeq_ps(f, _mm_set1_ps(-kInf)), _mm_cmplt_ps(f, zero)));
  const __m128i u = _mm_sub_epi32(_mm_add_epi32(_mm_castps_si128(f), pos), neg);  // positive: -1 ulp, negative: +1
  return select(_mm_cmpeq_ps(f, zero), _mm_castsi128_ps(_mm_set1_epi32(int32_t(0x80000001u))), _mm_castsi128_ps(u));
}

/// roundDown() of four doubles (lanes 0, 1 from x01, lanes 2, 3 from x23): the nearest float, one step down
/// unless it is already below. NaN stays NaN.
inline __m128 roundDown4(__m128d x01, __m128d x23) {
  const __m128 f = _mm_movelh_ps(_mm_cvtpd_ps(x01), _mm_cvtpd_ps(x23));
  const __m128d ge01 = _mm_cmpge_pd(_mm_cvtps_pd(f), x01), ge23 = _mm_cmpge_pd(_mm_cvtps_pd(_mm_movehl_ps(f, f)), x23);
  return select(_mm_shuffle_ps(_mm_castpd_ps(ge01), _mm_castpd_ps(ge23), _MM_SHUFFLE(2, 0, 2, 0)), nextDown4(f), f);
}

/// roundUp() of four doubles: -roundDown(-x).
inline __m128 roundUp4(__m128d x01, __m128d x23) {
  const __m128d sign = _mm_set1_pd(-0.0);
  return _mm_xor_ps(roundDown4(_mm_xor_pd(x01, sign), _mm_xor_pd(x23, sign)), _mm_set1_ps(-0.0f));
}

/// Lanes 0..2 kept, lane 3 zeroed.
inline __m128 xyz(__m128 v) {
  return _mm_and_ps(v, _mm_castsi128_ps(_mm_set_epi32(0, -1, -1, -1)));
}

/// Box in single precision, x y z in lanes 0..2 (lane 3 unused).
struct Box4 {
  __m128 lo = _mm_set1_ps(kInf), hi = _mm_set1_ps(-kInf);
  void extend(__m128 l, __m128 h) {
    lo = _mm_min_ps(lo, l);
    hi = _mm_max_ps(hi, h);
  }
  void extend(const Box4& b) { extend(b.lo, b.hi); }
};

/// Lane i of v.
inline float lane(__m128 v, int i) {
  alignas(16) float f[4];
  _mm_store_ps(f, v);
  return f[i];
}

/// Half surface area in double (the collapse order and the leaf-or-split decision use it).
inline double halfArea(const Box4& b) {
  alignas(16) float lo[4], hi[4];
  _mm_store_ps(lo, b.lo);
  _mm_store_ps(hi, b.hi);
  const double dx = double(hi[0]) - lo[0], dy = double(hi[1]) - lo[1], dz = double(hi[2]) - lo[2];
  return dx * dy + dy * dz + dz * dx;
}

/// Writes b as child c's box of wide node w.
inline void setChildBox(BvhWideNode& w, int c, const Box4& b) {
  alignas(16) float lo[4], hi[4];
  _mm_store_ps(lo, b.lo);
  _mm_store_ps(hi, b.hi);
  for (int k = 0; k < 3; ++k) {
    w.b[k][c] = lo[k];
    w.b[3 + k][c] = hi[k];
  }
}

/// A primitive's box relative to the tree's anchor, rounded outward to float. The subtraction rounds once, and
/// roundDown / roundUp step strictly outward (at least one double ulp), so the float box contains the exact one.
inline Box4 roundedBox(const Bounds3& b, const Vec3& anchor) {
  static_assert(sizeof(Bounds3) == 6 * sizeof(double), "lo.x lo.y lo.z hi.x hi.y hi.z");
  const double* d = &b.lo.x;
  const __m128d aXY = _mm_loadu_pd(&anchor.x), aZX = _mm_set_pd(anchor.x, anchor.z),
                aYZ = _mm_set_pd(anchor.z, anchor.y);
  // d0 = lo.x lo.y, d1 = lo.z hi.x, d2 = hi.y hi.z
  const __m128d d0 = _mm_sub_pd(_mm_loadu_pd(d), aXY), d1 = _mm_sub_pd(_mm_loadu_pd(d + 2), aZX),
                d2 = _mm_sub_pd(_mm_loadu_pd(d + 4), aYZ);
  Box4 r;
  r.lo = xyz(roundDown4(d0, d1));                                            // lo.x lo.y | lo.z (hi.x)
  r.hi = xyz(roundUp4(_mm_shuffle_pd(d1, d2, 1), _mm_unpackhi_pd(d2, d2)));  // hi.x hi.y | hi.z
  return r;
}

/// An anchored float box back in input coordinates, stepped outward over the addition's rounding.
inline Bounds3 toBounds(const Box4& b, const Vec3& anchor) {
  Bounds3 r;
  for (int k = 0; k < 3; ++k) {
    r.lo[k] = std::nextafter(double(lane(b.lo, k)) + anchor[k], -kInfinity);
    r.hi[k] = std::nextafter(double(lane(b.hi, k)) + anchor[k], kInfinity);
  }
  return r;
}

}  // namespace whitted::bvh_detail
