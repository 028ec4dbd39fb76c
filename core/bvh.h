// Bounding volume hierarchy: binned SAH build from boxes and centroids (it never sees geometry) and a templated
// traversal with a leaf callback. Used for both levels: per object over its primitives, and over instances.
#pragma once

#include "math.h"

#include <emmintrin.h>  // SSE2: part of every x86-64 CPU (Debian 12's baseline)

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

/// Ray data precomputed once per traversal.
struct RayTraversal {
  Vec3 origin;
  Vec3 invDir;
  bool negative[3];  ///< Direction component negative: the near plane is the box's hi face on that axis.
  int nearBound[3], farBound[3];  ///< Index into BvhWideNode::b of the near / far plane per axis.
  explicit RayTraversal(const Ray& r) : origin(r.origin) {
    for (int i = 0; i < 3; ++i) {
      // Slopes below 1e-290 (incl. denormals, whose reciprocal overflows) are treated as parallel: the reciprocal
      // is +-inf, and slab() ignores the NaN that 0 * inf gives for an origin exactly on a face plane, so such a
      // ray is kept (conservative) while a parallel ray outside the slab gets +-inf and is rejected.
      double d = std::abs(r.dir[i]) < 1e-290 ? std::copysign(0.0, r.dir[i]) : r.dir[i];
      invDir[i] = d != 0.0 ? 1.0 / d : std::copysign(kInfinity, d);
      negative[i] = std::signbit(invDir[i]);
      nearBound[i] = negative[i] ? 3 + i : i;
      farBound[i] = negative[i] ? i : 3 + i;
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
  /// Performance note: 4-wide nodes, their four boxes tested two at a time with SSE2 in double precision (the
  /// same slab arithmetic per box as slab(), so exactly the same boxes are entered); the stack carries each
  /// entry's distance, so entries behind a hit found meanwhile are dropped unvisited; fixed-size stack, no
  /// allocation, no virtual call; the callback is inlined.
  template <bool AnyHit, typename LeafFn>
  bool traverse(const Ray& ray, double& tMax, LeafFn&& leaf, uint64_t* nodesVisited = nullptr) const {
    if (wide_.empty()) return false;
    const RayTraversal rt(ray);
    struct Entry {
      double t;
      uint32_t first, count;
    };
    Entry stack[kWideStackSize];
    int sp = 0;
    uint64_t visited = 0;  // counted locally, stored once (no memory write per node)
    bool hitAny = false;
    const __m128d org[3] = {_mm_set1_pd(rt.origin.x), _mm_set1_pd(rt.origin.y), _mm_set1_pd(rt.origin.z)};
    const __m128d inv[3] = {_mm_set1_pd(rt.invDir.x), _mm_set1_pd(rt.invDir.y), _mm_set1_pd(rt.invDir.z)};
    const __m128d widen = _mm_set1_pd(1.0 + 2.0 * gammaBound(3));
    const __m128d tMinV = _mm_set1_pd(ray.tMin);
    stack[sp++] = Entry{ray.tMin, 0, 0};
    while (sp > 0) {
      const Entry e = stack[--sp];
      if (e.t > tMax) continue;  // behind a hit found since it was pushed
      if (e.count > 0) {
        ++visited;
        if (leaf(e.first, e.count, tMax)) {
          hitAny = true;
          if constexpr (AnyHit) break;
        }
        continue;
      }
      const BvhWideNode& n = wide_[e.first];
      ++visited;
      // Slab test of the four children, two per SSE2 register
      const __m128d tMaxV = _mm_set1_pd(tMax);
      alignas(16) double tNear[4];
      int hitMask = 0;
      for (int half = 0; half < 2; ++half) {
        __m128d t0 = tMinV, t1 = tMaxV;
        for (int a = 0; a < 3; ++a) {
          const __m128d nearPlane = _mm_cvtps_pd(_mm_castpd_ps(_mm_load_sd(reinterpret_cast<const double*>(
              &n.b[rt.nearBound[a]][2 * half]))));
          const __m128d farPlane = _mm_cvtps_pd(_mm_castpd_ps(_mm_load_sd(reinterpret_cast<const double*>(
              &n.b[rt.farBound[a]][2 * half]))));
          const __m128d lo = _mm_mul_pd(_mm_sub_pd(nearPlane, org[a]), inv[a]);
          const __m128d hi = _mm_mul_pd(_mm_mul_pd(_mm_sub_pd(farPlane, org[a]), inv[a]), widen);
          // max(lo, t0) / min(hi, t1) return the second operand for a NaN first one, as slab() ignores NaN
          t0 = _mm_max_pd(lo, t0);
          t1 = _mm_min_pd(hi, t1);
        }
        _mm_store_pd(tNear + 2 * half, t0);
        hitMask |= _mm_movemask_pd(_mm_cmple_pd(t0, t1)) << (2 * half);
      }
      if constexpr (AnyHit) {
        // Any hit ends the query (shadow rays): no ordering, every entered child is pushed as it comes
        for (int c = 0; c < 4; ++c)
          if ((hitMask & (1 << c)) && n.count[c] != BvhWideNode::kEmpty)  // a NaN ray "enters" even empty boxes
            stack[sp++] = Entry{tNear[c], n.first[c], n.count[c]};
      } else {
        // Push the entered children farthest first, so the nearest is popped next
        int order[4], k = 0;
        for (int c = 0; c < 4; ++c)
          if ((hitMask & (1 << c)) && n.count[c] != BvhWideNode::kEmpty) {  // NaN rays "enter" empty boxes too
            int j = k++;
            while (j > 0 && tNear[order[j - 1]] < tNear[c]) {
              order[j] = order[j - 1];
              --j;
            }
            order[j] = c;
          }
        for (int j = 0; j < k; ++j) stack[sp++] = Entry{tNear[order[j]], n.first[order[j]], n.count[order[j]]};
      }
    }
    if (nodesVisited) *nodesVisited += visited;
    return hitAny;
  }

  /// Slab test against a node; tEntry receives the entry distance. Near and far planes are chosen by the sign
  /// of the direction (precomputed), so no per-axis swap is needed.
  static bool slab(const BvhNode& n, const RayTraversal& r, double tMin, double tMax, double& tEntry) {
    const float* lo = n.lo;
    const float* hi = n.hi;
    double t0 = tMin, t1 = tMax;
    for (int i = 0; i < 3; ++i) {
      double a = (double(r.negative[i] ? hi[i] : lo[i]) - r.origin[i]) * r.invDir[i];
      double b = (double(r.negative[i] ? lo[i] : hi[i]) - r.origin[i]) * r.invDir[i];
      // Widen the far distance by the rounding bound so the test stays conservative (pbrt-v4). A NaN (0 * inf:
      // origin on a face plane of a parallel ray) compares false and leaves [t0, t1] unchanged.
      b *= 1.0 + 2.0 * gammaBound(3);
      t0 = a > t0 ? a : t0;
      t1 = b < t1 ? b : t1;
    }
    tEntry = t0;
    return t0 <= t1;
  }

 private:
  std::vector<BvhWideNode> wide_;
  Bounds3 bounds_;
  std::vector<uint32_t> primIndices_;
  int depth_ = 0;
};

}  // namespace whitted
