// Bounding volume hierarchy: binned SAH or Morton build from boxes and centroids (it never sees geometry) and
// templated traversals with a leaf callback. Used for both levels: per object over its primitives, and over
// instances. The class interface; the pieces live by concept: bvh_node.h (node layout), box_ray.h (box tests),
// bvh_traverse.h and bvh_traverse_packet.h (traversal bodies, included at the end), build.cpp, build_sah.cpp,
// build_morton.cpp (builders), refit.cpp (refit, SAH cost).
#pragma once

#include "accel/box_ray.h"
#include "accel/bvh_node.h"
#include "util/math.h"

#include <emmintrin.h>  // SSE2: part of every x86-64 CPU (Debian 12's baseline)

#include <atomic>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <vector>

namespace whitted {

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

/// Where a tree's leaf primitives live, when they are stored in leaf order (slot k at base + k * stride): lets the
/// traversal prefetch a leaf's primitives when it puts the leaf on its stack. Default: none.
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
  void refitLeafOrder(const std::vector<Bounds3>& leafBoxes) { refitFrom(leafBoxes.data(), leafBoxes.size(), false); }
  /// Fills boxes[0 .. end - first) with the boxes of leaf slots [first, end); false if one cannot be boxed. first is
  /// a multiple of kRefitSlice, and end - first at most kRefitSlice.
  using LeafBoxFill = std::function<bool(std::size_t first, std::size_t end, Bounds3* boxes)>;
  static constexpr std::size_t kRefitSlice = 256;
  /// refitLeafOrder() with the boxes made by fill in pieces on all cores and rounded there, never all stored in
  /// double (a 1M-triangle mesh's 48 MB). Returns false, and leaves the tree as it was, if fill returned false for
  /// some piece. Throws std::invalid_argument if n is not the tree's primitive count.
  bool refitLeafOrder(std::size_t n, const LeafBoxFill& fill);
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
                LeafData leafData = {}) const;

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
                        LeafData leafData = {}) const;

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
                     LeafData leafData = {}) const;

  /// Whether some leaf whose box and ancestors' boxes all pass mayEnter(const Bounds3&) (child boxes in input
  /// coordinates, childBounds) makes leaf(first, count) return true; depth first, ending at the first such leaf.
  /// For region queries (Scene::frustumMayHit); an empty tree has none.
  template <typename BoxFn, typename LeafFn>
  bool anyLeaf(BoxFn&& mayEnter, LeafFn&& leaf) const {
    if (wide_.empty()) return false;
    uint32_t stack[kWideStackSize + 4];
    int sp = 0;
    stack[sp++] = 0;
    while (sp > 0) {
      const BvhWideNode& n = wide_[stack[--sp]];
      for (int c = 0; c < 4; ++c) {
        if (n.count[c] == BvhWideNode::kEmpty || !mayEnter(childBounds(n, c))) continue;
        if (n.count[c] > 0) {
          if (leaf(n.first[c], n.count[c])) return true;
        } else {
          stack[sp++] = n.first[c];
        }
      }
    }
    return false;
  }

  /// The point node coordinates are relative to: b[k][c] + anchor[k % 3] bounds child c (conservatively).
  const Vec3& anchor() const { return anchor_; }
  /// Child c's box of a node, in the tree's input coordinates (double, containing the float box exactly).
  Bounds3 childBounds(const BvhWideNode& n, int c) const {
    Bounds3 b;
    for (int k = 0; k < 3; ++k) {
      b.lo[k] = nextDown(double(n.b[k][c]) + anchor_[k]);  // (nextafter's step, inline: no libm call)
      b.hi[k] = nextUp(double(n.b[3 + k][c]) + anchor_[k]);
    }
    return b;
  }

 private:
  /// active without the rays whose origin or direction is not finite (they visit nothing, as in traverse()).
  static unsigned finiteRays(const Ray* rays, unsigned active);
  /// A packet's per-ray box-test set-up (limits tMax[i], or each ray's tMax without it; lanes of inactive rays are
  /// 0 in tMaxF) and its joint test.
  JointBoxRay prepare(const Ray* rays, unsigned active, const double* tMax, BoxRay* br, __m128* tMinV, __m128* tMaxV,
                      float* tMaxF) const;
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
  /// visited: traversal of a large tree waits mostly on memory (the packet walks; traverse() has a branch-free
  /// copy).
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
  void refitFrom(const Bounds3* boxes, std::size_t n, bool gather);

  BvhWideNodes wide_;
  Vec3 anchor_{0.0};  ///< The first finite centroid; node boxes are stored relative to it.
  Bounds3 bounds_;
  std::vector<uint32_t> primIndices_;
  int depth_ = 0;
};

}  // namespace whitted

// The traversals' template bodies (inline, so callers compile them with their leaf callbacks)
#include "accel/bvh_traverse.h"
#include "accel/bvh_traverse_packet.h"
