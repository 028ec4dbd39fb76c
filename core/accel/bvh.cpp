#include "accel/bvh.h"

#include "util/parallel.h"

#include <algorithm>
#include <array>
#include <atomic>
#include <condition_variable>
#include <cstring>
#include <exception>
#include <functional>
#include <limits>
#include <mutex>
#include <new>
#include <stdexcept>
#include <system_error>
#include <thread>
#include <type_traits>

#ifdef __linux__
#include <sys/mman.h>  // madvise
#endif

namespace whitted {

namespace {

constexpr float kInf = std::numeric_limits<float>::infinity();

// Node bounds are stored as floats stepped one ulp outward (always, not only when rounding went inward), so a
// ray grazing a face with a tiny slope still enters the node: roundDown(x) is the largest float below x, roundUp(x)
// the smallest above. Both are monotonic, so the rounded union of boxes equals the union of the rounded boxes:
// primitives are rounded once and all unions are taken in float.

__m128 select(__m128 mask, __m128 a, __m128 b) {
  return _mm_or_ps(_mm_and_ps(mask, a), _mm_andnot_ps(mask, b));
}

/// The next float toward -infinity, per lane (NaN and -infinity stay, zero goes to -denorm_min).
__m128 nextDown4(__m128 f) {
  const __m128 zero = _mm_setzero_ps();
  const __m128i pos = _mm_castps_si128(_mm_cmpgt_ps(f, zero));
  const __m128i neg = _mm_castps_si128(_mm_andnot_ps(_mm_cmpeq_ps(f, _mm_set1_ps(-kInf)), _mm_cmplt_ps(f, zero)));
  const __m128i u = _mm_sub_epi32(_mm_add_epi32(_mm_castps_si128(f), pos), neg);  // positive: -1 ulp, negative: +1
  return select(_mm_cmpeq_ps(f, zero), _mm_castsi128_ps(_mm_set1_epi32(int32_t(0x80000001u))), _mm_castsi128_ps(u));
}

/// roundDown() of four doubles (lanes 0, 1 from x01, lanes 2, 3 from x23): the nearest float, one step down
/// unless it is already below. NaN stays NaN.
__m128 roundDown4(__m128d x01, __m128d x23) {
  const __m128 f = _mm_movelh_ps(_mm_cvtpd_ps(x01), _mm_cvtpd_ps(x23));
  const __m128d ge01 = _mm_cmpge_pd(_mm_cvtps_pd(f), x01), ge23 = _mm_cmpge_pd(_mm_cvtps_pd(_mm_movehl_ps(f, f)), x23);
  return select(_mm_shuffle_ps(_mm_castpd_ps(ge01), _mm_castpd_ps(ge23), _MM_SHUFFLE(2, 0, 2, 0)), nextDown4(f), f);
}

/// roundUp() of four doubles: -roundDown(-x).
__m128 roundUp4(__m128d x01, __m128d x23) {
  const __m128d sign = _mm_set1_pd(-0.0);
  return _mm_xor_ps(roundDown4(_mm_xor_pd(x01, sign), _mm_xor_pd(x23, sign)), _mm_set1_ps(-0.0f));
}

/// Lanes 0..2 kept, lane 3 zeroed.
__m128 xyz(__m128 v) {
  return _mm_and_ps(v, _mm_castsi128_ps(_mm_set_epi32(0, -1, -1, -1)));
}

/// Box in single precision, x y z in lanes 0..2 (lane 3 unused).
struct Box4 {
  __m128 lo = _mm_set1_ps(kInf), hi = _mm_set1_ps(-kInf);
  void extend(__m128 l, __m128 h) {
    lo = _mm_min_ps(lo, l);
    hi = _mm_max_ps(hi, h);
  }
  void extend(const Box4& b) { extend(b.lo, b.hi); }
};

float lane(__m128 v, int i) {
  alignas(16) float f[4];
  _mm_store_ps(f, v);
  return f[i];
}

/// Half surface area in double (the collapse order and the leaf-or-split decision use it).
double halfArea(const Box4& b) {
  alignas(16) float lo[4], hi[4];
  _mm_store_ps(lo, b.lo);
  _mm_store_ps(hi, b.hi);
  const double dx = double(hi[0]) - lo[0], dy = double(hi[1]) - lo[1], dz = double(hi[2]) - lo[2];
  return dx * dy + dy * dz + dz * dx;
}

/// A primitive during the SAH build: its box rounded outward, its centroid relative to an anchor (both float) and
/// its index.
struct alignas(16) PrimRef {
  float lo[4];
  float hi[4];
  float c[3];
  uint32_t id;  // lane 3 of the centroid vector: masked off before arithmetic
};


/// The build's representative points: the caller's centroids, or the boxes' centres when it gave none (saves the
/// caller an array: 24 bytes per primitive written and read twice).
struct Centroids {
  const Bounds3* boxes;
  const Vec3* given;  ///< null: boxes[i].center()
  Vec3 operator[](std::size_t i) const { return given ? given[i] : boxes[i].center(); }
};

// Work split ---------------------------------------------------------------------------------------------------

constexpr uint32_t kParallelMin = 32768;  // nodes at least this large bin and partition in parallel chunks
constexpr uint32_t kChunk = 8192;         // chunk size of those passes (fixed: results do not depend on threads)
constexpr uint32_t kTaskMax = 32768;      // subtrees below this size are built as one task each (on one thread)
static_assert(kTaskMax <= kParallelMin, "a task must not run parallel passes (no nested pool use)");

uint32_t chunksOf(uint32_t count) {
  return (count + kChunk - 1) / kChunk;
}

// Wide nodes ---------------------------------------------------------------------------------------------------

BvhWideNode emptyWideNode() {
  BvhWideNode w;
  for (int c = 0; c < 4; ++c) {
    for (int k = 0; k < 3; ++k) {
      w.b[k][c] = kInf;
      w.b[3 + k][c] = -kInf;
    }
    w.first[c] = 0;
    w.count[c] = BvhWideNode::kEmpty;
  }
  return w;
}

void setChildBox(BvhWideNode& w, int c, const Box4& b) {
  alignas(16) float lo[4], hi[4];
  _mm_store_ps(lo, b.lo);
  _mm_store_ps(hi, b.hi);
  for (int k = 0; k < 3; ++k) {
    w.b[k][c] = lo[k];
    w.b[3 + k][c] = hi[k];
  }
}

/// Contiguous wide nodes of one subtree: in a region reserved for it (of a build-wide arena), moving to a vector
/// of its own only if the region fills up.
class NodeStore {
 public:
  void setRegion(BvhWideNode* region, std::size_t capacity) {
    region_ = region;
    capacity_ = capacity;
  }
  uint32_t push(const BvhWideNode& n) {
    if (spill_.empty() && size_ < capacity_) {
      region_[size_] = n;
    } else {
      if (spill_.empty()) spill_.assign(region_, region_ + size_);
      spill_.push_back(n);
    }
    return uint32_t(size_++);
  }
  BvhWideNode& operator[](std::size_t i) { return spill_.empty() ? region_[i] : spill_[i]; }
  const BvhWideNode* data() const { return spill_.empty() ? region_ : spill_.data(); }
  std::size_t size() const { return size_; }

 private:
  BvhWideNode* region_ = nullptr;
  std::size_t capacity_ = 0, size_ = 0;
  std::vector<BvhWideNode> spill_;
};

/// One subtree's wide nodes with local indices (root at 0). Children that are separate tasks are recorded in
/// links and patched when the subtrees are concatenated.
struct Subtree {
  struct Link {
    uint32_t node;
    int slot;
    uint32_t task;
  };
  NodeStore nodes;
  std::vector<Link> links;
  int maxDepth = 0;
};

/// Builds a subtree top-down into 4-wide nodes with the collapse rule of Embree and tinybvh: a wide node takes a
/// binary inner node's two children and keeps opening its inner child of highest priority (SAH: largest surface
/// area) until it has four. S (the split strategy) decides whether a candidate is a leaf and splits it.
/// With spawn set, inner children smaller than kTaskMax become tasks (built later, each on one thread).
template <class S>
void buildSubtree(S& s, const typename S::Cand& root, Subtree& out, std::vector<typename S::Cand>* spawn,
                  const std::atomic<bool>* cancel) {
  using Cand = typename S::Cand;
  out.maxDepth = std::max(out.maxDepth, root.depth);
  out.nodes.push(emptyWideNode());
  if (root.leaf) {  // a root leaf: a wide root with one child
    s.setChild(out.nodes[0], 0, root);
    return;
  }
  std::vector<std::pair<Cand, uint32_t>> work;  // (inner candidate, its wide node)
  work.emplace_back(root, 0u);
  while (!work.empty()) {
    // Cancelled: stop with the nodes so far (consistent, unfinished children are empty nodes); build() drops them
    if (cancel && cancel->load(std::memory_order_relaxed)) return;
    const Cand cand = work.back().first;
    const uint32_t slot = work.back().second;
    work.pop_back();
    Cand ch[4];
    int n = 2;
    s.split(cand, ch[0], ch[1]);
    for (int c = 0; c < 2; ++c) out.maxDepth = std::max(out.maxDepth, ch[c].depth);
    while (n < 4) {
      int best = -1;
      double bestPriority = -1.0;
      for (int c = 0; c < n; ++c) {
        const double p = ch[c].leaf ? -1.0 : s.priority(ch[c]);
        if (p > bestPriority) {
          bestPriority = p;
          best = c;
        }
      }
      if (best < 0) break;
      const Cand opened = ch[best];
      s.split(opened, ch[best], ch[n]);
      out.maxDepth = std::max({out.maxDepth, ch[best].depth, ch[n].depth});
      ++n;
    }
    BvhWideNode w = emptyWideNode();
    for (int c = 0; c < n; ++c) {
      s.setChild(w, c, ch[c]);
      if (ch[c].leaf) continue;
      if (spawn && ch[c].count() < kTaskMax) {
        out.links.push_back({slot, c, uint32_t(spawn->size())});
        spawn->push_back(ch[c]);
      } else {
        w.first[c] = out.nodes.push(emptyWideNode());
        work.emplace_back(ch[c], w.first[c]);
      }
    }
    out.nodes[slot] = w;
  }
}

// SAH strategy -------------------------------------------------------------------------------------------------

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

// Morton strategy ----------------------------------------------------------------------------------------------

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

/// Builds the whole tree with strategy S: the top (inner nodes of at least kTaskMax primitives, whose passes run
/// in parallel chunks) on the calling thread, the subtrees below as parallel tasks, then concatenates the
/// subtrees in a fixed order (node layout independent of the thread count). Returns the tree depth.
template <class S>
int buildAll(S& s, const typename S::Cand& root, WorkerPool& pool, BvhWideNodes& wide,
             const std::atomic<bool>* cancel) {
  using Cand = typename S::Cand;
  Subtree top;
  std::vector<Cand> tasks;
  buildSubtree(s, root, top, root.count() >= kTaskMax ? &tasks : nullptr, cancel);
  // Each task's nodes go to a region of one arena (a few large allocations fault far less than many small ones)
  std::vector<Subtree> sub(tasks.size());
  std::size_t arenaSize = 0;
  for (const Cand& t : tasks) arenaSize += S::nodesFor(t.count());
  ScratchArray<BvhWideNode> arena(arenaSize);
  for (std::size_t i = 0, at = 0; i < tasks.size(); at += S::nodesFor(tasks[i++].count()))
    sub[i].nodes.setRegion(arena.data() + at, S::nodesFor(tasks[i].count()));
  // Largest tasks first (balance), each on one thread
  std::vector<uint32_t> order(tasks.size());
  for (uint32_t i = 0; i < order.size(); ++i) order[i] = i;
  std::stable_sort(order.begin(), order.end(),
                   [&](uint32_t a, uint32_t b) { return tasks[a].count() > tasks[b].count(); });
  pool.run(uint32_t(tasks.size()),
           [&](uint32_t j) { buildSubtree(s, tasks[order[j]], sub[order[j]], nullptr, cancel); });
  // Concatenate: top first, then the tasks in creation order (a child's index stays above its parent's)
  std::vector<uint32_t> base(tasks.size());
  std::size_t total = top.nodes.size();
  int depth = top.maxDepth;
  for (std::size_t i = 0; i < sub.size(); ++i) {
    base[i] = uint32_t(total);
    total += sub[i].nodes.size();
    depth = std::max(depth, sub[i].maxDepth);
  }
  wide.resize(total);
  std::copy(top.nodes.data(), top.nodes.data() + top.nodes.size(), wide.begin());
  for (const Subtree::Link& l : top.links) wide[l.node].first[l.slot] = base[l.task];
  pool.run(uint32_t(sub.size()), [&](uint32_t i) {
    BvhWideNode* dst = wide.data() + base[i];
    const BvhWideNode* src = sub[i].nodes.data();
    for (std::size_t k = 0; k < sub[i].nodes.size(); ++k) {
      BvhWideNode w = src[k];
      for (int c = 0; c < 4; ++c)
        if (w.count[c] == 0) w.first[c] += base[i];
      *dst++ = w;
    }
    sub[i].nodes = NodeStore();
  });
  return depth;
}

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

/// A double box rounded outward to float (lane 3: 0).
/// A primitive's box relative to the tree's anchor, rounded outward to float. The subtraction rounds once, and
/// roundDown / roundUp step strictly outward (at least one double ulp), so the float box contains the exact one.
Box4 roundedBox(const Bounds3& b, const Vec3& anchor) {
  static_assert(sizeof(Bounds3) == 6 * sizeof(double), "lo.x lo.y lo.z hi.x hi.y hi.z");
  const double* d = &b.lo.x;
  const __m128d aXY = _mm_loadu_pd(&anchor.x), aZX = _mm_set_pd(anchor.x, anchor.z),
                aYZ = _mm_set_pd(anchor.z, anchor.y);
  // d0 = lo.x lo.y, d1 = lo.z hi.x, d2 = hi.y hi.z
  const __m128d d0 = _mm_sub_pd(_mm_loadu_pd(d), aXY), d1 = _mm_sub_pd(_mm_loadu_pd(d + 2), aZX),
                d2 = _mm_sub_pd(_mm_loadu_pd(d + 4), aYZ);
  Box4 r;
  r.lo = xyz(roundDown4(d0, d1));                                            // lo.x lo.y | lo.z (hi.x)
  r.hi = xyz(roundUp4(_mm_shuffle_pd(d1, d2, 1), _mm_unpackhi_pd(d2, d2)));  // hi.x hi.y | hi.z
  return r;
}

/// An anchored float box back in input coordinates, stepped outward over the addition's rounding.
Bounds3 toBounds(const Box4& b, const Vec3& anchor) {
  Bounds3 r;
  for (int k = 0; k < 3; ++k) {
    r.lo[k] = std::nextafter(double(lane(b.lo, k)) + anchor[k], -kInfinity);
    r.hi[k] = std::nextafter(double(lane(b.hi, k)) + anchor[k], kInfinity);
  }
  return r;
}

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
  /// A leaf's box: the union of its rounded primitive boxes (= the rounded union: rounding is monotonic).
  Box4 operator()(uint32_t first, uint32_t count) const {
    Box4 u;
    for (uint32_t i = first; i < first + count; ++i) u.extend(box[i]);
    return u;
  }
};

int buildThreads(const BvhBuildOptions& opt, std::size_t n) {
  if (n < kParallelMin) return 1;
  return opt.threads > 0 ? opt.threads : hardwareThreads();
}

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

/// What a build leaves besides the nodes and the leaf order.
struct BuiltTree {
  int depth = 0;
  Bounds3 bounds;
};

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

}  // namespace

void Bvh::build(const Bounds3* boxes, const Vec3* givenCentroids, std::size_t count, const BvhBuildOptions& opt) {
  const Centroids centroids{boxes, givenCentroids};
  clear();
  if (count == 0) return;
  // An exception (std::bad_alloc) leaves an empty tree, not a half-built one
  struct EmptyOnThrow {
    Bvh& bvh;
    const int uncaught = std::uncaught_exceptions();
    ~EmptyOnThrow() {
      if (std::uncaught_exceptions() > uncaught) bvh.clear();
    }
  } emptyOnThrow{*this};
  const uint32_t n = uint32_t(count);
  // Node boxes are stored relative to the first finite centroid, so an object far from the origin keeps float
  // precision in its boxes (traversal subtracts the anchor from the ray origin once)
  anchor_ = Vec3(0.0);
  for (uint32_t i = 0; i < n; ++i)
    if (isFinite(centroids[i])) {
      anchor_ = centroids[i];
      break;
    }
  WorkerPool pool(buildThreads(opt, n));
  primIndices_.resize(n);
  const BuiltTree t = opt.quality == BvhBuildQuality::Fast
                          ? buildMorton(boxes, centroids, n, opt, anchor_, pool, wide_, primIndices_)
                          : buildSah(boxes, centroids, n, opt, anchor_, pool, wide_, primIndices_);
  depth_ = t.depth;
  bounds_ = t.bounds;
  if (opt.cancel && opt.cancel->load(std::memory_order_relaxed)) clear();  // maybe unfinished: nothing is kept
}

void Bvh::refit(const std::vector<Bounds3>& boxes) {
  refitFrom(boxes, true);
}

void Bvh::refitLeafOrder(const std::vector<Bounds3>& leafBoxes) {
  refitFrom(leafBoxes, false);
}

void Bvh::refitFrom(const std::vector<Bounds3>& boxes, bool gather) {
  if (boxes.size() != primIndices_.size()) throw std::invalid_argument("Bvh::refit: primitive count differs");
  if (wide_.empty()) return;
  WorkerPool pool(buildThreads(BvhBuildOptions(), boxes.size()));
  const LeafOrderBoxes leafBox(boxes.data(), uint32_t(boxes.size()), gather ? primIndices_.data() : nullptr, anchor_,
                               pool);
  bounds_ = toBounds(Refitter<LeafOrderBoxes>{wide_, leafBox}.all(pool), anchor_);
}

double Bvh::sahCost() const {
  const double rootArea = bounds_.halfArea();
  if (wide_.empty() || !(rootArea > 0.0) || !std::isfinite(rootArea)) return 0.0;
  // The root is always entered; below it each child by its area (node boxes are anchored: areas do not move)
  double cost = 1.0;
  for (const BvhWideNode& n : wide_)
    for (int c = 0; c < 4; ++c) {
      if (n.count[c] == BvhWideNode::kEmpty) continue;
      const Bounds3 b{Vec3(n.b[0][c], n.b[1][c], n.b[2][c]), Vec3(n.b[3][c], n.b[4][c], n.b[5][c])};
      cost += b.halfArea() / rootArea * (n.count[c] > 0 ? double(n.count[c]) : 1.0);
    }
  return cost;
}

}  // namespace whitted
