// The BVH's node layout: 4-wide nodes, four child boxes in structure-of-arrays order for one SSE slab test each
// (like Embree's BVH4 and tinybvh's BVH4_CPU). Written by the builders (build_common.h), read by the box tests
// (box_ray.h) and the traversals (bvh_traverse.h, bvh_traverse_packet.h).
#pragma once

#include "util/memory.h"

#include <emmintrin.h>  // SSE2: part of every x86-64 CPU (Debian 12's baseline)

#include <cstdint>
#include <limits>

namespace whitted {

/// 4-wide node, the traversal structure (each one collapses binary splits of the build). Bounds per child in
/// structure-of-arrays order: b[k][c] is bound k (0..2 = lo x, y, z; 3..5 = hi x, y, z) of child c, single
/// precision rounded outward (conservative for any double ray), relative to the tree's anchor. Child c is a leaf
/// when count[c] > 0 (primitive slots first[c] .. first[c]+count[c]), an inner node when count[c] == 0 (first[c] =
/// wide node index), and empty when count[c] == kEmpty (its box is inverted, and traversal skips it: a NaN ray
/// passes every slab test).
struct alignas(64) BvhWideNode {  // two whole cache lines
  static constexpr uint32_t kEmpty = 0xffffffffu;
  float b[6][4];
  uint32_t first[4];
  uint32_t count[4];
  /// Mask of the slots that hold a child. Empty slots are the children whose lo.x is +inf (a real box's lo is
  /// rounded down, so never +inf even beyond float range); slab tests mask them out when NaN exits (inf - inf, an
  /// origin beyond float range: BoxRay::emptyMayPass) could otherwise let them through.
  unsigned used() const {
    const __m128 inf = _mm_set1_ps(std::numeric_limits<float>::infinity());
    return unsigned(_mm_movemask_ps(_mm_cmplt_ps(_mm_load_ps(b[0]), inf)));
  }
};
/// A tree's wide nodes (on huge pages when large: memory.h).
using BvhWideNodes = LargeVector<BvhWideNode>;

}  // namespace whitted
