// Bounding volume hierarchy: binned SAH build from boxes and centroids (it never sees geometry) and a templated
// traversal with a leaf callback. Used for both levels: per object over its primitives, and over instances.
#pragma once

#include "math.h"

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

struct BvhBuildOptions {
  int maxLeafSize = 8;         ///< Leaves never hold more primitives than this (unless all centroids coincide).
  int bins = 16;               ///< SAH bins per axis.
  double traversalCost = 1.0;  ///< SAH cost of visiting a node, relative to one primitive test.
};

/// Ray data precomputed once per traversal.
struct RayTraversal {
  Vec3 origin;
  Vec3 invDir;
  bool negative[3];  ///< Direction component negative: the near plane is the box's hi face on that axis.
  explicit RayTraversal(const Ray& r) : origin(r.origin) {
    for (int i = 0; i < 3; ++i) {
      // Slopes below 1e-290 (incl. denormals, whose reciprocal overflows) are treated as parallel: the reciprocal
      // is +-inf, and slab() ignores the NaN that 0 * inf gives for an origin exactly on a face plane, so such a
      // ray is kept (conservative) while a parallel ray outside the slab gets +-inf and is rejected.
      double d = std::abs(r.dir[i]) < 1e-290 ? std::copysign(0.0, r.dir[i]) : r.dir[i];
      invDir[i] = d != 0.0 ? 1.0 / d : std::copysign(kInfinity, d);
      negative[i] = std::signbit(invDir[i]);
    }
  }
};

class Bvh {
 public:
  /// Traversal stack size; the builder caps tree depth below it (SAH splits below depth kSahDepthLimit fall back
  /// to median splits, which add at most 32 more levels).
  static constexpr int kStackSize = 128;
  static constexpr int kSahDepthLimit = 64;

  /// Builds over boxes[i] with representative points centroids[i]. Empty input gives an empty tree.
  void build(const std::vector<Bounds3>& boxes, const std::vector<Vec3>& centroids, const BvhBuildOptions& opt = {});

  bool empty() const { return nodes_.empty(); }
  const std::vector<BvhNode>& nodes() const { return nodes_; }
  /// Primitive order of the leaves: leaf slot -> original primitive index.
  const std::vector<uint32_t>& primIndices() const { return primIndices_; }
  Bounds3 bounds() const;
  std::size_t memoryBytes() const {
    return nodes_.capacity() * sizeof(BvhNode) + primIndices_.capacity() * sizeof(uint32_t);
  }
  int depth() const { return depth_; }

  /// Visits leaves front to back. leaf(first, count, tMax) tests primitive slots [first, first+count), may
  /// shrink tMax (closest hit) and returns true if it found a hit. With AnyHit, traversal stops at the first leaf
  /// returning true. Returns whether any leaf returned true. nodesVisited (if given) counts visited nodes.
  /// Performance note: fixed-size stack, no allocation, no virtual call; the callback is inlined.
  template <bool AnyHit, typename LeafFn>
  bool traverse(const Ray& ray, double& tMax, LeafFn&& leaf, uint64_t* nodesVisited = nullptr) const {
    if (nodes_.empty()) return false;
    RayTraversal rt(ray);
    uint32_t stack[kStackSize];
    int sp = 0;
    uint32_t node = 0;
    uint64_t visited = 0;  // counted locally, stored once (no memory write per node)
    bool hitAny = false;
    double tEntry;
    if (!slab(nodes_[0], rt, ray.tMin, tMax, tEntry)) return false;
    for (;;) {
      const BvhNode& n = nodes_[node];
      ++visited;
      if (n.count > 0) {
        if (leaf(n.first, n.count, tMax)) {
          hitAny = true;
          if constexpr (AnyHit) break;
        }
      } else {
        // Order children by entry distance; descend into the nearer one
        double tl, tr;
        bool hl = slab(nodes_[n.first], rt, ray.tMin, tMax, tl);
        bool hr = slab(nodes_[n.first + 1], rt, ray.tMin, tMax, tr);
        if (hl && hr) {
          bool leftFirst = tl <= tr;
          stack[sp++] = leftFirst ? n.first + 1 : n.first;
          node = leftFirst ? n.first : n.first + 1;
          continue;
        }
        if (hl || hr) {
          node = hl ? n.first : n.first + 1;
          continue;
        }
      }
      if (sp == 0) break;
      node = stack[--sp];
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
  std::vector<BvhNode> nodes_;
  std::vector<uint32_t> primIndices_;
  int depth_ = 0;
};

}  // namespace whitted
