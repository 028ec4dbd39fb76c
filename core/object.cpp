#include "object.h"

namespace whitted {

namespace {

template <typename Shape>
std::size_t rebuildShape(Object& o, typename Shape::Geometry& g, BvhBuildQuality quality) {
  Shape::sanitize(g);

  // Boxes of valid primitives; non-finite and degenerate ones are left out of the BVH
  const std::size_t n = Shape::count(g);
  std::vector<Bounds3> boxes;
  std::vector<Vec3> centroids;
  std::vector<uint32_t> valid;
  boxes.reserve(n);
  centroids.reserve(n);
  valid.reserve(n);
  o.bounds = Bounds3();
  Bounds3 box;
  for (uint32_t i = 0; i < n; ++i) {
    if (!Shape::bounds(g, i, box)) continue;
    boxes.push_back(box);
    centroids.push_back(box.center());
    valid.push_back(i);
    o.bounds.extend(box);
  }
  BvhBuildOptions opt;
  opt.quality = quality;
  o.bvh.build(boxes, centroids, opt);
  o.builtCost = o.bvh.sahCost();

  // Leaf order of every primitive (only needed when some are left out: otherwise it is the BVH's own order)
  o.primOrder.clear();
  if (valid.size() < n) {
    o.primOrder.reserve(n);
    for (uint32_t i : o.bvh.primIndices()) o.primOrder.push_back(valid[i]);
    std::size_t next = 0;  // valid is increasing: the others are the gaps
    for (uint32_t i = 0; i < n; ++i) {
      if (next < valid.size() && valid[next] == i)
        ++next;
      else
        o.primOrder.push_back(i);
    }
  }
  if constexpr (Shape::kLeafOrdered) {
    auto& stored = Shape::leafOrdered(g);
    std::remove_reference_t<decltype(stored)> leafOrdered(stored.size());
    const uint32_t* order = o.leafPrims();
    for (std::size_t k = 0; k < leafOrdered.size(); ++k) leafOrdered[k] = stored[order[k]];
    stored = std::move(leafOrdered);
  }
  o.dirty = false;
  return n - valid.size();
}

template <typename Shape>
bool refitShape(Object& o, typename Shape::Geometry& g) {
  Shape::sanitize(g);
  const std::size_t n = Shape::count(g);
  const std::vector<uint32_t>& order = o.bvh.primIndices();  // leaf slot -> primitive (all were valid)
  if (!o.primOrder.empty() || order.size() != n) return false;
  // Boxes in leaf order (leaf-ordered geometry is read in its stored order: no scatter, no gather)
  std::vector<Bounds3> boxes;
  boxes.reserve(n);
  Bounds3 all, box;
  for (uint32_t k = 0; k < n; ++k) {
    if (!Shape::bounds(g, Shape::kLeafOrdered ? k : order[k], box)) return false;
    boxes.push_back(box);
    all.extend(box);
  }
  o.bvh.refitLeafOrder(boxes);
  o.bounds = all;
  return true;
}

}  // namespace

bool Object::refit() {
  return visitShape(*this, [&](auto shape, auto& g) { return refitShape<decltype(shape)>(*this, g); });
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
