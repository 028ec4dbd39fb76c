// Bounding volume hierarchy: binned SAH build from boxes and centroids (it never sees geometry) and a templated
// traversal with a leaf callback. Used for both levels: per object over its primitives, and over instances.
#pragma once

#include "math.h"

#include <xmmintrin.h>  // SSE: part of every x86-64 CPU (Debian 12's baseline)

#include <cstddef>
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
struct alignas(16) BvhWideNode {
  static constexpr uint32_t kEmpty = 0xffffffffu;
  float b[6][4];
  uint32_t first[4];
  uint32_t count[4];
};

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
};

/// A ray prepared for the single-precision box tests of one tree: origin relative to the tree's anchor and
/// direction scaled by a power of two (so t' = t * tScale exactly), each rounded so that every computed entry
/// distance is at most, and every exit distance at least, the exact one of the double-precision ray (Embree's
/// robust mode, extended to a double ray): per axis the origin is rounded up for one plane and down for the other,
/// and the reciprocal direction toward zero for the near plane and away from zero for the far plane, by a margin
/// (2^-20) that covers the float subtraction's and product's rounding (2^-24 each). Overflow stays conservative:
/// a near reciprocal saturates at FLT_MAX, a far one may be infinite, and an origin beyond float range rounds to
/// +-FLT_MAX or +-inf on the conservative side. NaN products (0 * inf: an origin on a face plane of a parallel
/// ray) are ignored by the min/max, which keeps such a ray (conservative).
struct BoxRay {
  __m128 orgNear[3], orgFar[3], invNear[3], invFar[3];
  int nearBound[3], farBound[3];  ///< Index into BvhWideNode::b of the near / far plane per axis.
  double tScale = 1.0;            ///< Box-test distances are t * tScale.
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
    constexpr double kMargin = 0x1p-20;
    for (int a = 0; a < 3; ++a) {
      const double d = r.dir[a] * s;
      const bool negative = std::signbit(d);
      nearBound[a] = negative ? 3 + a : a;
      farBound[a] = negative ? a : 3 + a;
      // o - anchor carries one double rounding, which floatAbove / floatBelow (strictly above / below) cover
      const double o = r.origin[a] - anchor[a];
      orgNear[a] = _mm_set1_ps(negative ? floatBelow(o) : floatAbove(o));
      orgFar[a] = _mm_set1_ps(negative ? floatAbove(o) : floatBelow(o));
      const double inv = d != 0.0 ? 1.0 / d : std::copysign(kInfinity, d);
      const double nearMag = std::min(std::abs(inv) * (1.0 - kMargin), double(std::numeric_limits<float>::max()));
      const double farMag = std::abs(inv) * (1.0 + kMargin);
      const float nearF = std::min(floatBelow(nearMag), std::numeric_limits<float>::max());
      const float farF = floatAbove(farMag);
      invNear[a] = _mm_set1_ps(negative ? -std::max(nearF, 0.0f) : std::max(nearF, 0.0f));
      invFar[a] = _mm_set1_ps(negative ? -farF : farF);
    }
  }
};

class Bvh {
 public:
  /// Traversal stack size; the builder caps tree depth below it (SAH splits below depth kSahDepthLimit fall back
  /// to median splits, which add at most 32 more levels).
  static constexpr int kStackSize = 128;
  static constexpr int kSahDepthLimit = 64;
  /// Wide traversal stack: each wide level pushes at most 3 entries more than it pops.
  static constexpr int kWideStackSize = 3 * kStackSize + 1;

  /// Builds over boxes[i] with representative points centroids[i]. Empty input gives an empty tree.
  void build(const std::vector<Bounds3>& boxes, const std::vector<Vec3>& centroids, const BvhBuildOptions& opt = {});
  /// Recomputes every node box bottom-up from new primitive boxes (same count and order as the build's), keeping
  /// the topology: for primitives that moved but stay the same primitives (time steps, deformed meshes). Boxes are
  /// rounded outward exactly as build() rounds them, so traversal stays conservative; the tree's quality decays
  /// with the motion (rebuild when it matters). Throws std::invalid_argument if the count differs.
  void refit(const std::vector<Bounds3>& boxes);

  bool empty() const { return wide_.empty(); }
  /// The 4-wide traversal nodes; node 0 is the root, and every child node has a larger index than its parent.
  const std::vector<BvhWideNode>& nodes() const { return wide_; }
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
  bool traverse(const Ray& ray, double& tMax, LeafFn&& leaf, uint64_t* nodesVisited = nullptr) const {
    if (wide_.empty() || !isFinite(ray.origin) || !isFinite(ray.dir)) return false;
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
        __m128 t0 = tMinV, t1 = _mm_set1_ps(tMaxF);
        for (int a = 0; a < 3; ++a) {
          const __m128 lo = _mm_mul_ps(_mm_sub_ps(_mm_load_ps(n.b[br.nearBound[a]]), br.orgNear[a]), br.invNear[a]);
          const __m128 hi = _mm_mul_ps(_mm_sub_ps(_mm_load_ps(n.b[br.farBound[a]]), br.orgFar[a]), br.invFar[a]);
          // The far product's NaN (0 * inf: an origin on the far plane of a parallel ray) is ignored: min(hi, t1)
          // returns t1 for a NaN hi. The near product is never NaN for a real plane (its reciprocal is finite);
          // it is NaN only for an empty slot's infinite plane minus an origin beyond float range, and
          // max(t0, lo) returns that NaN, which rejects the slot. So empty slots (inverted, infinite boxes) are
          // never entered and need no check.
          t0 = _mm_max_ps(t0, lo);
          t1 = _mm_min_ps(hi, t1);
        }
        alignas(16) float tNear[4];
        _mm_store_ps(tNear, t0);
        unsigned mask = unsigned(_mm_movemask_ps(_mm_cmple_ps(t0, t1)));
        if (mask != 0) {
          int c = __builtin_ctz(mask);
          mask &= mask - 1;
          if constexpr (AnyHit) {
            // Any hit ends the query (shadow rays): no ordering, the first entered child is visited next
            for (; mask; mask &= mask - 1) {
              const int o = __builtin_ctz(mask);
              stack[sp++] = Entry{tNear[o], n.first[o], n.count[o]};
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
            for (int j = k - 1; j > 0; --j) stack[sp++] = Entry{tNear[order[j]], n.first[order[j]], n.count[order[j]]};
            c = order[0];
          }
          cur = Entry{tNear[c], n.first[c], n.count[c]};
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
  std::vector<BvhWideNode> wide_;
  Vec3 anchor_{0.0};  ///< The first finite centroid; node boxes are stored relative to it.
  Bounds3 bounds_;
  std::vector<uint32_t> primIndices_;
  int depth_ = 0;
};

}  // namespace whitted
