// Bottom-up recomputation of a tree's node boxes (private to accel/*.cpp): Refitter over the wide nodes, and the
// primitives' rounded boxes in leaf order it reads. Used by Bvh::refit (refit.cpp) and the Morton build, whose
// boxes come from a refit (build_morton.cpp).
#pragma once

#include "accel/box4.h"
#include "accel/build_common.h"
#include "util/memory.h"
#include "util/parallel.h"

#include <emmintrin.h>

#include <algorithm>
#include <atomic>
#include <cstddef>
#include <cstdint>
#include <new>
#include <vector>

namespace whitted::bvh_detail {

/// Recomputes every child box bottom-up; leafBox(first, count) gives a leaf's box.
template <class LeafBox>
struct Refitter {
  BvhWideNodes& wide;
  const LeafBox& leafBox;

  /// Depth first below node i; returns its box.
  Box4 subtree(uint32_t i) const {
    BvhWideNode& w = wide[i];
    Box4 all;
    for (int c = 0; c < 4; ++c) {
      if (w.count[c] == BvhWideNode::kEmpty) continue;
      const Box4 b = w.count[c] > 0 ? leafBox(w.first[c], w.count[c]) : subtree(w.first[c]);
      setChildBox(w, c, b);
      all.extend(b);
    }
    return all;
  }

  /// The subtrees below a frontier of inner nodes in parallel, then the nodes above it. Returns the root box.
  Box4 all(WorkerPool& pool) const {
    if (wide.empty()) return Box4();
    std::vector<uint32_t> upper, frontier{0};  // breadth first: parents before children
    const std::size_t want = wide.size() < 4096 ? 1 : 16 * std::size_t(pool.threads());
    while (frontier.size() < want) {
      std::vector<uint32_t> next;
      for (uint32_t i : frontier)
        for (int c = 0; c < 4; ++c)
          if (wide[i].count[c] == 0) next.push_back(wide[i].first[c]);
      if (next.empty()) break;
      upper.insert(upper.end(), frontier.begin(), frontier.end());
      frontier.swap(next);
    }
    ScratchArray<Box4> nodeBox(wide.size());  // written for the frontier and the upper nodes only
    pool.run(uint32_t(frontier.size()), [&](uint32_t j) { new (&nodeBox[frontier[j]]) Box4(subtree(frontier[j])); });
    for (std::size_t k = upper.size(); k-- > 0;) {
      BvhWideNode& w = wide[upper[k]];
      Box4 box;
      for (int c = 0; c < 4; ++c) {
        if (w.count[c] == BvhWideNode::kEmpty) continue;
        const Box4 b = w.count[c] > 0 ? leafBox(w.first[c], w.count[c]) : nodeBox[w.first[c]];
        setChildBox(w, c, b);
        box.extend(b);
      }
      new (&nodeBox[upper[k]]) Box4(box);
    }
    return nodeBox[0];
  }
};

/// The caller's primitive boxes rounded outward, in leaf order. Performance note: the gather is one flat pass
/// with independent loads (and prefetches) over all threads; reading the boxes leaf by leaf during the refit's
/// depth-first walk waited on one cache miss after another (most of a Morton build's time).
struct LeafOrderBoxes {
  ScratchArray<Box4> box;
  /// boxes[prims[i]] is leaf slot i's box; prims null: boxes are in leaf order already (no gather).
  LeafOrderBoxes(const Bounds3* boxes, uint32_t n, const uint32_t* prims, const Vec3& anchor, WorkerPool& pool)
      : box(n) {
    pool.run(chunksOf(n), [&](uint32_t k) {
      for (uint32_t i = k * kChunk, e = std::min(n, i + kChunk); i < e; ++i) {
        const uint32_t p = prims ? prims[i] : i;
        if (prims && i + 16 < n) _mm_prefetch(reinterpret_cast<const char*>(&boxes[prims[i + 16]]), _MM_HINT_T0);
        new (&box[i]) Box4(roundedBox(boxes[p], anchor));
      }
    });
  }
  /// Boxes made by make(first, end, out) for chunks of leaf slots on all cores (out: slot first's box); valid false
  /// if make returned false for some chunk (the boxes are then incomplete).
  template <typename Make>
  LeafOrderBoxes(uint32_t n, WorkerPool& pool, Make&& make) : box(n) {
    std::atomic<bool> ok{true};
    pool.run(chunksOf(n), [&](uint32_t k) {
      const uint32_t i = k * kChunk, e = std::min(n, i + kChunk);
      if (ok.load(std::memory_order_relaxed) && !make(i, e, &box[i])) ok.store(false, std::memory_order_relaxed);
    });
    valid = ok.load();
  }
  bool valid = true;
  /// A leaf's box: the union of its rounded primitive boxes (= the rounded union: rounding is monotonic).
  Box4 operator()(uint32_t first, uint32_t count) const {
    Box4 u;
    for (uint32_t i = first; i < first + count; ++i) u.extend(box[i]);
    return u;
  }
};

}  // namespace whitted::bvh_detail
