// Bounding volume hierarchy: binned SAH build from boxes and centroids (it never sees geometry) and a templated
// traversal with a leaf callback. Used for both levels: per object over its primitives, and over instances.
#pragma once

#include "util/math.h"
#include "util/memory.h"

#include <emmintrin.h>  // SSE2: part of every x86-64 CPU (Debian 12's baseline)

#include <atomic>
#include <cstddef>
#include <limits>
#include <vector>

namespace whitted {

/// 32-byte node. Bounds are single precision rounded outward (conservative for any double ray).
/// Inner node: count == 0, first = index of the left child (right child = first + 1).
/// Leaf: primitives primIndices[first .. first+count).
struct BvhNode {
  float lo[3];
  uint32_t first;
  float hi[3];
  uint32_t count;
};

/// 4-wide node, the traversal structure (collapsed from the binary SAH tree). Bounds per child in structure-of-
/// arrays order: b[k][c] is bound k (0..2 = lo x, y, z; 3..5 = hi x, y, z) of child c, single precision rounded
/// outward like the binary nodes. Child c is a leaf when count[c] > 0 (primitive slots first[c] ..
/// first[c]+count[c]), an inner node when count[c] == 0 (first[c] = wide node index), and empty when
/// count[c] == kEmpty (its box is inverted, and traversal skips it: a NaN ray passes every slab test).
struct alignas(64) BvhWideNode {  // two whole cache lines
  static constexpr uint32_t kEmpty = 0xffffffffu;
  float b[6][4];
  uint32_t first[4];
  uint32_t count[4];
  /// Mask of the slots that hold a child. Empty slots are the children whose lo.x is +inf (a real box's lo is
  /// rounded down, so never +inf even beyond float range); slab tests mask them out, since NaN exits (inf - inf)
  /// could otherwise let them through.
  unsigned used() const {
    const __m128 inf = _mm_set1_ps(std::numeric_limits<float>::infinity());
    return unsigned(_mm_movemask_ps(_mm_cmplt_ps(_mm_load_ps(b[0]), inf)));
  }
};
/// A tree's wide nodes (on huge pages when large: memory.h).
using BvhWideNodes = LargeVector<BvhWideNode>;

/// Build algorithm: the binned SAH build gives the fastest traversal; the Morton (LBVH) build takes a fraction of
/// its time for a tree that traces somewhat slower (first frames, time steps, geometry that changes every frame).
enum class BvhBuildQuality { Sah, Fast };

struct BvhBuildOptions {
  BvhBuildQuality quality = BvhBuildQuality::Sah;  ///< Default Sah.
  /// Leaves never hold more primitives than this (unless all centroids coincide); the Fast build uses at most 4.
  int maxLeafSize = 8;
  int bins = 16;  ///< SAH bins per axis (2..32); nodes under 240 primitives use 4 + count / 20. Default 16.
  double traversalCost = 1.0;  ///< SAH cost of visiting a node, relative to one primitive test.
  /// Build threads; 0 = hardwareThreads(). The tree does not depend on it. Inputs below 32768 primitives are
  /// built on the calling thread whatever this says. Default 0.
  int threads = 0;
  /// If given, polled between nodes: once it is set the build stops early and leaves an empty tree (a background
  /// build whose work is no longer wanted). Default none.
  const std::atomic<bool>* cancel = nullptr;
};

/// A ray prepared for the single-precision box tests of one tree: origin relative to the tree's anchor and
/// direction scaled by a power of two (so t' = t * tScale exactly), each rounded so that every computed entry
/// distance is at most, and every exit distance at least, the exact one of the double-precision ray (Embree's
/// robust mode, extended to a double ray): per axis the origin is rounded up for one plane and down for the other,
/// and the reciprocal direction toward zero for the near plane and away from zero for the far plane, by margins
/// that cover the float subtraction's and product's rounding (2^-24 each). Overflow stays conservative: a near
/// reciprocal saturates at FLT_MAX, a far one may be infinite, and an origin beyond float range becomes +-FLT_MAX
/// or +-inf on the conservative side. A NaN far product (0 * inf: an origin on a face plane of a parallel ray) is
/// ignored by the slab test, which keeps such a ray (conservative). Computed for the three axes at once (SSE2).
struct BoxRay {
  __m128 orgNear[3], orgFar[3], invNear[3], invFar[3];
  int nearBound[3], farBound[3];  ///< Index into BvhWideNode::b of the near / far plane per axis.
  double tScale = 1.0;            ///< Box-test distances are t * tScale.
  BoxRay() = default;             ///< Unset (the lanes of a packet's inactive rays).
  /// Slab test of wide node n's four boxes against [t0, t1] (box-test units): t0 becomes each box's entry distance
  /// (at most the exact one); returns the mask of the boxes entered (AND it with n.used(): empty slots may pass).
  unsigned enter(const BvhWideNode& n, __m128& t0, __m128 t1) const {
    for (int a = 0; a < 3; ++a) {
      const __m128 lo = _mm_mul_ps(_mm_sub_ps(_mm_load_ps(n.b[nearBound[a]]), orgNear[a]), invNear[a]);
      const __m128 hi = _mm_mul_ps(_mm_sub_ps(_mm_load_ps(n.b[farBound[a]]), orgFar[a]), invFar[a]);
      // The far product's NaN (0 * inf: an origin on the far plane of a parallel ray; inf - inf: an infinite
      // plane and an origin beyond float range) is ignored: min(hi, t1) returns t1 for a NaN hi. A near
      // product is never NaN for a real box (its lo is never +inf nor its hi -inf, and the rounded origin
      // never goes past +-FLT_MAX toward them); max(t0, lo) would return a NaN and reject the child.
      t0 = _mm_max_ps(t0, lo);
      t1 = _mm_min_ps(hi, t1);
    }
    return unsigned(_mm_movemask_ps(_mm_cmple_ps(t0, t1)));
  }
  BoxRay(const Ray& r, const Vec3& anchor) {
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
      nearBound[k] = (negative >> k) & 1 ? 3 + k : k;
      farBound[k] = (negative >> k) & 1 ? k : 3 + k;
    }
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

/// Where a tree's leaf primitives live, when they are stored in leaf order (slot k at base + k * stride): lets the
/// traversal prefetch a leaf's primitives when it decides to visit it. Default: none.
struct LeafData {
  const void* base = nullptr;
  uint32_t stride = 0;
};

class Bvh {
 public:
  /// Traversal stack size; the builder caps tree depth below it (SAH splits below depth kSahDepthLimit fall back
  /// to median splits, which add at most 32 more levels).
  static constexpr int kStackSize = 128;
  static constexpr int kSahDepthLimit = 64;
  /// Wide traversal stack: each wide level pushes at most 3 entries more than it pops.
  static constexpr int kWideStackSize = 3 * kStackSize + 1;
  /// traverseAny4 tests a packet's rays together while their origins lie within this share of the tree's extent
  /// (per axis); farther apart, each ray tests every node.
  static constexpr double kJointSpread = 1.0 / 64.0;

  /// Builds over boxes[i] with representative points centroids[i]. Empty input gives an empty tree, and so does a
  /// build cancelled through BvhBuildOptions::cancel.
  void build(const std::vector<Bounds3>& boxes, const std::vector<Vec3>& centroids, const BvhBuildOptions& opt = {}) {
    build(boxes.data(), centroids.data(), boxes.size(), opt);
  }
  /// The same over arrays the caller owns (boxes[0 .. count), centroids[0 .. count)): no copy into vectors.
  /// centroids null: the boxes' centres (Bounds3::center), the same tree as passing them.
  void build(const Bounds3* boxes, const Vec3* centroids, std::size_t count, const BvhBuildOptions& opt = {});
  /// Recomputes every node box bottom-up from new primitive boxes (same count and order as the build's), keeping
  /// the topology: for primitives that moved but stay the same primitives (time steps, deformed meshes). Boxes are
  /// rounded outward exactly as build() rounds them, so traversal stays conservative; the tree's quality decays
  /// with the motion (rebuild when it matters). Throws std::invalid_argument if the count differs.
  void refit(const std::vector<Bounds3>& boxes);
  /// refit() with the boxes in leaf order (leafBoxes[k] bounds primitive primIndices()[k]): saves the gather, for
  /// callers whose primitives are stored in leaf order.
  void refitLeafOrder(const std::vector<Bounds3>& leafBoxes);
  /// The tree's expected trace cost by the surface area heuristic, for a ray crossing the root box: every wide node
  /// entered costs one (its four box tests), every leaf entered its primitive count, each weighted by the chance
  /// area(box) / area(root box) that such a ray enters it. 0 for an empty tree or a root box without area. Compares
  /// trees over the same primitives: after refit(), the ratio to the cost at build time says how much slower the
  /// refitted tree traces (Object::refit rebuilds beyond kRefitRebuildRatio). Cost: one pass over the nodes.
  double sahCost() const;

  bool empty() const { return wide_.empty(); }
  /// The 4-wide traversal nodes; node 0 is the root, and every child node has a larger index than its parent.
  const BvhWideNodes& nodes() const { return wide_; }
  /// Primitive order of the leaves: leaf slot -> original primitive index.
  const std::vector<uint32_t>& primIndices() const { return primIndices_; }
  Bounds3 bounds() const { return bounds_; }
  std::size_t memoryBytes() const {
    return wide_.capacity() * sizeof(BvhWideNode) + primIndices_.capacity() * sizeof(uint32_t);
  }
  int depth() const { return depth_; }

  /// Visits leaves front to back. leaf(first, count, tMax) tests primitive slots [first, first+count), may
  /// shrink tMax (closest hit) and returns true if it found a hit. With AnyHit, traversal stops at the first leaf
  /// returning true. Returns whether any leaf returned true. nodesVisited (if given) counts visited wide nodes.
  /// A ray with a non-finite origin or direction visits nothing (no primitive test can hit it).
  /// Performance note: 4-wide nodes, their four boxes tested at once in single precision (one SSE register per
  /// plane), conservatively for the double ray (BoxRay); the stack carries each entry's distance, so entries
  /// behind a hit found meanwhile are dropped unvisited; fixed-size stack, no allocation, no virtual call; the
  /// callback is inlined.
  template <bool AnyHit, typename LeafFn>
  bool traverse(const Ray& ray, double& tMax, LeafFn&& leaf, uint64_t* nodesVisited = nullptr,
                LeafData leafData = {}) const {
    if (wide_.empty() || !isFinite(ray.origin) || !isFinite(ray.dir)) return false;
    // A tree that is one leaf (a one-sphere object, a small mesh): its box was tested by the level above, and the
    // leaf tests are exact, so the root's box test only costs (8% of the classic scene's instructions)
    if (isOneLeaf()) {
      if (nodesVisited) ++*nodesVisited;
      return leaf(wide_[0].first[0], wide_[0].count[0], tMax);
    }
    const BoxRay br(ray, anchor_);
    struct Entry {
      float t;  // entry distance (box-test units), at most the exact one
      uint32_t first, count;
    };
    Entry stack[kWideStackSize];
    int sp = 0;
    uint64_t visited = 0;  // counted locally, stored once (no memory write per node)
    bool hitAny = false;
    const __m128 tMinV = _mm_set1_ps(floatBelow(ray.tMin * br.tScale));
    float tMaxF = floatAbove(tMax * br.tScale);
    // The nearest entered child is visited next without a trip through the stack; the others are pushed
    Entry cur{-std::numeric_limits<float>::infinity(), 0, 0};
    for (;;) {
      ++visited;
      if (cur.count > 0) {
        if (leaf(cur.first, cur.count, tMax)) {
          hitAny = true;
          if constexpr (AnyHit) break;
          tMaxF = floatAbove(tMax * br.tScale);
        }
      } else {
        const BvhWideNode& n = wide_[cur.first];
        // Slab test of the four children at once
        __m128 t0 = tMinV;
        unsigned mask = br.enter(n, t0, _mm_set1_ps(tMaxF)) & n.used();
        alignas(16) float tNear[4];
        _mm_store_ps(tNear, t0);
        if (mask != 0) {
          int c = __builtin_ctz(mask);
          mask &= mask - 1;
          if constexpr (AnyHit) {
            // Any hit ends the query (shadow rays): no ordering, the first entered child is visited next
            for (; mask; mask &= mask - 1) {
              const int o = __builtin_ctz(mask);
              stack[sp++] = Entry{tNear[o], n.first[o], n.count[o]};
              prefetchChild(n.first[o], n.count[o], leafData);
            }
          } else if (mask != 0) {
            // Entered children by distance, nearest first; the rest are pushed farthest first
            int order[4] = {c, 0, 0, 0}, k = 1;
            for (; mask; mask &= mask - 1) {
              const int o = __builtin_ctz(mask);
              int j = k++;
              while (j > 0 && tNear[order[j - 1]] > tNear[o]) {
                order[j] = order[j - 1];
                --j;
              }
              order[j] = o;
            }
            for (int j = k - 1; j > 0; --j) {
              stack[sp++] = Entry{tNear[order[j]], n.first[order[j]], n.count[order[j]]};
              prefetchChild(n.first[order[j]], n.count[order[j]], leafData);
            }
            c = order[0];
          }
          cur = Entry{tNear[c], n.first[c], n.count[c]};
          prefetchChild(cur.first, cur.count, leafData);
          continue;
        }
      }
      // Next entry from the stack, skipping those behind a hit found since they were pushed
      do {
        if (sp == 0) goto done;
        cur = stack[--sp];
      } while (cur.t > tMaxF);
    }
  done:
    if (nodesVisited) *nodesVisited += visited;
    return hitAny;
  }

  /// Any-hit walk of up to four rays at once (shadow packets): rays[i] takes part when bit i of active is set.
  /// leaf(first, count, rays) tests primitive slots [first, first+count) for the rays of the bit mask rays and
  /// returns the mask of those it has finished (blocked, or handed elsewhere): a finished ray visits nothing more.
  /// Returns the mask of finished rays. Each ray keeps its own conservative box test (BoxRay, the same rounding as
  /// traverse()), so a ray enters every child that its single-ray walk would enter; only the order of the visits
  /// differs, which does not change any-hit results when the leaf tests are exact. nodesVisited (if given) counts
  /// visited wide nodes once per packet.
  /// Performance note: a node's boxes are loaded once for all its rays (single-ray traversal waits on memory);
  /// each ray's four-box test is the single-ray one, and the children entered by any ray carry the mask of rays
  /// that entered them.
  template <typename LeafFn>
  unsigned traverseAny4(const Ray* rays, unsigned active, LeafFn&& leaf, uint64_t* nodesVisited = nullptr,
                        LeafData leafData = {}) const {
    if (wide_.empty() || (active = finiteRays(rays, active)) == 0) return 0;
    if (isOneLeaf()) {  // see traverse()
      if (nodesVisited) ++*nodesVisited;
      return leaf(wide_[0].first[0], wide_[0].count[0], active) & active;
    }
    BoxRay br[4];
    __m128 tMinV[4], tMaxV[4];
    alignas(16) float tMaxF[4];
    const JointBoxRay joint = prepare(rays, active, nullptr, br, tMinV, tMaxV, tMaxF);
    struct Entry {
      uint32_t first, count;
      unsigned rays;
    };
    Entry stack[kWideStackSize];
    int sp = 0;
    uint64_t visited = 0;
    unsigned finished = 0;
    Entry cur{0, 0, active};
    for (;;) {
      ++visited;
      if (cur.count > 0) {
        finished |= leaf(cur.first, cur.count, cur.rays) & cur.rays;
        if (finished == active) break;
      } else {
        const BvhWideNode& n = wide_[cur.first];
        const unsigned used = n.used();
        // Per child, the rays that enter it (bit i of enter[c]). With a joint test, its inner children take all
        // the node's rays and only leaf children are tested ray by ray (a leaf's primitive tests cost more than a
        // box test); else each ray's slab test as in traverse()
        unsigned enter[4] = {0, 0, 0, 0};
        unsigned perRay = cur.rays, children = 0xfu;  // rays and children left to the per-ray tests
        if (joint.valid && (cur.rays & (cur.rays - 1))) {
          const unsigned hit = joint.test(n) & used;
          children = 0;
          for (int c = 0; c < 4; ++c) {
            if (!(hit >> c & 1)) continue;
            if (n.count[c] == 0)
              enter[c] = cur.rays;
            else
              children |= 1u << c;
          }
          if (children == 0) perRay = 0;
        }
        for (unsigned m = perRay; m; m &= m - 1) {
          const int i = __builtin_ctz(m);
          __m128 t0 = tMinV[i];
          const unsigned hit = br[i].enter(n, t0, tMaxV[i]) & used & children;
          for (int c = 0; c < 4; ++c) enter[c] |= (hit >> c & 1u) << i;
        }
        // The first entered child is visited next, the others pushed
        int next = -1;
        for (int c = 0; c < 4; ++c) {
          if (enter[c] == 0) continue;
          if (next < 0) {
            next = c;
          } else {
            stack[sp++] = Entry{n.first[c], n.count[c], enter[c]};
            prefetchChild(n.first[c], n.count[c], leafData);
          }
        }
        if (next >= 0) {
          cur = Entry{n.first[next], n.count[next], enter[next]};
          prefetchChild(cur.first, cur.count, leafData);
          continue;
        }
      }
      // Next entry from the stack, without the rays finished since it was pushed
      do {
        if (sp == 0) goto done;
        cur = stack[--sp];
        cur.rays &= ~finished;
      } while (cur.rays == 0);
    }
  done:
    if (nodesVisited) *nodesVisited += visited;
    return finished;
  }

  /// Closest-hit walk of up to four rays at once (camera-ray packets): rays[i] takes part when bit i of active is
  /// set, with its own limit tMax[i]. leaf(first, count, rays, tMax) tests primitive slots [first, first+count)
  /// for the rays of the bit mask rays, may shrink their tMax[i], and returns the mask of rays whose tMax it
  /// shrank. Returns the mask of rays for which any leaf reported a hit. Each ray keeps its own conservative box
  /// test (BoxRay, traverse()'s rounding) or the joint test, which enters every child any of its rays enters, and a
  /// child is dropped for a ray only once its entry distance (at most the ray's own computed one) lies beyond the
  /// ray's current limit: every leaf the single-ray walk tests with the ray still ahead is tested here too, in
  /// another order. The leaf tests (exact, per ray) and an order-independent choice between equal distances
  /// (closestHit's tie rule) then give the single ray's hit. nodesVisited (if given) counts visited wide nodes
  /// once per packet.
  /// Performance note: a node's boxes are loaded once for the packet; while the rays are close (JointBoxRay) one
  /// box test serves all of them for inner children, and each stack entry carries a per-ray entry distance so
  /// entries behind every ray's hit are dropped unvisited; children are visited nearest first by the joint entry
  /// distance (or the first active ray's).
  template <typename LeafFn>
  unsigned traverse4(const Ray* rays, unsigned active, double* tMax, LeafFn&& leaf, uint64_t* nodesVisited = nullptr,
                     LeafData leafData = {}) const {
    if (wide_.empty() || (active = finiteRays(rays, active)) == 0) return 0;
    if (isOneLeaf()) {  // see traverse()
      if (nodesVisited) ++*nodesVisited;
      return leaf(wide_[0].first[0], wide_[0].count[0], active, tMax) & active;
    }
    BoxRay br[4];
    __m128 tMinV[4], tMaxV[4];
    alignas(16) float tMaxF[4];  // lane i: ray i's limit (its box-test units)
    const JointBoxRay joint = prepare(rays, active, tMax, br, tMinV, tMaxV, tMaxF);
    __m128 jointTMax = joint.valid ? joint.tMax : _mm_setzero_ps();  // the largest active limit (one tScale)
    struct Entry {
      __m128 t;  // lane i: ray i's entry distance (box-test units), at most its own computed one
      uint32_t first, count;
      unsigned rays;
    };
    Entry stack[kWideStackSize];
    int sp = 0;
    uint64_t visited = 0;
    unsigned hitAny = 0;
    Entry cur{_mm_set1_ps(-std::numeric_limits<float>::infinity()), 0, 0, active};
    for (;;) {
      ++visited;
      if (cur.count > 0) {
        const unsigned shrunk = leaf(cur.first, cur.count, cur.rays, tMax) & cur.rays;
        if (shrunk) {
          hitAny |= shrunk;
          for (unsigned m = shrunk; m; m &= m - 1) {
            const int i = __builtin_ctz(m);
            tMaxF[i] = floatAbove(tMax[i] * br[i].tScale);
          }
          if (joint.valid) {
            float jm = -std::numeric_limits<float>::infinity();
            for (unsigned m = active; m; m &= m - 1) jm = std::max(jm, tMaxF[__builtin_ctz(m)]);
            jointTMax = _mm_set1_ps(jm);
          }
        }
      } else {
        const BvhWideNode& n = wide_[cur.first];
        const unsigned used = n.used();
        // Per child, the rays that enter it and their entry distances (as traverseAny4: with a joint test its
        // inner children take all the node's rays, leaf children are tested ray by ray)
        unsigned enter[4] = {0, 0, 0, 0};
        alignas(16) float tEnter[4][4];  // [child][ray]
        alignas(16) float tJoint[4];
        unsigned perRay = cur.rays, children = 0xfu;
        const bool useJoint = joint.valid && (cur.rays & (cur.rays - 1));
        if (useJoint) {
          __m128 t0;
          const unsigned hit = joint.test(n, jointTMax, t0) & used;
          _mm_store_ps(tJoint, t0);
          children = 0;
          const __m128 limits = _mm_load_ps(tMaxF);
          for (int c = 0; c < 4; ++c) {
            if (!(hit >> c & 1)) continue;
            if (n.count[c] == 0) {
              // The rays whose current limit lies beyond the joint entry distance (one tScale: comparable)
              const __m128 t = _mm_set1_ps(tJoint[c]);
              enter[c] = cur.rays & unsigned(_mm_movemask_ps(_mm_cmple_ps(t, limits)));
              _mm_store_ps(tEnter[c], t);
            } else {
              children |= 1u << c;
            }
          }
          if (children == 0) perRay = 0;
        }
        for (unsigned m = perRay; m; m &= m - 1) {
          const int i = __builtin_ctz(m);
          __m128 t0 = tMinV[i];
          const unsigned hit = br[i].enter(n, t0, _mm_set1_ps(tMaxF[i])) & used & children;
          alignas(16) float t[4];
          _mm_store_ps(t, t0);
          for (int c = 0; c < 4; ++c) {
            if (!(hit >> c & 1)) continue;
            if (enter[c] == 0) _mm_store_ps(tEnter[c], _mm_set1_ps(std::numeric_limits<float>::infinity()));
            enter[c] |= 1u << i;
            tEnter[c][i] = t[c];
          }
        }
        // Entered children nearest first by the joint entry distance (or the first ray's); the rest are pushed
        // farthest first
        const int lead = __builtin_ctz(cur.rays);
        float key[4];
        int order[4], k = 0;
        for (int c = 0; c < 4; ++c) {
          if (enter[c] == 0) continue;
          key[c] = useJoint ? tJoint[c] : tEnter[c][lead];
          int j = k++;
          while (j > 0 && key[order[j - 1]] > key[c]) {
            order[j] = order[j - 1];
            --j;
          }
          order[j] = c;
        }
        if (k > 0) {
          for (int j = k - 1; j > 0; --j) {
            const int c = order[j];
            stack[sp++] = Entry{_mm_load_ps(tEnter[c]), n.first[c], n.count[c], enter[c]};
            prefetchChild(n.first[c], n.count[c], leafData);
          }
          const int c = order[0];
          cur = Entry{_mm_load_ps(tEnter[c]), n.first[c], n.count[c], enter[c]};
          prefetchChild(cur.first, cur.count, leafData);
          continue;
        }
      }
      // Next entry from the stack, without the rays whose hit found since it was pushed lies before it
      do {
        if (sp == 0) goto done;
        cur = stack[--sp];
        cur.rays &= unsigned(_mm_movemask_ps(_mm_cmple_ps(cur.t, _mm_load_ps(tMaxF))));
      } while (cur.rays == 0);
    }
  done:
    if (nodesVisited) *nodesVisited += visited;
    return hitAny;
  }

  /// The point node coordinates are relative to: b[k][c] + anchor[k % 3] bounds child c (conservatively).
  const Vec3& anchor() const { return anchor_; }
  /// Child c's box of a node, in the tree's input coordinates (double, containing the float box exactly).
  Bounds3 childBounds(const BvhWideNode& n, int c) const {
    Bounds3 b;
    for (int k = 0; k < 3; ++k) {
      b.lo[k] = std::nextafter(double(n.b[k][c]) + anchor_[k], -kInfinity);
      b.hi[k] = std::nextafter(double(n.b[3 + k][c]) + anchor_[k], kInfinity);
    }
    return b;
  }

 private:
  /// active without the rays whose origin or direction is not finite (they visit nothing, as in traverse()).
  static unsigned finiteRays(const Ray* rays, unsigned active) {
    for (int i = 0; i < 4; ++i)
      if ((active >> i & 1) && (!isFinite(rays[i].origin) || !isFinite(rays[i].dir))) active &= ~(1u << i);
    return active;
  }
  /// A packet's per-ray box-test set-up (limits tMax[i], or each ray's tMax without it; lanes of inactive rays are
  /// 0 in tMaxF) and its joint test.
  JointBoxRay prepare(const Ray* rays, unsigned active, const double* tMax, BoxRay* br, __m128* tMinV,
                      __m128* tMaxV, float* tMaxF) const {
    for (int i = 0; i < 4; ++i) {
      tMaxF[i] = 0.0f;
      if (!(active >> i & 1)) continue;
      br[i] = BoxRay(rays[i], anchor_);
      tMinV[i] = _mm_set1_ps(floatBelow(rays[i].tMin * br[i].tScale));
      tMaxF[i] = floatAbove((tMax ? tMax[i] : rays[i].tMax) * br[i].tScale);
      tMaxV[i] = _mm_set1_ps(tMaxF[i]);
    }
    const Vec3 extent = bounds_.hi - bounds_.lo;
    return JointBoxRay(br, tMinV, tMaxV, active,
                       float(std::max(extent.x, std::max(extent.y, extent.z)) * kJointSpread));
  }
  /// The tree is one leaf: a root with a single leaf child.
  bool isOneLeaf() const {
    const BvhWideNode& root = wide_[0];
    return wide_.size() == 1 && root.count[1] == BvhWideNode::kEmpty && root.count[0] != 0 &&
           root.count[0] != BvhWideNode::kEmpty;
  }
  void clear() {  // the empty tree
    wide_.clear();
    primIndices_.clear();
    bounds_ = Bounds3();
    depth_ = 0;
  }
  /// Starts loading a child's node (both cache lines) or leaf primitives (first and last) while its siblings are
  /// visited: traversal of a large tree waits mostly on memory.
  void prefetchChild(uint32_t first, uint32_t count, const LeafData& leafData) const {
    if (count == 0) {
      const char* p = reinterpret_cast<const char*>(&wide_[first]);
      _mm_prefetch(p, _MM_HINT_T0);
      _mm_prefetch(p + 64, _MM_HINT_T0);
    } else if (leafData.base) {
      const char* p = static_cast<const char*>(leafData.base) + std::size_t(first) * leafData.stride;
      _mm_prefetch(p, _MM_HINT_T0);
      _mm_prefetch(p + std::size_t(count) * leafData.stride - 1, _MM_HINT_T0);
    }
  }

  /// refit() (gather: boxes by original primitive index) and refitLeafOrder() (boxes in leaf order).
  void refitFrom(const std::vector<Bounds3>& boxes, bool gather);

  BvhWideNodes wide_;
  Vec3 anchor_{0.0};  ///< The first finite centroid; node boxes are stored relative to it.
  Bounds3 bounds_;
  std::vector<uint32_t> primIndices_;
  int depth_ = 0;
};

}  // namespace whitted
