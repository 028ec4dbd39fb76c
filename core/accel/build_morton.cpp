// Morton (LBVH) build (BvhBuildQuality::Fast): primitives sorted by the Morton code of their centroids (parallel
// radix sort), nodes split where the codes' highest differing bit changes, node boxes filled by a refit.
#include "accel/box4.h"
#include "accel/build_common.h"
#include "accel/refit.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <vector>

namespace whitted::bvh_detail {

namespace {

/// Spreads the low 10 bits of v to every third bit.
uint32_t spreadBits(uint32_t v) {
  v &= 0x3ffu;
  v = (v | (v << 16)) & 0x030000ffu;
  v = (v | (v << 8)) & 0x0300f00fu;
  v = (v | (v << 4)) & 0x030c30c3u;
  v = (v | (v << 2)) & 0x09249249u;
  return v;
}

/// Linear BVH: primitives sorted by the Morton code of their centroid; a node splits where its range's highest
/// differing code bit changes (at the middle where all codes are equal). Boxes are filled afterwards by a refit.
struct MortonStrategy {
  struct Cand {
    uint32_t begin = 0, end = 0;
    int depth = 0;
    bool leaf = true;
    uint32_t mid = 0;
    uint32_t count() const { return end - begin; }
  };
  /// Wide nodes to reserve for a subtree of count primitives (iso1m: 0.16 per primitive, leaves of up to 4).
  static std::size_t nodesFor(uint32_t count) { return count / 5 + 1; }

  const uint32_t* codes;  // sorted
  uint32_t leafSize;

  double priority(const Cand& c) const { return double(c.count()); }  // no boxes yet: the largest child opens
  void setChild(BvhWideNode& w, int slot, const Cand& c) const {
    w.first[slot] = c.begin;
    w.count[slot] = c.leaf ? c.count() : 0;
  }
  void decide(Cand& c) const {
    const uint32_t count = c.count();
    c.leaf = count <= leafSize;
    if (c.leaf) return;
    const uint32_t a = codes[c.begin], b = codes[c.end - 1];
    if (a == b) {
      c.mid = c.begin + count / 2;
      return;
    }
    int bit = 31;
    while (!(((a ^ b) >> bit) & 1u)) --bit;
    c.mid = uint32_t(
        std::partition_point(codes + c.begin, codes + c.end, [bit](uint32_t x) { return !((x >> bit) & 1u); }) - codes);
  }
  void split(const Cand& c, Cand& l, Cand& r) const {
    l = Cand{c.begin, c.mid, c.depth + 1};
    r = Cand{c.mid, c.end, c.depth + 1};
    decide(l);
    decide(r);
  }
};

/// LSD radix sort of (code << 32 | index) keys on the 30 code bits, 10 per pass; stable, so its result does not
/// depend on the split into parts (one per thread: part histograms, then each part scatters its keys in order).
/// The sorted keys end in keys (the buffers are swapped as the passes go).
void radixSortMortonKeys(uint64_t*& keys, uint64_t*& tmp, uint32_t n, WorkerPool& pool) {
  const uint32_t parts = uint32_t(pool.threads()), partSize = (n + parts - 1) / parts;
  std::vector<std::array<uint32_t, 1024>> hist(parts);
  for (int pass = 0; pass < 3; ++pass) {
    const int shift = 32 + 10 * pass;
    pool.run(parts, [&](uint32_t p) {
      hist[p].fill(0);
      for (uint32_t i = p * partSize, e = std::min(n, i + partSize); i < e; ++i) ++hist[p][(keys[i] >> shift) & 1023u];
    });
    uint32_t sum = 0;
    for (int b = 0; b < 1024; ++b)
      for (uint32_t p = 0; p < parts; ++p) {
        const uint32_t c = hist[p][b];
        hist[p][b] = sum;
        sum += c;
      }
    pool.run(parts, [&](uint32_t p) {
      for (uint32_t i = p * partSize, e = std::min(n, i + partSize); i < e; ++i)
        tmp[hist[p][(keys[i] >> shift) & 1023u]++] = keys[i];
    });
    std::swap(keys, tmp);
  }
}

/// Primitives in Morton order of their centroids: primIndices gets the order, codes the sorted 30-bit codes.
void mortonOrder(const Centroids& centroids, uint32_t n, WorkerPool& pool, std::vector<uint32_t>& primIndices,
                 ScratchArray<uint32_t>& codes) {
  const uint32_t chunks = chunksOf(n);
  // Centroid bounds
  std::vector<Bounds3> part(chunks);
  pool.run(chunks, [&](uint32_t k) {
    for (uint32_t i = k * kChunk, e = std::min(n, i + kChunk); i < e; ++i) part[k].extend(centroids[i]);
  });
  Bounds3 cb;
  for (const Bounds3& b : part) cb.extend(b);
  Vec3 scale(0.0);
  for (int a = 0; a < 3; ++a) {
    const double e = cb.hi[a] - cb.lo[a];
    if (e > 0.0 && std::isfinite(e) && std::isfinite(1024.0 / e)) scale[a] = 1024.0 / e;
  }
  // Keys (code, index), sorted
  ScratchArray<uint64_t> keyArrays[2] = {ScratchArray<uint64_t>(n), ScratchArray<uint64_t>(n)};
  uint64_t *keys = keyArrays[0].data(), *tmp = keyArrays[1].data();
  pool.run(chunks, [&](uint32_t k) {
    for (uint32_t i = k * kChunk, e = std::min(n, i + kChunk); i < e; ++i) {
      uint32_t code = 0;
      const Vec3 c = centroids[i];
      for (int a = 0; a < 3; ++a) {
        const double f = (c[a] - cb.lo[a]) * scale[a];
        const uint32_t q = f > 0.0 ? (f < 1023.0 ? uint32_t(f) : 1023u) : 0u;  // NaN -> 0
        code |= spreadBits(q) << (2 - a);
      }
      keys[i] = (uint64_t(code) << 32) | i;
    }
  });
  radixSortMortonKeys(keys, tmp, n, pool);
  pool.run(chunks, [&](uint32_t k) {
    for (uint32_t i = k * kChunk, e = std::min(n, i + kChunk); i < e; ++i) {
      codes[i] = uint32_t(keys[i] >> 32);
      primIndices[i] = uint32_t(keys[i]);
    }
  });
}

}  // namespace

/// Fast (Morton, LBVH) build into wide and primIndices (sized n).
BuiltTree buildMorton(const Bounds3* boxes, const Centroids& centroids, uint32_t n, const BvhBuildOptions& opt,
                      const Vec3& anchor, WorkerPool& pool, BvhWideNodes& wide, std::vector<uint32_t>& primIndices) {
  ScratchArray<uint32_t> codes(n);
  mortonOrder(centroids, n, pool, primIndices, codes);
  MortonStrategy s{codes.data(), uint32_t(std::clamp(opt.maxLeafSize, 1, 4))};
  MortonStrategy::Cand root{0, n, 1};
  s.decide(root);
  BuiltTree t;
  t.depth = buildAll(s, root, pool, wide, opt.cancel);
  // Node boxes: a refit over the primitives' boxes in leaf order
  const LeafOrderBoxes leafBox(boxes, n, primIndices.data(), anchor, pool);
  t.bounds = toBounds(Refitter<LeafOrderBoxes>{wide, leafBox}.all(pool), anchor);
  return t;
}

}  // namespace whitted::bvh_detail
