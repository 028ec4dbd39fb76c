// Bvh::build: the anchor, the build threads, and the choice between the SAH and Morton builders (build_sah.cpp,
// build_morton.cpp); a cancelled or failed build leaves an empty tree.
#include "accel/build_common.h"
#include "accel/bvh.h"
#include "util/parallel.h"

#include <atomic>
#include <cstdint>
#include <exception>

namespace whitted {

using namespace bvh_detail;

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

}  // namespace whitted
