// An object: the geometry of one shape (a triangle mesh, a sphere set or a tube set) with its own BVH over its
// valid primitives, and the leaf order that maps BVH leaf slots to the primitives as given. visitShape() is the one
// place that turns the object's shape type into its compile-time shape class (shape.h), once per object visit.
#pragma once

#include "accel/bvh.h"
#include "geometry/shapes.h"
#include "util/parallel.h"

#include <atomic>
#include <variant>

namespace whitted {

struct Object {
  /// The geometry; its index is the GeometryType. A committed triangle mesh holds its triangles in BVH leaf order
  /// (TriangleShape::kLeafOrdered); originalGeometry() gives them back in the order given.
  std::variant<TriangleMesh, SphereSet, TubeSet> geometry;
  Bvh bvh;
  /// Leaf slot -> index of the primitive as given, for every primitive: the valid ones in leaf order, then the
  /// invalid ones in their order. Empty when every primitive is valid: bvh.primIndices() is then that map.
  std::vector<uint32_t> primOrder;
  Bounds3 bounds;
  bool dirty = true;  ///< Geometry replaced since the last rebuild (then nothing is in leaf order).
  /// This object id's geometry had been built before and was replaced since: rebuilt with the fast builder.
  bool replaced = false;
  /// New positions on the same topology since the last build (see sameTopology): commit refits the BVH.
  bool refitPending = false;
  bool alive = true;
  /// The BVH's SAH cost (Bvh::sahCost) when it was last built; refits are measured against it.
  double builtCost = 0.0;
  /// The builder the BVH came from (a refit keeps it). Scene upgrades Fast trees to SAH ones in the background.
  BvhBuildQuality builtQuality = BvhBuildQuality::Sah;
  /// Which tree the object holds: Scene renews it at every rebuild and refit, so a background build started from
  /// an earlier tree is recognised as stale and dropped. 0 before the first build.
  uint64_t treeVersion = 0;
  /// A refitted BVH whose SAH cost exceeds this many times builtCost is rebuilt (with the fast builder): the
  /// refit keeps the tree's topology, so primitives that moved apart leave ever larger, overlapping boxes and the
  /// trace slows down by about this ratio; a fast rebuild costs about one frame's worth of tracing at that point.
  static constexpr double kRefitRebuildRatio = 1.4;

  GeometryType type() const { return GeometryType(geometry.index()); }
  /// Leaf slot -> primitive as given (see primOrder). Valid after a rebuild.
  const uint32_t* leafPrims() const { return primOrder.empty() ? bvh.primIndices().data() : primOrder.data(); }

  /// Clamps the geometry's colours, builds the BVH (with the given builder) over the valid primitives (non-finite and degenerate ones are
  /// left out) and puts leaf-ordered arrays in leaf order. Returns the number of invalid primitives.
  std::size_t rebuild(BvhBuildQuality quality);
  /// For a background rebuild of this committed object: the boxes and centroids of its valid primitives in their
  /// given order and those primitives' indices, exactly what rebuild() builds from. Only reads the object.
  void validBoxes(std::vector<Bounds3>& boxes, std::vector<Vec3>& centroids, std::vector<uint32_t>& valid) const;
  /// Swaps in a tree built elsewhere from validBoxes() of this committed object (same geometry): leaf-ordered
  /// arrays follow its leaf order, and the object ends as rebuild(quality) would have left it.
  void adoptTree(Bvh tree, const std::vector<uint32_t>& valid, BvhBuildQuality quality);
  /// True if g (of shape type G) has bit-for-bit the geometry this committed object was built from (see
  /// Shape::sameGeometry; leaf-ordered arrays are compared through the leaf order). Cost: one pass over it.
  template <typename G>
  bool sameGeometry(const G& g) const;
  /// True if g (of shape type G) has this committed object's topology: the same number of primitives, the same
  /// leaf-ordered arrays (a mesh's triangles, compared through the leaf order), and every primitive was valid when
  /// the BVH was built. Then only positions (or radii) differ, and refit() can keep the tree. Cost: one pass.
  template <typename G>
  bool sameTopology(const G& g) const;
  /// Recomputes the BVH's boxes bottom-up for the current geometry (same topology, same leaf order). Returns false
  /// and changes nothing if some primitive is no longer valid (then the caller rebuilds).
  bool refit();
  /// The refitted tree's SAH cost over its cost when built (1 right after a build; 0 if unknown).
  double refitCostRatio() const { return builtCost > 0.0 ? bvh.sahCost() / builtCost : 0.0; }
  /// Memory held: geometry, BVH and leaf order (allocated capacity), bytes.
  std::size_t memoryBytes() const;
  /// Puts leaf-ordered arrays back in the order given and marks the object for a (fast) rebuild.
  void markForRebuild();
  /// True if g's leaf-ordered arrays (given order) equal stored's (leaf order), compared through the leaf order;
  /// true for shapes without such arrays.
  template <typename G>
  bool sameLeafOrdered(const G& stored, const G& g) const;
  /// Replaces the attributes by g's, keeping the geometry (for which sameGeometry(g) holds), BVH and leaf order.
  template <typename G>
  void replaceAttributes(G&& g);
  /// A copy of the geometry as given (leaf-ordered arrays back in their original order), or an empty G if the
  /// object has another shape.
  template <typename G>
  G originalGeometry() const;
};

/// The shape class of a geometry container.
template <typename G>
struct ShapeOf;
template <>
struct ShapeOf<TriangleMesh> {
  using type = TriangleShape;
};
template <>
struct ShapeOf<SphereSet> {
  using type = SphereShape;
};
template <>
struct ShapeOf<TubeSet> {
  using type = TubeShape;
};

/// Calls fn(Shape{}, geometry) with the object's shape class and its geometry (const if o is): the one switch on
/// the shape type, so everything fn runs, per-primitive loops included, is compiled for one shape.
template <typename O, typename Fn>
decltype(auto) visitShape(O& o, Fn&& fn) {
  switch (o.type()) {
    case GeometryType::Triangles:
      return fn(TriangleShape{}, *std::get_if<TriangleMesh>(&o.geometry));
    case GeometryType::Spheres:
      return fn(SphereShape{}, *std::get_if<SphereSet>(&o.geometry));
    case GeometryType::Tubes:
      break;
  }
  return fn(TubeShape{}, *std::get_if<TubeSet>(&o.geometry));
}

template <typename G>
bool Object::sameLeafOrdered(const G& stored, const G& g) const {
  using Shape = typename ShapeOf<G>::type;
  if constexpr (Shape::kLeafOrdered) {
    const auto &mine = Shape::leafOrdered(stored), &theirs = Shape::leafOrdered(g);
    if (mine.size() != theirs.size()) return false;
    const uint32_t* order = leafPrims();
    // A gather through the leaf order (1M triangles: about 5 ms on one core): large arrays on all cores, in
    // pieces that stop once any piece found a difference
    constexpr std::size_t kPiece = 65536;
    std::atomic<bool> same{true};
    WorkerPool pool(mine.size() >= 4 * kPiece ? hardwareThreads() : 1);
    forChunks(pool, mine.size(), kPiece, [&](std::size_t b, std::size_t e) {
      if (!same.load(std::memory_order_relaxed)) return;
      for (std::size_t k = b; k < e; ++k)
        if (mine[k] != theirs[order[k]]) {
          same.store(false, std::memory_order_relaxed);
          return;
        }
    });
    return same.load();
  }
  return true;
}

template <typename G>
bool Object::sameGeometry(const G& g) const {
  using Shape = typename ShapeOf<G>::type;
  const G* stored = std::get_if<G>(&geometry);
  if (!alive || dirty || !stored || !Shape::sameGeometry(*stored, g)) return false;
  return sameLeafOrdered(*stored, g);
}

template <typename G>
bool Object::sameTopology(const G& g) const {
  using Shape = typename ShapeOf<G>::type;
  const G* stored = std::get_if<G>(&geometry);
  if (!alive || dirty || !stored || !primOrder.empty() || Shape::count(*stored) != Shape::count(g)) return false;
  return sameLeafOrdered(*stored, g);
}

template <typename G>
void Object::replaceAttributes(G&& g) {
  using Shape = typename ShapeOf<std::decay_t<G>>::type;
  auto& stored = std::get<std::decay_t<G>>(geometry);
  if constexpr (Shape::kLeafOrdered) {
    auto leafOrder = std::move(Shape::leafOrdered(stored));
    stored = std::forward<G>(g);
    Shape::leafOrdered(stored) = std::move(leafOrder);
  } else {
    stored = std::forward<G>(g);
  }
  Shape::sanitize(stored);
}

template <typename G>
G Object::originalGeometry() const {
  using Shape = typename ShapeOf<G>::type;
  const G* stored = std::get_if<G>(&geometry);
  if (!stored) return G{};
  G out = *stored;
  if constexpr (Shape::kLeafOrdered) {
    if (alive && !dirty) {
      const auto& leafOrdered = Shape::leafOrdered(*stored);
      auto& given = Shape::leafOrdered(out);
      const uint32_t* order = leafPrims();
      for (std::size_t k = 0; k < leafOrdered.size(); ++k) given[order[k]] = leafOrdered[k];
    }
  }
  return out;
}

}  // namespace whitted
