// Binned SAH build (BvhBuildQuality::Sah): primitives binned per node over three axes at once (SSE), the split of
// least surface area cost, median splits where SAH finds none; large nodes bin and partition in parallel chunks.
#include "accel/box4.h"
#include "accel/build_common.h"

#include <emmintrin.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <utility>
#include <vector>

namespace whitted::bvh_detail {

namespace {

/// A primitive during the SAH build: its box rounded outward, its centroid relative to an anchor (both float) and
/// its index.
struct alignas(16) PrimRef {
  float lo[4];
  float hi[4];
  float c[3];
  uint32_t id;  // lane 3 of the centroid vector: masked off before arithmetic
};

constexpr int kMaxBins = 32;

/// Centroid -> bin mapping of one node, all three axes at once (an axis that cannot be split maps to bin 0).
struct BinMap {
  alignas(16) float clo[4] = {0, 0, 0, 0};
  alignas(16) float scale[4] = {0, 0, 0, 0};
  alignas(16) float top[4] = {0, 0, 0, 0};  // nb - 1
  /// Bin per axis in lanes 0..2. NaN (0 * inf) and out-of-range products clamp to the end bins.
  __m128i index(const PrimRef& r) const {
    // Lane 3 (the id) is masked to 0 first: its bits as a float may be denormal, which costs microcode assists
    const __m128 c = _mm_and_ps(_mm_load_ps(r.c), _mm_castsi128_ps(_mm_set_epi32(0, -1, -1, -1)));
    const __m128 f = _mm_mul_ps(_mm_sub_ps(c, _mm_load_ps(clo)), _mm_load_ps(scale));
    return _mm_cvttps_epi32(_mm_min_ps(_mm_max_ps(f, _mm_setzero_ps()), _mm_load_ps(top)));  // max(): 0 for NaN
  }
  /// The same bin for one axis in scalar float (the same operations: bit-identical to the vector lane).
  int index(const PrimRef& r, int axis) const {
    const float f = (r.c[axis] - clo[axis]) * scale[axis];
    const float g = f > 0.0f ? f : 0.0f;
    return int(g < top[axis] ? g : top[axis]);
  }
};

struct alignas(16) Bins {
  __m128 lo[3][kMaxBins], hi[3][kMaxBins];
  alignas(16) int32_t count[kMaxBins][4];  // [bin][axis]: one load gives the three axes' counts
  void clear(int nb) {
    for (int b = 0; b < nb; ++b) {
      for (int a = 0; a < 3; ++a) {
        lo[a][b] = _mm_set1_ps(kInf);
        hi[a][b] = _mm_set1_ps(-kInf);
      }
      _mm_store_si128(reinterpret_cast<__m128i*>(count[b]), _mm_setzero_si128());
    }
  }
  void add(const PrimRef& r, const BinMap& map) {
    alignas(16) int32_t b[4];
    _mm_store_si128(reinterpret_cast<__m128i*>(b), map.index(r));
    const __m128 l = _mm_load_ps(r.lo), h = _mm_load_ps(r.hi);
    for (int a = 0; a < 3; ++a) {
      lo[a][b[a]] = _mm_min_ps(lo[a][b[a]], l);
      hi[a][b[a]] = _mm_max_ps(hi[a][b[a]], h);
      ++count[b[a]][a];
    }
  }
  /// Bins r[0, n) (this must be cleared for nb bins). Performance note: neighbouring primitives mostly fall into
  /// the same bins, and each bin update waits for the previous one's store; large runs alternate between two bin
  /// sets (two independent chains) merged at the end.
  void add(const PrimRef* r, uint32_t n, const BinMap& map, int nb) {
    if (n < 256) {
      for (uint32_t i = 0; i < n; ++i) add(r[i], map);
      return;
    }
    Bins odd;
    odd.clear(nb);
    uint32_t i = 0;
    for (; i + 1 < n; i += 2) {
      add(r[i], map);
      odd.add(r[i + 1], map);
    }
    if (i < n) add(r[i], map);
    merge(odd, nb);
  }
  void merge(const Bins& o, int nb) {
    for (int b = 0; b < nb; ++b) {
      for (int a = 0; a < 3; ++a) {
        lo[a][b] = _mm_min_ps(lo[a][b], o.lo[a][b]);
        hi[a][b] = _mm_max_ps(hi[a][b], o.hi[a][b]);
      }
      for (int a = 0; a < 3; ++a) count[b][a] += o.count[b][a];
    }
  }
};

/// Half areas of three boxes given by their extents (lane k of the result: box k).
__m128 halfAreas3(__m128 e0, __m128 e1, __m128 e2) {
  __m128 e3 = _mm_setzero_ps();
  _MM_TRANSPOSE4_PS(e0, e1, e2, e3);  // e0 = x extents, e1 = y, e2 = z
  return _mm_add_ps(_mm_add_ps(_mm_mul_ps(e0, e1), _mm_mul_ps(e1, e2)), _mm_mul_ps(e2, e0));
}

/// Partitions r[0, n) so that primitives with bin <= bin on axis come first; returns their count and the centroid
/// boxes of both sides (their geometry boxes are the unions of their bins).
uint32_t partitionRefs(PrimRef* r, uint32_t n, const BinMap& map, int axis, int bin, Box4 cside[2]) {
  auto take = [&](const PrimRef& p, int s) {
    const __m128 c = xyz(_mm_load_ps(p.c));
    cside[s].extend(c, c);
  };
  uint32_t i = 0, j = n;
  for (;;) {
    while (i < j && map.index(r[i], axis) <= bin) take(r[i++], 0);
    while (i < j && map.index(r[j - 1], axis) > bin) take(r[--j], 1);
    if (i >= j) break;
    std::swap(r[i], r[j - 1]);
    take(r[i++], 0);
    take(r[--j], 1);
  }
  return i;
}

void boundsOf(const PrimRef* r, uint32_t n, Box4& box, Box4& cbox) {
  const __m128 cmask = _mm_castsi128_ps(_mm_set_epi32(0, -1, -1, -1));
  for (uint32_t i = 0; i < n; ++i) {
    box.extend(_mm_load_ps(r[i].lo), _mm_load_ps(r[i].hi));
    const __m128 c = _mm_and_ps(_mm_load_ps(r[i].c), cmask);
    cbox.extend(c, c);
  }
}

struct SahStrategy {
  struct Cand {
    uint32_t begin = 0, end = 0;
    int depth = 0;
    bool leaf = true;
    bool median = false;  // split at the median centroid on axis instead of at bin
    int axis = 0, bin = 0;
    Box4 box, cbox;
    Box4 side[2];  // SAH split: the boxes of both sides (unions of their bins)
    BinMap map;
    uint32_t count() const { return end - begin; }
  };

  /// Wide nodes to reserve for a subtree of count primitives (iso1m: 0.26 per primitive, leaves of 1-2).
  static std::size_t nodesFor(uint32_t count) { return count / 3 + 1; }

  PrimRef* refs;
  const BvhBuildOptions& opt;
  WorkerPool* pool;  // runs the chunks of nodes of kParallelMin primitives or more (maybe on one thread)
  Bins* chunkBins;   // one per chunk of the root

  double priority(const Cand& c) const { return halfArea(c.box); }
  void setChild(BvhWideNode& w, int slot, const Cand& c) const {
    setChildBox(w, slot, c.box);
    w.first[slot] = c.begin;
    w.count[slot] = c.leaf ? c.count() : 0;
  }

  /// Decides whether c is a leaf and, if not, how it splits (binned SAH over three axes).
  void decide(Cand& c) const {
    const uint32_t count = c.count();
    c.leaf = true;
    if (count <= 1) return;
    // Node extent scales the areas so they stay within float range at any coordinate scale
    const __m128 ext = _mm_sub_ps(c.box.hi, c.box.lo);
    const __m128 cext = _mm_sub_ps(c.cbox.hi, c.cbox.lo);
    const float maxExt = std::max({lane(ext, 0), lane(ext, 1), lane(ext, 2)});
    // Fewer bins for small nodes (Embree's rule): the sweeps' cost is per bin, and few centroids need few bins
    const int nb = std::min(std::clamp(opt.bins, 2, kMaxBins), int(4.0 + 0.05 * count));
    int bestAxis = -1, bestBin = 0;
    float bestCost = kInf;
    double parentArea = 0.0;
    Bins bins;
    if (c.depth < Bvh::kSahDepthLimit && maxExt > 0.0f && std::isfinite(maxExt)) {
      // Binning over all three axes in one pass
      int axisOk[3];
      _mm_store_ps(c.map.clo, c.cbox.lo);
      for (int a = 0; a < 3; ++a) {
        const float e = lane(cext, a), sc = float(nb) / e;
        axisOk[a] = e > 0.0f && std::isfinite(e) && std::isfinite(sc);
        c.map.scale[a] = axisOk[a] ? sc : 0.0f;
        c.map.top[a] = float(nb - 1);
      }
      bins.clear(nb);
      if (count >= kParallelMin) {
        const uint32_t chunks = chunksOf(count);
        Bins* part = chunkBins;  // (the top of the tree is built on one thread: one scratch serves every node)
        pool->run(chunks, [&](uint32_t k) {
          const uint32_t b = c.begin + k * kChunk, e = std::min(c.end, b + kChunk);
          part[k].clear(nb);
          part[k].add(refs + b, e - b, c.map, nb);
        });
        for (uint32_t k = 0; k < chunks; ++k) bins.merge(part[k], nb);
      } else {
        bins.add(refs + c.begin, count, c.map, nb);
      }
      // Sweep from the right, then from the left, all axes at once (lane = axis)
      const __m128 inv = _mm_set1_ps(1.0f / maxExt);
      __m128 rightCost[kMaxBins];
      Box4 acc[3];
      __m128i n = _mm_setzero_si128();
      for (int b = nb - 1; b > 0; --b) {
        for (int a = 0; a < 3; ++a) acc[a].extend(bins.lo[a][b], bins.hi[a][b]);
        n = _mm_add_epi32(n, _mm_load_si128(reinterpret_cast<const __m128i*>(bins.count[b])));
        const __m128 area = halfAreas3(_mm_mul_ps(_mm_sub_ps(acc[0].hi, acc[0].lo), inv),
                                       _mm_mul_ps(_mm_sub_ps(acc[1].hi, acc[1].lo), inv),
                                       _mm_mul_ps(_mm_sub_ps(acc[2].hi, acc[2].lo), inv));
        rightCost[b] = _mm_mul_ps(area, _mm_cvtepi32_ps(n));
      }
      const __m128i total = _mm_set1_epi32(int32_t(count));
      const __m128 okMask =
          _mm_castsi128_ps(_mm_set_epi32(0, axisOk[2] ? -1 : 0, axisOk[1] ? -1 : 0, axisOk[0] ? -1 : 0));
      __m128 best = _mm_set1_ps(kInf);
      __m128i bestB = _mm_setzero_si128();
      for (int a = 0; a < 3; ++a) acc[a] = Box4();
      n = _mm_setzero_si128();
      for (int b = 0; b < nb - 1; ++b) {
        for (int a = 0; a < 3; ++a) acc[a].extend(bins.lo[a][b], bins.hi[a][b]);
        n = _mm_add_epi32(n, _mm_load_si128(reinterpret_cast<const __m128i*>(bins.count[b])));
        const __m128 area = halfAreas3(_mm_mul_ps(_mm_sub_ps(acc[0].hi, acc[0].lo), inv),
                                       _mm_mul_ps(_mm_sub_ps(acc[1].hi, acc[1].lo), inv),
                                       _mm_mul_ps(_mm_sub_ps(acc[2].hi, acc[2].lo), inv));
        const __m128 cost = _mm_add_ps(_mm_mul_ps(area, _mm_cvtepi32_ps(n)), rightCost[b + 1]);
        // Only splits with primitives on both sides
        const __m128 valid = _mm_and_ps(
            okMask,
            _mm_castsi128_ps(_mm_andnot_si128(_mm_cmpeq_epi32(n, _mm_setzero_si128()), _mm_cmplt_epi32(n, total))));
        const __m128 better = _mm_and_ps(valid, _mm_cmplt_ps(cost, best));
        best = select(better, cost, best);
        bestB = _mm_or_si128(_mm_and_si128(_mm_castps_si128(better), _mm_set1_epi32(b)),
                             _mm_andnot_si128(_mm_castps_si128(better), bestB));
      }
      alignas(16) float bc[4];
      alignas(16) int32_t bb[4];
      _mm_store_ps(bc, best);
      _mm_store_si128(reinterpret_cast<__m128i*>(bb), bestB);
      for (int a = 0; a < 3; ++a)
        if (bc[a] < bestCost) {  // ties: the lower axis
          bestCost = bc[a];
          bestAxis = a;
          bestBin = bb[a];
        }
      parentArea = lane(halfAreas3(_mm_mul_ps(ext, inv), ext, ext), 0);
    }
    const double leafCost = double(count);
    const double splitCost =
        bestAxis >= 0 && parentArea > 0.0 ? opt.traversalCost + double(bestCost) / parentArea : kInfinity;
    if (bestAxis >= 0 && (splitCost < leafCost || count > uint32_t(opt.maxLeafSize))) {
      c.leaf = false;
      c.median = false;
      c.axis = bestAxis;
      c.bin = bestBin;
      c.side[0] = c.side[1] = Box4();
      for (int b = 0; b < nb; ++b) c.side[b > bestBin].extend(bins.lo[bestAxis][b], bins.hi[bestAxis][b]);
    } else if (count > uint32_t(opt.maxLeafSize)) {
      // No SAH split (coincident centroids or depth limit): median split on the widest centroid axis
      c.leaf = false;
      c.median = true;
      const float x = lane(cext, 0), y = lane(cext, 1), z = lane(cext, 2);
      c.axis = x >= y ? (x >= z ? 0 : 2) : (y >= z ? 1 : 2);
    }
  }

  /// Splits an inner candidate into two decided children.
  void split(const Cand& c, Cand& l, Cand& r) const {
    const uint32_t count = c.count();
    l = Cand();
    r = Cand();
    l.begin = c.begin;
    r.end = c.end;
    l.depth = r.depth = c.depth + 1;
    uint32_t mid = c.begin;
    if (!c.median) {
      Box4 cside[2];
      if (count >= kParallelMin) {
        mid = c.begin + parallelPartition(c, cside);
      } else {
        mid = c.begin + partitionRefs(refs + c.begin, count, c.map, c.axis, c.bin, cside);
      }
      l.box = c.side[0];
      l.cbox = cside[0];
      r.box = c.side[1];
      r.cbox = cside[1];
    }
    if (c.median || mid == c.begin || mid == c.end) {  // (an SAH split never leaves a side empty)
      mid = c.begin + count / 2;
      const int axis = c.axis;
      std::nth_element(refs + c.begin, refs + mid, refs + c.end,
                       [axis](const PrimRef& a, const PrimRef& b) { return a.c[axis] < b.c[axis]; });
      l.box = l.cbox = r.box = r.cbox = Box4();
      boundsOf(refs + c.begin, mid - c.begin, l.box, l.cbox);
      boundsOf(refs + mid, c.end - mid, r.box, r.cbox);
    }
    l.end = r.begin = mid;
    decide(l);
    decide(r);
  }

  /// Partition of a large node: chunks partition in place in parallel, then the right-side primitives left of the
  /// final middle swap places with the left-side ones right of it. Returns the left count.
  uint32_t parallelPartition(const Cand& c, Box4 cside[2]) const {
    const uint32_t chunks = chunksOf(c.count());
    std::vector<uint32_t> left(chunks);
    std::vector<Box4> part(2 * std::size_t(chunks));
    pool->run(chunks, [&](uint32_t k) {
      const uint32_t b = c.begin + k * kChunk, e = std::min(c.end, b + kChunk);
      left[k] = partitionRefs(refs + b, e - b, c.map, c.axis, c.bin, &part[2 * k]);
    });
    uint32_t nLeft = 0;
    for (uint32_t k = 0; k < chunks; ++k) {
      nLeft += left[k];
      for (int s = 0; s < 2; ++s) cside[s].extend(part[2 * k + s]);
    }
    // Misplaced runs: right-side primitives below mid, left-side ones at or above it (equal totals)
    const uint32_t mid = c.begin + nLeft;
    std::vector<std::pair<uint32_t, uint32_t>> wrongR, wrongL;  // [from, to)
    for (uint32_t k = 0; k < chunks; ++k) {
      const uint32_t b = c.begin + k * kChunk, e = std::min(c.end, b + kChunk), m = b + left[k];
      if (m < std::min(e, mid)) wrongR.emplace_back(m, std::min(e, mid));
      if (std::max(b, mid) < m) wrongL.emplace_back(std::max(b, mid), m);
    }
    std::size_t ir = 0, il = 0;
    uint32_t pr = wrongR.empty() ? 0 : wrongR[0].first, pl = wrongL.empty() ? 0 : wrongL[0].first;
    // Swap run by run (memory bound: a parallel swap gains little on two cores)
    while (ir < wrongR.size() && il < wrongL.size()) {
      const uint32_t len = std::min(wrongR[ir].second - pr, wrongL[il].second - pl);
      std::swap_ranges(refs + pr, refs + pr + len, refs + pl);
      pr += len;
      pl += len;
      if (pr == wrongR[ir].second && ++ir < wrongR.size()) pr = wrongR[ir].first;
      if (pl == wrongL[il].second && ++il < wrongL.size()) pl = wrongL[il].first;
    }
    return nLeft;
  }
};

}  // namespace

/// Binned-SAH build into wide and primIndices (sized n).
BuiltTree buildSah(const Bounds3* boxes, const Centroids& centroids, uint32_t n, const BvhBuildOptions& opt,
                   const Vec3& anchor, WorkerPool& pool, BvhWideNodes& wide, std::vector<uint32_t>& primIndices) {
  const uint32_t chunks = chunksOf(n);
  // Primitive references (boxes rounded outward once; centroids relative to the first one, so that a small
  // object far from the origin keeps distinct float centroids), with box and centroid bounds per chunk
  uint32_t a = 0;
  while (a + 1 < n && !isFinite(centroids[a])) ++a;
  const Vec3 first = centroids[a];
  const __m128d anchorXY = _mm_loadu_pd(&first.x), anchorZ = _mm_load_sd(&first.z);
  ScratchArray<PrimRef> refs(n);
  std::vector<Box4> part(2 * std::size_t(chunks));
  pool.run(chunks, [&](uint32_t k) {
    Box4 box, cbox;
    for (uint32_t i = k * kChunk, e = std::min(n, i + kChunk); i < e; ++i) {
      PrimRef& r = refs[i];
      const Box4 b = roundedBox(boxes[i], anchor);
      _mm_store_ps(r.lo, b.lo);
      _mm_store_ps(r.hi, b.hi);
      const Vec3 ci = centroids[i];
      const double* c = &ci.x;
      _mm_store_ps(r.c, _mm_movelh_ps(_mm_cvtpd_ps(_mm_sub_pd(_mm_loadu_pd(c), anchorXY)),
                                      _mm_cvtpd_ps(_mm_sub_sd(_mm_load_sd(c + 2), anchorZ))));
      r.id = i;
    }
    boundsOf(refs.data() + k * kChunk, std::min(n, (k + 1) * kChunk) - k * kChunk, box, cbox);
    part[2 * k] = box;
    part[2 * k + 1] = cbox;
  });

  // The tree from the root's bounds down
  ScratchArray<Bins> chunkBins(n >= kParallelMin ? chunks : 0);
  SahStrategy s{refs.data(), opt, &pool, chunkBins.data()};
  SahStrategy::Cand root;
  root.begin = 0;
  root.end = n;
  root.depth = 1;
  for (uint32_t k = 0; k < chunks; ++k) {
    root.box.extend(part[2 * k]);
    root.cbox.extend(part[2 * k + 1]);
  }
  s.decide(root);
  BuiltTree t;
  t.depth = buildAll(s, root, pool, wide, opt.cancel);
  t.bounds = toBounds(root.box, anchor);

  // Leaf order
  pool.run(chunks, [&](uint32_t k) {
    for (uint32_t i = k * kChunk, e = std::min(n, i + kChunk); i < e; ++i) primIndices[i] = refs[i].id;
  });
  return t;
}

}  // namespace whitted::bvh_detail
