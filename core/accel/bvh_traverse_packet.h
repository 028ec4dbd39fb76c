// Packet traversals of a Bvh (bodies of Bvh::traverseAny4 and Bvh::traverse4, declared in bvh.h): up to four
// rays walk the tree together, any hit (shadow packets) or closest hit (camera-ray packets), each ray keeping
// the hits of its single-ray walk.
#pragma once

#include "accel/bvh.h"

#include <emmintrin.h>

#include <algorithm>
#include <cstdint>
#include <limits>

namespace whitted {

/// active without the rays whose origin or direction is not finite (they visit nothing, as in traverse()).
inline unsigned Bvh::finiteRays(const Ray* rays, unsigned active) {
  for (int i = 0; i < 4; ++i)
    if ((active >> i & 1) && (!isFinite(rays[i].origin) || !isFinite(rays[i].dir))) active &= ~(1u << i);
  return active;
}

/// A packet's per-ray box-test set-up (limits tMax[i], or each ray's tMax without it; lanes of inactive rays are
/// 0 in tMaxF) and its joint test.
inline JointBoxRay Bvh::prepare(const Ray* rays, unsigned active, const double* tMax, BoxRay* br, __m128* tMinV,
                                __m128* tMaxV, float* tMaxF) const {
  for (int i = 0; i < 4; ++i) {
    tMaxF[i] = 0.0f;
    if (!(active >> i & 1)) continue;
    br[i].set(rays[i], anchor_);
    tMinV[i] = _mm_set1_ps(floatBelow(rays[i].tMin * br[i].tScale));
    tMaxF[i] = floatAbove((tMax ? tMax[i] : rays[i].tMax) * br[i].tScale);
    tMaxV[i] = _mm_set1_ps(tMaxF[i]);
  }
  const Vec3 extent = bounds_.hi - bounds_.lo;
  return JointBoxRay(br, tMinV, tMaxV, active, float(std::max(extent.x, std::max(extent.y, extent.z)) * kJointSpread));
}

// Any hit (shadow packets)
template <typename LeafFn>
inline unsigned Bvh::traverseAny4(const Ray* rays, unsigned active, LeafFn&& leaf, uint64_t* nodesVisited,
                                  LeafData leafData) const {
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

// Closest hit (camera-ray packets)
template <typename LeafFn>
inline unsigned Bvh::traverse4(const Ray* rays, unsigned active, double* tMax, LeafFn&& leaf, uint64_t* nodesVisited,
                               LeafData leafData) const {
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

}  // namespace whitted
