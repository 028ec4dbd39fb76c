// The parallel build framework shared by the BVH builders (private to accel/*.cpp): a split strategy (binned SAH in
// build_sah.cpp, Morton in build_morton.cpp) decides leaves and splits; buildAll() collapses its binary splits into
// 4-wide nodes top-down, the top on the calling thread (its passes in parallel chunks), the subtrees below as
// parallel tasks, concatenated in a fixed order (the tree never depends on the thread count).
#pragma once

#include "accel/box4.h"
#include "accel/bvh.h"
#include "util/memory.h"
#include "util/parallel.h"

#include <algorithm>
#include <atomic>
#include <cstddef>
#include <cstdint>
#include <utility>
#include <vector>

namespace whitted::bvh_detail {

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

/// Chunks of kChunk primitives covering count.
inline uint32_t chunksOf(uint32_t count) {
  return (count + kChunk - 1) / kChunk;
}

/// Threads for a build or refit of n primitives: one below kParallelMin, else opt.threads (0: all cores).
inline int buildThreads(const BvhBuildOptions& opt, std::size_t n) {
  if (n < kParallelMin) return 1;
  return opt.threads > 0 ? opt.threads : hardwareThreads();
}

// Wide nodes ---------------------------------------------------------------------------------------------------

/// A wide node whose four slots are empty.
inline BvhWideNode emptyWideNode() {
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

/// What a build leaves besides the nodes and the leaf order.
struct BuiltTree {
  int depth = 0;
  Bounds3 bounds;
};

/// Fast (Morton, LBVH) build into wide and primIndices (sized n); build_morton.cpp.
BuiltTree buildMorton(const Bounds3* boxes, const Centroids& centroids, uint32_t n, const BvhBuildOptions& opt,
                      const Vec3& anchor, WorkerPool& pool, BvhWideNodes& wide, std::vector<uint32_t>& primIndices);

/// Binned-SAH build into wide and primIndices (sized n); build_sah.cpp.
BuiltTree buildSah(const Bounds3* boxes, const Centroids& centroids, uint32_t n, const BvhBuildOptions& opt,
                   const Vec3& anchor, WorkerPool& pool, BvhWideNodes& wide, std::vector<uint32_t>& primIndices);

}  // namespace whitted::bvh_detail
