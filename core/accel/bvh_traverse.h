// Single-ray traversal of a Bvh (the body of Bvh::traverse, declared in bvh.h): closest hit, or any hit for
// shadow rays, one loop with a compile-time switch (like bvh v2).
#pragma once

#include "accel/bvh.h"

#include <emmintrin.h>

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <limits>

namespace whitted {

namespace bvh_detail {

/// Sort keys of four entry distances (box-test units, never NaN): the float's bits mapped to an unsigned integer
/// of the same order (negative floats reversed; -0 added to +0 first, as the float comparison treats them), shifted
/// up two bits to hold the child index. Sorting the keys of the entered children orders them by distance and,
/// between equal distances, by child order.
inline void distanceKeys(__m128 t, uint64_t key[4]) {
  const __m128i bits = _mm_castps_si128(_mm_add_ps(t, _mm_setzero_ps()));
  const __m128i ord = _mm_xor_si128(bits, _mm_or_si128(_mm_srai_epi32(bits, 31), _mm_set1_epi32(INT32_MIN)));
  alignas(16) uint32_t u[4];
  _mm_store_si128(reinterpret_cast<__m128i*>(u), ord);
  for (int c = 0; c < 4; ++c) key[c] = uint64_t(u[c]) << 2 | uint64_t(c);
}

/// Whether the ray's origin and direction are finite (six doubles, three SSE2 compares).
inline bool finiteRay(const Ray& r) {
  static_assert(offsetof(Ray, dir) == offsetof(Ray, origin) + 3 * sizeof(double), "origin, then direction");
  const double* d = &r.origin.x;
  const __m128d mag = _mm_castsi128_pd(_mm_set1_epi64x(0x7fffffffffffffff));
  const __m128d big = _mm_set1_pd(std::numeric_limits<double>::max());
  const __m128d ok = _mm_and_pd(_mm_and_pd(_mm_cmple_pd(_mm_and_pd(_mm_loadu_pd(d), mag), big),
                                           _mm_cmple_pd(_mm_and_pd(_mm_loadu_pd(d + 2), mag), big)),
                                _mm_cmple_pd(_mm_and_pd(_mm_loadu_pd(d + 4), mag), big));
  return _mm_movemask_pd(ok) == 3;
}

/// a, b in ascending order (branch-free: conditional moves).
inline void sort2(uint64_t& a, uint64_t& b) {
  const uint64_t lo = std::min(a, b), hi = std::max(a, b);
  a = lo;
  b = hi;
}

}  // namespace bvh_detail

template <bool AnyHit, typename LeafFn>
inline bool Bvh::traverse(const Ray& ray, double& tMax, LeafFn&& leaf, uint64_t* nodesVisited,
                          LeafData leafData) const {
  if (wide_.empty() || !bvh_detail::finiteRay(ray)) return false;
  // A tree that is one leaf (a one-sphere object, a small mesh): its box was tested by the level above, and the
  // leaf tests are exact, so the root's box test only costs (8% of the classic scene's instructions)
  if (isOneLeaf()) {
    if (nodesVisited) ++*nodesVisited;
    return leaf(wide_[0].first[0], wide_[0].count[0], tMax);
  }
  const BoxRay br(ray, anchor_);
  const bool maskEmpty = br.emptyMayPass;
  const BvhWideNode* nodes = wide_.data();
  // Where pushed leaves' primitives are prefetched from (without leaf-ordered primitives: the root node, cached)
  const uintptr_t nodeBase = reinterpret_cast<uintptr_t>(nodes);
  const uintptr_t leafBase = leafData.base ? reinterpret_cast<uintptr_t>(leafData.base) : nodeBase;
  const uintptr_t leafStride = leafData.base ? leafData.stride : 0;
  // Starts loading a pushed child while the nearer ones are visited: both cache lines of a wide node, the first and
  // last primitive of a leaf (branch-free; addresses as integers, since only one of the two is a real address)
  auto prefetch = [&](uint32_t first, uint32_t count) __attribute__((always_inline)) {
    const uintptr_t node = nodeBase + uintptr_t(first) * sizeof(BvhWideNode);
    const uintptr_t prims = leafBase + uintptr_t(first) * leafStride;
    const uintptr_t p = count == 0 ? node : prims;
    const uintptr_t q = count == 0 ? node + 64 : prims + uintptr_t(count) * leafStride - (leafStride != 0);
    _mm_prefetch(reinterpret_cast<const char*>(p), _MM_HINT_T0);
    _mm_prefetch(reinterpret_cast<const char*>(q), _MM_HINT_T0);
  };
  struct Entry {
    float t;  // entry distance (box-test units), at most the exact one
    uint32_t first, count;
  };
  Entry stack[kWideStackSize];
  int sp = 0;
  auto push = [&](const BvhWideNode& n, const float* tNear, int c) __attribute__((always_inline)) {
    stack[sp++] = Entry{tNear[c], n.first[c], n.count[c]};
    prefetch(n.first[c], n.count[c]);
  };
  uint64_t visited = 0;  // counted locally, stored once (no memory write per node)
  bool hitAny = false;
  const __m128 tMinV = _mm_set1_ps(floatBelow(ray.tMin * br.tScale));
  float tMaxF = floatAbove(tMax * br.tScale);
  // The child visited next: a wide node (count 0, first its index) or a leaf (slots first .. first+count). The
  // nearest entered child is visited next without a trip through the stack; the others are pushed
  uint32_t first = 0, count = 0;
  for (;;) {
    ++visited;
    if (count > 0) {
      if (leaf(first, count, tMax)) {
        hitAny = true;
        if constexpr (AnyHit) break;
        tMaxF = floatAbove(tMax * br.tScale);
      }
    } else {
      const BvhWideNode& n = nodes[first];
      // Slab test of the four children at once
      __m128 t0 = tMinV;
      unsigned mask = br.enter(n, t0, _mm_set1_ps(tMaxF));
      if (maskEmpty) mask &= n.used();
      if (mask != 0) {
        alignas(16) float tNear[4];
        _mm_store_ps(tNear, t0);
        int c = __builtin_ctz(mask);
        mask &= mask - 1;
        if (mask != 0) {
          if constexpr (AnyHit) {
            // Any hit ends the query (shadow rays): no ordering, the first entered child is visited next
            for (; mask; mask &= mask - 1) push(n, tNear, __builtin_ctz(mask));
          } else {
            const int o = __builtin_ctz(mask);
            mask &= mask - 1;
            if (mask == 0) {
              // Two entered children (the most common case after one): the farther is pushed, the nearer visited
              // next; on equal distances the first in child order is visited first
              int far = o;
              if (tNear[c] > tNear[o]) {
                far = c;
                c = o;
              }
              push(n, tNear, far);
            } else {
              // Three or four: a sorting network on (distance, child) keys, nearest first (the fourth key of
              // three children is the largest possible, sorted last and not pushed); the rest are pushed farthest
              // first, so they pop nearest first, equal distances in child order
              uint64_t key[4];
              bvh_detail::distanceKeys(t0, key);
              uint64_t k0 = key[c], k1 = key[o], k2 = key[__builtin_ctz(mask)];
              mask &= mask - 1;
              uint64_t k3 = mask ? key[__builtin_ctz(mask)] : ~uint64_t(0);
              bvh_detail::sort2(k0, k1);
              bvh_detail::sort2(k2, k3);
              bvh_detail::sort2(k0, k2);
              bvh_detail::sort2(k1, k3);
              bvh_detail::sort2(k1, k2);
              if (mask) push(n, tNear, int(k3 & 3));
              push(n, tNear, int(k2 & 3));
              push(n, tNear, int(k1 & 3));
              c = int(k0 & 3);
            }
          }
        }
        first = n.first[c];
        count = n.count[c];
        continue;
      }
    }
    // Next entry from the stack, skipping those behind a hit found since they were pushed (any-hit walks end at
    // their first hit: every entry is still ahead)
    for (;;) {
      if (sp == 0) goto done;
      const Entry& e = stack[--sp];
      if (AnyHit || !(e.t > tMaxF)) {
        first = e.first;
        count = e.count;
        break;
      }
    }
  }
done:
  if (nodesVisited) *nodesVisited += visited;
  return hitAny;
}

}  // namespace whitted
