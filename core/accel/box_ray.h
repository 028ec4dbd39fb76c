// Conservative single-precision box tests of a BVH's 4-wide nodes for double-precision rays: BoxRay (one ray) and
// JointBoxRay (one test for a packet of close rays). Used by the traversals (bvh_traverse.h,
// bvh_traverse_packet.h).
#pragma once

#include "accel/bvh_node.h"
#include "util/math.h"

#include <emmintrin.h>  // SSE2: part of every x86-64 CPU (Debian 12's baseline)

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <limits>

namespace whitted {

/// A ray prepared for the single-precision box tests of one tree: origin relative to the tree's anchor and
/// direction scaled by a power of two (so t' = t * tScale exactly), each rounded so that every computed entry
/// distance is at most, and every exit distance at least, the exact one of the double-precision ray (Embree's
/// robust mode, extended to a double ray): per axis the origin is rounded up for one plane and down for the other,
/// and the reciprocal direction toward zero for the near plane and away from zero for the far plane, by margins
/// that cover the float subtraction's and product's rounding (2^-24 each). Overflow stays conservative: a near
/// reciprocal saturates at FLT_MAX, a far one may be infinite, and an origin beyond float range becomes +-FLT_MAX
/// or +-inf on the conservative side. A NaN far product (0 * inf: an origin on a face plane of a parallel ray) is
/// ignored by the slab test, which keeps such a ray (conservative). Computed for the three axes at once (SSE2).
/// Which of a wide node's planes a ray meets first and last per axis, by the signs of its direction.
struct BoxRayPlanes {
  int nearBound[3], farBound[3];  ///< Index into BvhWideNode::b of the near / far plane per axis.
  /// The same as byte offsets into a BvhWideNode (the single-ray loop adds them to the node's address).
  std::size_t nearOffset[3], farOffset[3];
};

/// BoxRayPlanes for the direction signs negative (bit k: the direction is negative along axis k): lo first for a
/// positive direction, hi first for a negative one.
constexpr BoxRayPlanes boxRayPlanes(int negative) {
  BoxRayPlanes p{};
  for (int k = 0; k < 3; ++k) {
    p.nearBound[k] = (negative >> k) & 1 ? 3 + k : k;
    p.farBound[k] = (negative >> k) & 1 ? k : 3 + k;
    p.nearOffset[k] = offsetof(BvhWideNode, b) + std::size_t(p.nearBound[k]) * sizeof(BvhWideNode::b[0]);
    p.farOffset[k] = offsetof(BvhWideNode, b) + std::size_t(p.farBound[k]) * sizeof(BvhWideNode::b[0]);
  }
  return p;
}
/// The eight sign patterns' planes, looked up per ray (one 72-byte copy instead of computing twelve values).
inline constexpr BoxRayPlanes kBoxRayPlanes[8] = {boxRayPlanes(0), boxRayPlanes(1), boxRayPlanes(2), boxRayPlanes(3),
                                                  boxRayPlanes(4), boxRayPlanes(5), boxRayPlanes(6), boxRayPlanes(7)};

struct BoxRay : BoxRayPlanes {
  __m128 orgNear[3], orgFar[3], invNear[3], invFar[3];
  double tScale = 1.0;  ///< Box-test distances are t * tScale.
  /// False when every origin coordinate is a float (not +-inf): then an empty child slot (box lo = +inf, hi = -inf)
  /// never passes the slab test (its near distance is +inf, its far one -inf), and its mask needs no used().
  bool emptyMayPass = true;
  BoxRay() = default;  ///< Unset (the lanes of a packet's inactive rays).
  /// Slab test of wide node n's four boxes against [t0, t1] (box-test units): t0 becomes each box's entry distance
  /// (at most the exact one); returns the mask of the boxes entered (AND it with n.used() when emptyMayPass: empty
  /// slots may pass then).
  unsigned enter(const BvhWideNode& n, __m128& t0, __m128 t1) const {
    const char* node = reinterpret_cast<const char*>(&n);
    for (int a = 0; a < 3; ++a) {
      const __m128 lo = _mm_mul_ps(
          _mm_sub_ps(_mm_load_ps(reinterpret_cast<const float*>(node + nearOffset[a])), orgNear[a]), invNear[a]);
      const __m128 hi = _mm_mul_ps(
          _mm_sub_ps(_mm_load_ps(reinterpret_cast<const float*>(node + farOffset[a])), orgFar[a]), invFar[a]);
      // The far product's NaN (0 * inf: an origin on the far plane of a parallel ray; inf - inf: an infinite
      // plane and an origin beyond float range) is ignored: min(hi, t1) returns t1 for a NaN hi. A near
      // product is never NaN for a real box (its lo is never +inf nor its hi -inf, and the rounded origin
      // never goes past +-FLT_MAX toward them); max(t0, lo) would return a NaN and reject the child.
      t0 = _mm_max_ps(t0, lo);
      t1 = _mm_min_ps(hi, t1);
    }
    return unsigned(_mm_movemask_ps(_mm_cmple_ps(t0, t1)));
  }
  BoxRay(const Ray& r, const Vec3& anchor) { set(r, anchor); }
  /// Sets this ray up in place (a packet's lanes: no temporary of the whole struct to copy).
  void set(const Ray& r, const Vec3& anchor) {
    // Power-of-two scale bringing the largest direction component into [1, 2) (exact, keeps t' in float range)
    // (exponent bits of the largest component; callers pass finite directions)
    const double m = std::max(std::abs(r.dir.x), std::max(std::abs(r.dir.y), std::abs(r.dir.z)));
    uint64_t bits;
    std::memcpy(&bits, &m, sizeof bits);
    const int biased = int(bits >> 52);  // 0 for zero and subnormal components: no scaling then
    const int e = biased == 0 ? 0 : std::min(biased - 1023, 1022);
    const uint64_t sBits = uint64_t(1023 - e) << 52, tBits = uint64_t(1023 + e) << 52;
    double s;  // d' = d * s = d * 2^-e, and t' = t * 2^e
    std::memcpy(&s, &sBits, sizeof s);
    std::memcpy(&tScale, &tBits, sizeof tScale);
    // Three axes at once (SSE2), branch-free: lanes x, y, z (lane 3 unused)
    const __m128d sV = _mm_set1_pd(s);
    const __m128d dXY = _mm_mul_pd(_mm_loadu_pd(&r.dir.x), sV), dZ = _mm_mul_sd(_mm_load_sd(&r.dir.z), sV);
    // The origin relative to the anchor, rounded to the nearest float f, then stepped out by |f| 2^-22 (at least
    // 1.5 ulp of f after the step's own rounding: more than the nearest rounding's 0.5 ulp plus the subtraction's
    // one double rounding) plus FLT_MIN (zero and denormals). Beyond float range: +-inf on the outer side,
    // +-FLT_MAX on the inner one (a NaN from inf - inf is replaced by the clamp: min/max return the bound).
    const __m128 o = _mm_movelh_ps(_mm_cvtpd_ps(_mm_sub_pd(_mm_loadu_pd(&r.origin.x), _mm_loadu_pd(&anchor.x))),
                                   _mm_cvtpd_ps(_mm_sub_sd(_mm_load_sd(&r.origin.z), _mm_load_sd(&anchor.z))));
    const __m128 signBit = _mm_set1_ps(-0.0f), fltMax = _mm_set1_ps(std::numeric_limits<float>::max());
    const __m128 step = _mm_add_ps(_mm_mul_ps(_mm_andnot_ps(signBit, o), _mm_set1_ps(0x1p-22f)),
                                   _mm_set1_ps(std::numeric_limits<float>::min()));
    const __m128 up = _mm_max_ps(_mm_add_ps(o, step), _mm_xor_ps(fltMax, signBit));
    const __m128 down = _mm_min_ps(_mm_sub_ps(o, step), fltMax);
    // Reciprocals (1 / +-0 = +-inf), magnitudes shrunk / grown by 2^-19 before the float conversion, whose
    // rounding (2^-24) leaves more than the 2^-23 that the float subtraction and product need. The near one
    // saturates at FLT_MAX, the far one may overflow to inf.
    const __m128d one = _mm_set1_pd(1.0), signD = _mm_set1_pd(-0.0);
    const __m128d invXY = _mm_div_pd(one, dXY), invZ = _mm_div_sd(one, dZ);
    const __m128d absXY = _mm_andnot_pd(signD, invXY), absZ = _mm_andnot_pd(signD, invZ);
    const __m128d shrink = _mm_set1_pd(1.0 - 0x1p-19), grow = _mm_set1_pd(1.0 + 0x1p-19);
    const __m128d maxD = _mm_set1_pd(double(std::numeric_limits<float>::max()));
    const __m128 nearMag = _mm_movelh_ps(_mm_cvtpd_ps(_mm_min_pd(_mm_mul_pd(absXY, shrink), maxD)),
                                         _mm_cvtpd_ps(_mm_min_pd(_mm_mul_pd(absZ, shrink), maxD)));
    const __m128 farMag = _mm_movelh_ps(_mm_cvtpd_ps(_mm_mul_pd(absXY, grow)), _mm_cvtpd_ps(_mm_mul_pd(absZ, grow)));
    // Direction signs (of d, -0 included) per lane, as a float sign bit and as an all-ones mask
    const __m128 dSign = _mm_and_ps(_mm_movelh_ps(_mm_cvtpd_ps(dXY), _mm_cvtpd_ps(dZ)), signBit);
    const __m128 negMask = _mm_castsi128_ps(_mm_srai_epi32(_mm_castps_si128(dSign), 31));
    // Near plane: lo for a positive direction (origin rounded up), hi for a negative one (rounded down)
    const __m128 nearOrg = _mm_or_ps(_mm_and_ps(negMask, down), _mm_andnot_ps(negMask, up));
    const __m128 farOrg = _mm_or_ps(_mm_and_ps(negMask, up), _mm_andnot_ps(negMask, down));
    const __m128 nearInv = _mm_or_ps(nearMag, dSign), farInv = _mm_or_ps(farMag, dSign);
    const int negative = _mm_movemask_ps(negMask);
    alignas(16) float lanes[4][4];  // near origin, far origin, near reciprocal, far reciprocal
    _mm_store_ps(lanes[0], nearOrg);
    _mm_store_ps(lanes[1], farOrg);
    _mm_store_ps(lanes[2], nearInv);
    _mm_store_ps(lanes[3], farInv);
    for (int k = 0; k < 3; ++k) {  // broadcast per axis for the four-box test
      orgNear[k] = _mm_set1_ps(lanes[0][k]);
      orgFar[k] = _mm_set1_ps(lanes[1][k]);
      invNear[k] = _mm_set1_ps(lanes[2][k]);
      invFar[k] = _mm_set1_ps(lanes[3][k]);
    }
    static_cast<BoxRayPlanes&>(*this) = kBoxRayPlanes[negative & 7];
    // Rounded origins beyond float range are +-inf (up, down): the empty-slot masks are needed then
    const __m128 infinite = _mm_cmpeq_ps(_mm_max_ps(_mm_andnot_ps(signBit, up), _mm_andnot_ps(signBit, down)),
                                         _mm_set1_ps(std::numeric_limits<float>::infinity()));
    emptyMayPass = (_mm_movemask_ps(infinite) & 7) != 0;
  }
};

/// One conservative box test for a packet of rays (Bvh::traverseAny4): per axis the range of the rays' rounded
/// origins and reciprocals (BoxRay), usable when the rays share their direction signs and scale and all are finite.
/// The rounding of a float subtraction and product is monotonic, so the smallest computed near distance over the
/// ranges' corners is at most every ray's computed near distance (itself at most the exact one), and the largest
/// far distance at least every ray's far distance: a child any ray's own test enters is entered by the joint test.
/// Per axis with a positive direction the near distance (lo - o) * inv is smallest at the largest origin, the far
/// distance at the smallest (mirrored for a negative direction); the reciprocal's corner depends on the sign of
/// the difference, so both are taken.
struct JointBoxRay {
  bool valid = false;
  __m128 orgNear[3], orgFar[3], invLo[3], invHi[3], invFarLo[3], invFarHi[3], tMin, tMax;
  int nearBound[3], farBound[3];
  /// maxSpread: the largest origin spread (per axis, in the tree's units) for which the joint test is used; rays
  /// further apart (neighbouring pixels on different surfaces, a block across a silhouette) enter many more
  /// children together than alone, and keep their own tests. Reciprocals spreading by more than 1/8 of their
  /// magnitude (a point light close to the surface) likewise.
  JointBoxRay(const BoxRay* br, const __m128* tMinV, const __m128* tMaxV, unsigned active, float maxSpread) {
    const int f = __builtin_ctz(active);
    for (unsigned m = active; m; m &= m - 1) {
      const int i = __builtin_ctz(m);
      if (br[i].tScale != br[f].tScale) return;
      for (int a = 0; a < 3; ++a)
        if (br[i].nearBound[a] != br[f].nearBound[a]) return;
    }
    const __m128 finiteMax = _mm_set1_ps(std::numeric_limits<float>::max());
    const __m128 signBit = _mm_set1_ps(-0.0f);
    tMin = tMinV[f];
    tMax = tMaxV[f];
    for (int a = 0; a < 3; ++a) {
      const bool negative = br[f].nearBound[a] >= 3;
      __m128 oNearLo = br[f].orgNear[a], oNearHi = oNearLo, oFarLo = br[f].orgFar[a], oFarHi = oFarLo;
      __m128 nLo = br[f].invNear[a], nHi = nLo, fLo = br[f].invFar[a], fHi = fLo;
      __m128 finite = _mm_set1_ps(-1.0f);  // all ones while every value is finite
      for (unsigned m = active; m; m &= m - 1) {
        const BoxRay& r = br[__builtin_ctz(m)];
        oNearLo = _mm_min_ps(oNearLo, r.orgNear[a]), oNearHi = _mm_max_ps(oNearHi, r.orgNear[a]);
        oFarLo = _mm_min_ps(oFarLo, r.orgFar[a]), oFarHi = _mm_max_ps(oFarHi, r.orgFar[a]);
        nLo = _mm_min_ps(nLo, r.invNear[a]), nHi = _mm_max_ps(nHi, r.invNear[a]);
        fLo = _mm_min_ps(fLo, r.invFar[a]), fHi = _mm_max_ps(fHi, r.invFar[a]);
        for (__m128 v : {r.orgNear[a], r.orgFar[a], r.invNear[a], r.invFar[a]})
          finite = _mm_and_ps(finite, _mm_cmple_ps(_mm_andnot_ps(signBit, v), finiteMax));
      }
      if (_mm_movemask_ps(finite) != 0xf) return;  // infinite or NaN values: the rays' own tests
      const float spread =
          std::max(_mm_cvtss_f32(_mm_sub_ps(oNearHi, oNearLo)), _mm_cvtss_f32(_mm_sub_ps(oFarHi, oFarLo)));
      const float invSpread = _mm_cvtss_f32(_mm_max_ps(_mm_sub_ps(nHi, nLo), _mm_sub_ps(fHi, fLo)));
      if (!(spread <= maxSpread) || !(invSpread <= 0.125f * std::abs(_mm_cvtss_f32(nLo)))) return;
      orgNear[a] = negative ? oNearLo : oNearHi;
      orgFar[a] = negative ? oFarHi : oFarLo;
      invLo[a] = nLo, invHi[a] = nHi, invFarLo[a] = fLo, invFarHi[a] = fHi;
      nearBound[a] = br[f].nearBound[a];
      farBound[a] = br[f].farBound[a];
    }
    for (unsigned m = active; m; m &= m - 1) {
      tMin = _mm_min_ps(tMin, tMinV[__builtin_ctz(m)]);
      tMax = _mm_max_ps(tMax, tMaxV[__builtin_ctz(m)]);
    }
    valid = true;
  }
  /// Mask of the children of n the joint test enters (empty children not excluded).
  unsigned test(const BvhWideNode& n) const {
    __m128 t0;
    return test(n, tMax, t0);
  }
  /// The same with the far limit t1 (the largest of the rays' current ones) and t0 set to each child's joint entry
  /// distance, at most every ray's own computed one (Bvh::traverse4's stack distances).
  unsigned test(const BvhWideNode& n, __m128 t1, __m128& t0) const {
    t0 = tMin;
    for (int a = 0; a < 3; ++a) {
      const __m128 dn = _mm_sub_ps(_mm_load_ps(n.b[nearBound[a]]), orgNear[a]);
      const __m128 df = _mm_sub_ps(_mm_load_ps(n.b[farBound[a]]), orgFar[a]);
      t0 = _mm_max_ps(t0, _mm_min_ps(_mm_mul_ps(dn, invLo[a]), _mm_mul_ps(dn, invHi[a])));
      t1 = _mm_min_ps(t1, _mm_max_ps(_mm_mul_ps(df, invFarLo[a]), _mm_mul_ps(df, invFarHi[a])));
    }
    return unsigned(_mm_movemask_ps(_mm_cmple_ps(t0, t1)));
  }
};

}  // namespace whitted
