#include "bvh.h"

#include <algorithm>
#include <array>
#include <exception>
#include <limits>
#include <numeric>
#include <thread>

namespace whitted {

namespace {

// Node bounds are stored as floats stepped one ulp outward (always, not only when rounding went inward), so a
// ray grazing a face with a tiny slope still enters the node.
float roundDown(double x) {
  float f = static_cast<float>(x);
  if (double(f) > x || double(f) == x) f = std::nextafter(f, -std::numeric_limits<float>::infinity());
  return f;
}
float roundUp(double x) {
  float f = static_cast<float>(x);
  if (double(f) < x || double(f) == x) f = std::nextafter(f, std::numeric_limits<float>::infinity());
  return f;
}

/// Bin of a centroid coordinate; robust to NaN and to out-of-range products (huge or denormal extents).
int binIndex(double c, double lo, double scale, int nb) {
  double f = (c - lo) * scale;
  if (!(f > 0.0)) return 0;  // also catches NaN
  return f < double(nb) ? int(f) : nb - 1;
}

constexpr int kMaxBins = 32;
constexpr uint32_t kParallelMin = 65536;  // primitives below which a subtree is built on the current thread
constexpr int kParallelDepth = 2;         // levels that fork: up to 4 concurrent builders

struct Builder {
  const std::vector<Bounds3>& boxes;
  const std::vector<Vec3>& centroids;
  const BvhBuildOptions& opt;
  std::vector<BvhNode>& nodes;
  std::vector<uint32_t>& idx;
  Vec3 anchor;  // node boxes are stored relative to it
  int maxDepth = 0;

  void setBounds(BvhNode& n, const Bounds3& b) {
    // The subtraction rounds once; roundDown / roundUp step strictly outward, at least one double ulp (so the
    // float box contains the exact difference)
    for (int i = 0; i < 3; ++i) {
      n.lo[i] = roundDown(b.lo[i] - anchor[i]);
      n.hi[i] = roundUp(b.hi[i] - anchor[i]);
    }
  }

  void makeLeaf(uint32_t node, uint32_t begin, uint32_t end) {
    nodes[node].first = begin;
    nodes[node].count = end - begin;
  }

  // Recursively splits idx[begin, end) into the subtree rooted at node.
  void split(uint32_t node, uint32_t begin, uint32_t end, int depth) {
    maxDepth = std::max(maxDepth, depth);
    Bounds3 box, cbox;
    for (uint32_t i = begin; i < end; ++i) {
      box.extend(boxes[idx[i]]);
      cbox.extend(centroids[idx[i]]);
    }
    setBounds(nodes[node], box);
    uint32_t count = end - begin;
    if (count <= 1) return makeLeaf(node, begin, end);

    // Binned SAH over all three axes
    const int nb = std::clamp(opt.bins, 2, kMaxBins);
    int bestAxis = -1, bestBin = 0;
    double bestCost = kInfinity;
    Vec3 cext = cbox.extent();
    if (depth < Bvh::kSahDepthLimit) {
      for (int axis = 0; axis < 3; ++axis) {
        if (!(cext[axis] > 0.0) || !std::isfinite(cext[axis]) || !std::isfinite(nb / cext[axis])) continue;
        std::array<Bounds3, kMaxBins> binBox;
        std::array<uint32_t, kMaxBins> binCount{};
        double scale = nb / cext[axis];
        for (uint32_t i = begin; i < end; ++i) {
          int b = binIndex(centroids[idx[i]][axis], cbox.lo[axis], scale, nb);
          binBox[b].extend(boxes[idx[i]]);
          ++binCount[b];
        }
        // Sweep from the right, then from the left
        std::array<double, kMaxBins> rightCost{};
        Bounds3 acc;
        uint32_t n = 0;
        for (int b = nb - 1; b > 0; --b) {
          acc.extend(binBox[b]);
          n += binCount[b];
          rightCost[b] = n ? acc.halfArea() * n : 0.0;
        }
        acc = Bounds3();
        n = 0;
        for (int b = 0; b < nb - 1; ++b) {
          acc.extend(binBox[b]);
          n += binCount[b];
          if (n == 0 || n == count) continue;
          double cost = acc.halfArea() * n + rightCost[b + 1];
          if (cost < bestCost) {
            bestCost = cost;
            bestAxis = axis;
            bestBin = b;
          }
        }
      }
    }

    double parentArea = box.halfArea();
    double leafCost = double(count);
    double splitCost = bestAxis >= 0 && parentArea > 0.0 ? opt.traversalCost + bestCost / parentArea : kInfinity;
    uint32_t mid;
    if (bestAxis >= 0 && (splitCost < leafCost || count > uint32_t(opt.maxLeafSize))) {
      double scale = nb / cext[bestAxis];
      auto it = std::partition(idx.begin() + begin, idx.begin() + end, [&](uint32_t p) {
        int b = binIndex(centroids[p][bestAxis], cbox.lo[bestAxis], scale, nb);
        return b <= bestBin;
      });
      mid = uint32_t(it - idx.begin());
    } else if (count <= uint32_t(opt.maxLeafSize)) {
      return makeLeaf(node, begin, end);
    } else {
      // No SAH split (coincident centroids or depth limit): median split on the widest centroid axis
      int axis = cext.x >= cext.y ? (cext.x >= cext.z ? 0 : 2) : (cext.y >= cext.z ? 1 : 2);
      mid = begin + count / 2;
      std::nth_element(idx.begin() + begin, idx.begin() + mid, idx.begin() + end,
                       [&](uint32_t a, uint32_t b) { return centroids[a][axis] < centroids[b][axis]; });
    }
    if (mid == begin || mid == end) mid = begin + count / 2;

    uint32_t left = uint32_t(nodes.size());
    nodes.push_back({});
    nodes.push_back({});
    nodes[node].first = left;
    nodes[node].count = 0;
    // Large subtrees build in parallel (each in its own node array, spliced in afterwards)
    if (count >= kParallelMin && depth <= kParallelDepth) {
      std::vector<BvhNode> rightNodes(1);
      Builder rightBuilder{boxes, centroids, opt, rightNodes, idx, anchor};
      // Exceptions (std::bad_alloc) must not escape a thread or unwind past a joinable one: carry them back
      std::exception_ptr workerError;
      std::thread worker([&] {
        try {
          rightBuilder.split(0, mid, end, depth + 1);
        } catch (...) {
          workerError = std::current_exception();
        }
      });
      try {
        split(left, begin, mid, depth + 1);
      } catch (...) {
        worker.join();
        throw;
      }
      worker.join();
      if (workerError) std::rethrow_exception(workerError);
      splice(left + 1, rightNodes);
      maxDepth = std::max(maxDepth, rightBuilder.maxDepth);
    } else {
      split(left, begin, mid, depth + 1);
      split(left + 1, mid, end, depth + 1);
    }
  }

  // Copies a subtree built in its own array (root at 0) to slot `at`, re-basing child indices.
  void splice(uint32_t at, const std::vector<BvhNode>& sub) {
    uint32_t base = uint32_t(nodes.size()) - 1;  // sub[i] (i >= 1) goes to base + i
    for (std::size_t i = 1; i < sub.size(); ++i) {
      BvhNode n = sub[i];
      if (n.count == 0) n.first += base;
      nodes.push_back(n);
    }
    BvhNode root = sub[0];
    if (root.count == 0) root.first += base;
    nodes[at] = root;
  }
};

}  // namespace

void Bvh::build(const std::vector<Bounds3>& boxes, const std::vector<Vec3>& centroids, const BvhBuildOptions& opt) {
  wide_.clear();
  bounds_ = Bounds3();
  primIndices_.clear();
  depth_ = 0;
  if (boxes.empty()) return;
  primIndices_.resize(boxes.size());
  std::iota(primIndices_.begin(), primIndices_.end(), 0u);
  // The binary SAH tree exists only here: it is collapsed into the wide traversal nodes and freed
  std::vector<BvhNode> binary;
  binary.reserve(2 * boxes.size());
  binary.push_back({});
  for (const Bounds3& box : boxes) bounds_.extend(box);
  // Anchor at the centre, so float node boxes keep their precision for objects far from the origin
  anchor_ = isFinite(bounds_.center()) ? bounds_.center() : Vec3(0.0);
  Builder b{boxes, centroids, opt, binary, primIndices_, anchor_};
  b.split(0, 0, uint32_t(boxes.size()), 1);
  depth_ = b.maxDepth;
  collapse(binary);
}

void Bvh::collapse(const std::vector<BvhNode>& binary) {
  // Each wide node takes a binary inner node's children and keeps opening the inner child of largest surface
  // area until it has four (Embree's and tinybvh's collapse). A root leaf becomes a wide root with one child.
  wide_.reserve(binary.size() / 2 + 1);
  auto area = [&](uint32_t i) {
    const BvhNode& n = binary[i];
    const double dx = double(n.hi[0]) - n.lo[0], dy = double(n.hi[1]) - n.lo[1], dz = double(n.hi[2]) - n.lo[2];
    return dx * dy + dy * dz + dz * dx;
  };
  // Explicit work list (binary node, wide slot) instead of recursion
  std::vector<std::pair<uint32_t, uint32_t>> work;
  wide_.emplace_back();
  work.emplace_back(0u, 0u);
  while (!work.empty()) {
    const auto [bin, slot] = work.back();
    work.pop_back();
    uint32_t children[4] = {bin, 0, 0, 0};
    int n = 1;
    if (binary[bin].count == 0) {
      children[0] = binary[bin].first;
      children[1] = binary[bin].first + 1;
      n = 2;
    }
    while (n < 4) {
      int best = -1;
      double bestArea = -1.0;
      for (int c = 0; c < n; ++c) {
        const double a = binary[children[c]].count == 0 ? area(children[c]) : -1.0;
        if (a > bestArea) {
          bestArea = a;
          best = c;
        }
      }
      if (best < 0) break;
      const uint32_t opened = children[best];
      children[best] = binary[opened].first;
      children[n++] = binary[opened].first + 1;
    }
    // Unused slots are empty: inverted boxes, count kEmpty
    BvhWideNode w;
    for (int c = 0; c < 4; ++c) {
      const bool used = c < n;
      for (int k = 0; k < 3; ++k) {
        w.b[k][c] = used ? binary[children[c]].lo[k] : std::numeric_limits<float>::infinity();
        w.b[3 + k][c] = used ? binary[children[c]].hi[k] : -std::numeric_limits<float>::infinity();
      }
      w.first[c] = used ? binary[children[c]].first : 0;
      w.count[c] = used ? binary[children[c]].count : BvhWideNode::kEmpty;
      if (used && w.count[c] == 0) {  // inner: allocate its wide node and queue it
        w.first[c] = uint32_t(wide_.size());
        wide_.emplace_back();
        work.emplace_back(children[c], w.first[c]);
      }
    }
    wide_[slot] = w;
  }
  wide_.shrink_to_fit();
}

}  // namespace whitted
