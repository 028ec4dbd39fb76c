// Bvh::refit (node boxes recomputed for moved primitives, same topology) and Bvh::sahCost (the tree's expected
// trace cost, which tells when a refitted tree should be rebuilt).
#include "accel/refit.h"
#include "accel/box4.h"
#include "accel/build_common.h"
#include "accel/bvh.h"
#include "util/parallel.h"

#include <cmath>
#include <cstdint>
#include <stdexcept>
#include <vector>

namespace whitted {

using namespace bvh_detail;

void Bvh::refit(const std::vector<Bounds3>& boxes) {
  refitFrom(boxes.data(), boxes.size(), true);
}

void Bvh::refitFrom(const Bounds3* boxes, std::size_t n, bool gather) {
  if (n != primIndices_.size()) throw std::invalid_argument("Bvh::refit: primitive count differs");
  if (wide_.empty()) return;
  WorkerPool pool(buildThreads(BvhBuildOptions(), n));
  const LeafOrderBoxes leafBox(boxes, uint32_t(n), gather ? primIndices_.data() : nullptr, anchor_, pool);
  bounds_ = toBounds(Refitter<LeafOrderBoxes>{wide_, leafBox}.all(pool), anchor_);
}

bool Bvh::refitLeafOrder(std::size_t n, const LeafBoxFill& fill) {
  if (n != primIndices_.size()) throw std::invalid_argument("Bvh::refit: primitive count differs");
  if (wide_.empty()) return true;
  WorkerPool pool(buildThreads(BvhBuildOptions(), n));
  LeafOrderBoxes leafBox(uint32_t(n), pool, [&](uint32_t first, uint32_t end, Box4* out) {
    // In slices of a chunk, so the double boxes stay in a small buffer
    constexpr uint32_t kSlice = uint32_t(kRefitSlice);
    static_assert(kChunk % kSlice == 0, "slices start at multiples of kRefitSlice");
    Bounds3 boxes[kSlice];
    for (uint32_t b = first; b < end; b += kSlice) {
      const uint32_t e = std::min(end, b + kSlice);
      if (!fill(b, e, boxes)) return false;
      for (uint32_t i = b; i < e; ++i) new (&out[i - first]) Box4(roundedBox(boxes[i - b], anchor_));
    }
    return true;
  });
  if (!leafBox.valid) return false;
  bounds_ = toBounds(Refitter<LeafOrderBoxes>{wide_, leafBox}.all(pool), anchor_);
  return true;
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
