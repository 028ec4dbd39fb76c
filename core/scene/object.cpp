#include "scene/object.h"

#include "util/parallel.h"

namespace whitted {

namespace {

/// Objects of at least this many primitives compute their boxes and reorder their arrays on all cores, in pieces of
/// kPiece primitives (fixed: the result does not depend on the thread count).
constexpr std::size_t kParallelMin = 32768;
constexpr std::size_t kPiece = 8192;

int threadsFor(std::size_t n) {
  return n >= kParallelMin ? hardwareThreads() : 1;
}

/// Leaf order of every primitive after o.bvh was built over the valid primitives `valid` of n (given order), and
/// leaf-ordered arrays (stored in the given order) put in that order.
template <typename Shape>
void applyLeafOrder(Object& o, typename Shape::Geometry& g, const uint32_t* valid, std::size_t nValid, std::size_t n) {
  // Leaf order of every primitive (only needed when some are left out: otherwise it is the BVH's own order)
  o.primOrder.clear();
  if (nValid < n) {
    o.primOrder.reserve(n);
    for (uint32_t i : o.bvh.primIndices()) o.primOrder.push_back(valid[i]);
    std::size_t next = 0;  // valid is increasing: the others are the gaps
    for (uint32_t i = 0; i < n; ++i) {
      if (next < nValid && valid[next] == i)
        ++next;
      else
        o.primOrder.push_back(i);
    }
  }
  if constexpr (Shape::kLeafOrdered) {
    auto& stored = Shape::leafOrdered(g);
    std::remove_reference_t<decltype(stored)> leafOrdered(stored.size());
    const uint32_t* order = o.leafPrims();
    WorkerPool pool(threadsFor(stored.size()));
    forChunks(pool, stored.size(), kPiece, [&](std::size_t b, std::size_t e) {
      for (std::size_t k = b; k < e; ++k) leafOrdered[k] = stored[order[k]];
    });
    stored = std::move(leafOrdered);
  }
  o.dirty = false;
}

template <typename Shape>
std::size_t rebuildShape(Object& o, typename Shape::Geometry& g, BvhBuildQuality quality) {
  Shape::sanitize(g);

  // Boxes of valid primitives; non-finite and degenerate ones are left out of the BVH. Each piece keeps its valid
  // ones at its start, then the pieces close ranks in order: the same arrays as one pass in order. Scratch arrays
  // (uninitialised, first touched by the parallel fill: see ScratchArray)
  const std::size_t n = Shape::count(g);
  ScratchArray<Bounds3> boxes(n);
  ScratchArray<uint32_t> valid(n);
  const std::size_t pieces = (n + kPiece - 1) / kPiece;
  std::vector<std::size_t> kept(pieces);
  std::vector<Bounds3> pieceBounds(pieces);
  WorkerPool pool(threadsFor(n));
  forChunks(pool, n, kPiece, [&](std::size_t b, std::size_t e) {
    std::size_t m = b;
    Bounds3 box, all;
    for (std::size_t i = b; i < e; ++i) {
      if (!Shape::bounds(g, uint32_t(i), box)) continue;
      boxes[m] = box;
      valid[m++] = uint32_t(i);
      all.extend(box);
    }
    kept[b / kPiece] = m - b;
    pieceBounds[b / kPiece] = all;
  });
  std::size_t nValid = 0;
  o.bounds = Bounds3();
  for (std::size_t k = 0; k < pieces; ++k) {
    const std::size_t b = k * kPiece;
    if (nValid != b) {  // some primitive before was left out
      std::copy(boxes.data() + b, boxes.data() + b + kept[k], boxes.data() + nValid);
      std::copy(valid.data() + b, valid.data() + b + kept[k], valid.data() + nValid);
    }
    nValid += kept[k];
    o.bounds.extend(pieceBounds[k]);
  }
  BvhBuildOptions opt;
  opt.quality = quality;
  o.bvh.build(boxes.data(), nullptr, nValid, opt);  // centroids: the boxes' centres
  o.builtCost = o.bvh.sahCost();
  o.builtQuality = quality;
  applyLeafOrder<Shape>(o, g, valid.data(), nValid, n);
  return n - nValid;
}

template <typename Shape>
bool refitShape(Object& o, typename Shape::Geometry& g) {
  Shape::sanitize(g);
  const std::size_t n = Shape::count(g);
  const std::vector<uint32_t>& order = o.bvh.primIndices();  // leaf slot -> primitive (all were valid)
  if (!o.primOrder.empty() || order.size() != n) return false;
  // Boxes in leaf order (leaf-ordered geometry is read in its stored order: no scatter, no gather), made and
  // rounded by the tree in slices on all cores; the object's box merges the slices' boxes in slice order (the same
  // bits, -0 and +0 included, whichever thread made which)
  std::vector<Bounds3> sliceBounds((n + Bvh::kRefitSlice - 1) / Bvh::kRefitSlice);
  const bool valid = o.bvh.refitLeafOrder(n, [&](std::size_t b, std::size_t e, Bounds3* boxes) {
    Bounds3 slice;
    for (std::size_t k = b; k < e; ++k) {
      if (!Shape::bounds(g, Shape::kLeafOrdered ? uint32_t(k) : order[k], boxes[k - b])) return false;
      slice.extend(boxes[k - b]);
    }
    sliceBounds[b / Bvh::kRefitSlice] = slice;
    return true;
  });
  if (!valid) return false;
  Bounds3 all;
  for (const Bounds3& b : sliceBounds) all.extend(b);
  o.bounds = all;
  return true;
}

}  // namespace

bool Object::refit() {
  return visitShape(*this, [&](auto shape, auto& g) { return refitShape<decltype(shape)>(*this, g); });
}

void Object::validBoxes(std::vector<Bounds3>& boxes, std::vector<Vec3>& centroids, std::vector<uint32_t>& valid) const {
  visitShape(*this, [&](auto shape, const auto& g) {
    using Shape = decltype(shape);
    // Slots [0, nValid) of the leaf order hold the valid primitives; rank: given index -> index among the valid
    // ones in given order (the identity when all are valid, the common case: no map then)
    const std::size_t n = Shape::count(g), nValid = bvh.primIndices().size();
    const uint32_t* order = leafPrims();
    std::vector<uint32_t> rank;
    valid.clear();
    if (nValid < n) {
      rank.assign(n, ~0u);
      for (std::size_t k = 0; k < nValid; ++k) rank[order[k]] = 0;
      for (uint32_t i = 0; i < n; ++i)
        if (rank[i] == 0) {
          rank[i] = uint32_t(valid.size());
          valid.push_back(i);
        }
    } else {
      valid.resize(n);
      for (uint32_t i = 0; i < n; ++i) valid[i] = i;
    }
    boxes.resize(nValid);
    centroids.resize(nValid);
    Bounds3 box;
    for (uint32_t k = 0; k < nValid; ++k) {
      Shape::bounds(g, Shape::kLeafOrdered ? k : order[k], box);  // valid: it was when built
      const uint32_t j = rank.empty() ? order[k] : rank[order[k]];
      boxes[j] = box;
      centroids[j] = box.center();
    }
  });
}

void Object::adoptTree(Bvh tree, const std::vector<uint32_t>& valid, BvhBuildQuality quality) {
  visitShape(*this, [&](auto shape, auto& g) {
    using Shape = decltype(shape);
    if constexpr (Shape::kLeafOrdered) {
      // Leaf-ordered arrays back to their given order, then into the new tree's
      auto& stored = Shape::leafOrdered(g);
      std::remove_reference_t<decltype(stored)> given(stored.size());
      const uint32_t* order = leafPrims();
      for (std::size_t k = 0; k < stored.size(); ++k) given[order[k]] = stored[k];
      stored = std::move(given);
    }
    bvh = std::move(tree);
    builtCost = bvh.sahCost();
    builtQuality = quality;
    applyLeafOrder<Shape>(*this, g, valid.data(), valid.size(), Shape::count(g));
  });
}

void Object::markForRebuild() {
  visitShape(*this, [&](auto, auto& g) {
    using G = std::decay_t<decltype(g)>;
    g = originalGeometry<G>();
  });
  dirty = replaced = true;
}

std::size_t Object::memoryBytes() const {
  const std::size_t geometryBytes =
      visitShape(*this, [](auto shape, const auto& g) { return decltype(shape)::bytes(g); });
  return geometryBytes + bvh.memoryBytes() + primOrder.capacity() * sizeof(uint32_t);
}

std::size_t Object::rebuild(BvhBuildQuality quality) {
  return visitShape(*this, [&](auto shape, auto& g) { return rebuildShape<decltype(shape)>(*this, g, quality); });
}

}  // namespace whitted
