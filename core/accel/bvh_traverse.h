// Single-ray traversal of a Bvh (the body of Bvh::traverse, declared in bvh.h): closest hit, or any hit for
// shadow rays, one loop with a compile-time switch (like bvh v2).
#pragma once

#include "accel/bvh.h"

#include <emmintrin.h>

#include <cstdint>
#include <limits>

namespace whitted {

template <bool AnyHit, typename LeafFn>
inline bool Bvh::traverse(const Ray& ray, double& tMax, LeafFn&& leaf, uint64_t* nodesVisited,
                          LeafData leafData) const {
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
        } else if ((mask & (mask - 1)) == 0 && mask != 0) {
          // Two entered children (the most common case after one): the farther is pushed, the nearer visited
          // next; on equal distances the first in child order is visited first, as the sort below would
          const int o = __builtin_ctz(mask);
          int far = o;
          if (tNear[c] > tNear[o]) {
            far = c;
            c = o;
          }
          stack[sp++] = Entry{tNear[far], n.first[far], n.count[far]};
          prefetchChild(n.first[far], n.count[far], leafData);
        } else if (mask != 0) {
          // Three or four: entered children by distance, nearest first; the rest are pushed farthest first
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

}  // namespace whitted
