// The two-level traversal: closest hit (with its tie-break between hits at the same distance), shadow-ray
// transmittance (counting each surface crossing once) and the surface data at a hit. The top level walks the
// instances' BVH; each object visit dispatches once on the object's shape (visitShape) to a traversal compiled for
// that shape, so the per-primitive loops contain no switch.
#include "scene/scene.h"

#include <algorithm>
#include <new>
#include <type_traits>

namespace whitted {

namespace {

/// Error bound of an affine transform applied to a point p with error e (pbrt-v4 Transform::operator()).
Vec3 transformError(const Mat4& m, const Vec3& p, const Vec3& e) {
  Vec3 out(0.0);
  for (int r = 0; r < 3; ++r) {
    double absMp = std::abs(m[3][r]), absMe = 0.0;
    for (int c = 0; c < 3; ++c) {
      absMp += std::abs(m[c][r] * p[c]);
      absMe += std::abs(m[c][r]) * e[c];
    }
    out[r] = (1.0 + gammaBound(3)) * absMe + gammaBound(3) * absMp;
  }
  return out;
}

/// Surface crossings of one instance already counted by a shadow ray, to recognise the same crossing reported again
/// by a neighbouring primitive (a shared edge or vertex, a tube joint). Fixed size, no allocation: boundary hits
/// are rare (only exact edge/vertex hits of triangles, caps and seams of tubes), and past kSize the oldest
/// entries are overwritten (a later duplicate of an overwritten crossing is then counted again).
class CountedCrossings {
 public:
  /// True if a crossing at t (rounding error tError) was counted already; otherwise records it and returns false.
  bool seenOrAdd(double t, double tError) {
    for (uint32_t i = 0, n = std::min(n_, kSize); i < n; ++i)
      if (std::abs(t - t_[i]) <= tError + error_[i]) return true;
    t_[n_ & (kSize - 1)] = t;
    error_[n_ & (kSize - 1)] = tError;
    ++n_;
    return false;
  }
  void clear() { n_ = 0; }

 private:
  static constexpr uint32_t kSize = 16;  // a power of two
  double t_[kSize];
  double error_[kSize];
  uint32_t n_ = 0;
};

/// Where o's leaf primitives live, for the traversal's prefetches (shapes stored in leaf order only).
template <typename Shape>
LeafData leafData(const typename Shape::Geometry& g) {
  if constexpr (Shape::kLeafOrdered) {
    const auto& a = Shape::leafOrdered(g);
    return LeafData{a.data(), uint32_t(sizeof(a[0]))};
  } else {
    return LeafData{};
  }
}

/// Hits within kTieRelative * t of the best one count as the same distance: the lower (instance, primitive) wins,
/// so coplanar overlapping surfaces never speckle. This is a fixed rule, not OpenGL's draw order: instance ids
/// follow the order in which the caller added the instances (the VTK adapter: the order actors were first
/// converted), so which of two coplanar surfaces shows may differ from OpenGL's image (README, "Coplanar
/// surfaces"). The rule does not depend on the order in which the hits are met (so a packet, which visits leaves
/// in another order, finds the single ray's hit).
constexpr double kTieRelative = 1e-10;

/// Leaf test of a closest-hit walk: primitive slots [first, first+count) of instance's object against the
/// object-space ray, whose limit is tm; keeps the best hit by the tie rule and returns true if hit changed.
/// Performance note: the limit is widened by the tie tolerance so tying candidates are not culled.
template <typename Shape>
[[gnu::always_inline]] inline bool closestLeaf(const typename Shape::Tester& test, const uint32_t* leafPrims, uint32_t instance, const Ray& ray,
                 double tLimit, uint32_t first, uint32_t count, double& tm, Hit& hit) {
  bool found = false;
  PrimHit h;
  for (uint32_t s = first; s < first + count; ++s) {
    if (test.hit(s, ray, tm, h)) {
      uint32_t prim = leafPrims[s];
      double tie = kTieRelative * std::abs(hit.t);
      bool better = !(h.t >= hit.t - tie);  // clearly closer (or the first hit)
      if (!better && h.t <= hit.t + tie)
        better = instance < hit.instance || (instance == hit.instance && prim < hit.prim);
      if (better) {
        hit.t = h.t;
        hit.instance = instance;
        hit.prim = prim;
        hit.slot = s;
        hit.u = h.u;
        hit.v = h.v;
        tm = std::min(tLimit, hit.t + kTieRelative * std::abs(hit.t));
        found = true;
      }
    }
  }
  return found;
}

/// Closest hit of an object-space ray with object o of shape Shape (instance: its instance id, for the tie-break)
/// within tLimit (ray.tMax is not read: a world ray serves an identity instance without a copy). Shrinks tMax and
/// updates hit; returns true if hit changed.
template <typename Shape>
bool closestHit(const Object& o, const typename Shape::Geometry& g, uint32_t instance, const Ray& ray, double tLimit,
                double& tMax, Hit& hit, uint64_t* nodes) {
  const uint32_t* leafPrims = o.leafPrims();
  return o.bvh.traverse<false>(
      ray, tMax,
      [&, test = typename Shape::Tester(g, leafPrims, ray)](uint32_t first, uint32_t count, double& tm) {
        return closestLeaf<Shape>(test, leafPrims, instance, ray, tLimit, first, count, tm, hit);
      },
      nodes, leafData<Shape>(g));
}

/// closestHit() of object o by its shape (one switch; the shape's traversal is compiled for it).
bool closestInObject(const Object& o, uint32_t instance, const Ray& ray, double& tMax, Hit& hit, uint64_t* nodes) {
  const double tLimit = tMax;
  return visitShape(o, [&](auto shape, const auto& g) {
    return closestHit<decltype(shape)>(o, g, instance, ray, tLimit, tMax, hit, nodes);
  });
}

/// Testers (a Tester has no default constructor) for the active rays of a packet, set up in place.
template <typename Shape>
struct PacketTesters {
  using Tester = typename Shape::Tester;
  static_assert(std::is_trivially_destructible_v<Tester>, "the testers are never destroyed");
  alignas(Tester) unsigned char storage[4][sizeof(Tester)];
  const Tester* test[4] = {};
  PacketTesters(const typename Shape::Geometry& g, const uint32_t* leafPrims, const Ray* r, unsigned active) {
    for (unsigned m = active; m; m &= m - 1) {
      const int i = __builtin_ctz(m);
      test[i] = new (storage[i]) Tester(g, leafPrims, r[i]);
    }
  }
  const Tester& operator[](int i) const { return *test[i]; }
};

/// closestHit() for the object-space rays r[i] of the bit mask active, walking o's tree as one packet (tMax[i],
/// hit[i]: each ray's). Returns the mask of rays whose hit changed.
template <typename Shape>
unsigned closestHit4(const Object& o, const typename Shape::Geometry& g, uint32_t instance, const Ray* r,
                     unsigned active, double* tMax, Hit* hit, uint64_t* nodes) {
  const uint32_t* leafPrims = o.leafPrims();
  const PacketTesters<Shape> test(g, leafPrims, r, active);
  return o.bvh.traverse4(
      r, active, tMax,
      [&](uint32_t first, uint32_t count, unsigned rays, double* tm) {
        unsigned found = 0;
        for (unsigned m = rays; m; m &= m - 1) {
          const int i = __builtin_ctz(m);
          if (closestLeaf<Shape>(test[i], leafPrims, instance, r[i], r[i].tMax, first, count, tm[i], hit[i]))
            found |= 1u << i;
        }
        return found;
      },
      nodes, leafData<Shape>(g));
}

/// Shadow ray r (object space) through object o of shape Shape with transmittance kt: multiplies atten by kt at
/// every crossing not counted already. Returns true when the ray is blocked (an opaque surface, or atten below
/// cutoff: then cut is set).
template <typename Shape>
bool crossObject(const Object& o, const typename Shape::Geometry& g, const Ray& r, const Color& kt, float cutoff,
                 Color& atten, CountedCrossings& counted, bool& cut, uint64_t* nodes) {
  const bool opaque = maxComponent(kt) <= 0.0f;
  double tm = r.tMax;
  const typename Shape::Tester test(g, o.leafPrims(), r);
  return o.bvh.traverse<true>(
      r, tm,
      [&](uint32_t f, uint32_t c, double&) {
        for (uint32_t k = f; k < f + c; ++k) {
          // Every crossing of a transmissive surface multiplies by kt once; an opaque one blocks. A hit on a
          // primitive boundary that coincides (within both rounding bounds) with a boundary hit counted
          // already is the same crossing seen by a neighbour (shared edge or vertex, tube joint): skipped.
          PrimHit h;
          if (!test.hit(k, r, r.tMax, h)) continue;
          if (opaque) return true;
          Ray rr = r;
          for (int guard = 0;;) {
            if (!h.boundary || !counted.seenOrAdd(h.t, h.tError)) {
              atten *= kt;
              if (maxComponent(atten) < cutoff) return cut = true;
            }
            if constexpr (Shape::kCrossedOnce) break;
            if (++guard == 4) break;
            rr.tMin = h.t;  // the primitive's next crossing
            if (!test.hit(k, rr, rr.tMax, h)) break;
          }
        }
        return false;
      },
      nodes, leafData<Shape>(g));
}

/// crossObject() of object o by its shape (one switch; the shape's traversal is compiled for it).
bool crossInObject(const Object& o, const Ray& r, const Color& kt, float cutoff, Color& atten, CountedCrossings& counted,
                   bool& cut, uint64_t* nodes) {
  return visitShape(o, [&](auto shape, const auto& g) {
    return crossObject<decltype(shape)>(o, g, r, kt, cutoff, atten, counted, cut, nodes);
  });
}

/// Opaque-object part of a shadow packet: the object-space rays r[i] (bits of active) through object o of shape
/// Shape. Returns the mask of rays blocked (each ray's exact leaf test, as crossObject's opaque case).
template <typename Shape>
unsigned blockObject4(const Object& o, const typename Shape::Geometry& g, const Ray* r, unsigned active,
                      uint64_t* nodes) {
  const PacketTesters<Shape> test(g, o.leafPrims(), r, active);
  return o.bvh.traverseAny4(
      r, active,
      [&](uint32_t f, uint32_t c, unsigned rays) {
        unsigned blocked = 0;
        for (unsigned m = rays; m; m &= m - 1) {
          const int i = __builtin_ctz(m);
          for (uint32_t k = f; k < f + c; ++k)
            if (PrimHit h; test[i].hit(k, r[i], r[i].tMax, h)) {
              blocked |= 1u << i;
              break;
            }
        }
        return blocked;
      },
      nodes, leafData<Shape>(g));
}

}  // namespace

unsigned Scene::occludedPacket(const Ray* rays, unsigned active, unsigned& blocked, uint64_t* nodes) const {
  blocked = 0;
  if (features_.volumes) return active;  // volumes attenuate: every answer comes from transmittance()
  unsigned fallback = 0;
  auto instancesInLeaf = [&](uint32_t first, uint32_t count, unsigned raysIn) {
    unsigned done = 0;
    for (uint32_t s = first; s < first + count && (raysIn & ~done); ++s) {
      const unsigned alive = raysIn & ~done;
      const Instance& in = instances_[topInstances_[s]];
      if (maxComponent(materials_[in.material].transmittance) > 0.0f) {
        // A transmissive surface may lie on these rays: their products of kt are formed by transmittance()
        fallback |= alive;
        done |= alive;
        continue;
      }
      const Object& o = objects_[in.object];
      Ray r[4];
      for (unsigned m = alive; m; m &= m - 1) r[__builtin_ctz(m)] = in.objectRay(rays[__builtin_ctz(m)]);
      const unsigned hit = visitShape(
          o, [&](auto shape, const auto& g) { return blockObject4<decltype(shape)>(o, g, r, alive, nodes); });
      blocked |= hit;
      done |= hit;
    }
    return done;
  };
  if (topInstances_.size() == 1)
    instancesInLeaf(0, 1, active);
  else
    top_.traverseAny4(rays, active, instancesInLeaf, nodes);
  // With transmissive surfaces in the scene, a blocked ray's walk by transmittance() might have met them before
  // the opaque blocker and been cut by the threshold (which the caller's error bound counts): traced again
  if (features_.transmissive) {
    fallback |= blocked;
    blocked = 0;
  }
  return fallback & active;
}

bool Scene::intersect(const Ray& ray, Hit& hit, uint64_t* nodes) const {
  hit = Hit{};
  double tMax = ray.tMax;
  // One instance: the world ray itself for an identity transform (no copy), else the object-space ray
  auto instance = [&](uint32_t id, double& tm) __attribute__((always_inline)) {
    const Instance& in = instances_[id];
    const Object& o = objects_[in.object];
    return in.identity ? closestInObject(o, id, ray, tm, hit, nodes)
                       : closestInObject(o, id, in.objectRay(ray), tm, hit, nodes);
  };
  // A single instance needs no top level (its object's root node tests the same box)
  if (topInstances_.size() == 1) return instance(topInstances_[0], tMax);
  return top_.traverse<false>(
      ray, tMax,
      [&](uint32_t first, uint32_t count, double& tm) {
        bool any = false;
        for (uint32_t s = first; s < first + count; ++s) any |= instance(topInstances_[s], tm);
        return any;
      },
      nodes);
}

unsigned Scene::intersectPacket(const Ray* rays, unsigned active, Hit* hits, uint64_t* nodes) const {
  double tMax[4];
  for (unsigned m = active; m; m &= m - 1) {
    const int i = __builtin_ctz(m);
    hits[i] = Hit{};
    tMax[i] = rays[i].tMax;
  }
  auto instancesInLeaf = [&](uint32_t first, uint32_t count, unsigned raysIn, double* tm) {
    unsigned any = 0;
    for (uint32_t s = first; s < first + count; ++s) {
      const uint32_t id = topInstances_[s];
      const Instance& in = instances_[id];
      const Object& o = objects_[in.object];
      Ray r[4];
      for (unsigned m = raysIn; m; m &= m - 1) {
        const int i = __builtin_ctz(m);
        r[i] = in.objectRay(rays[i]);
        r[i].tMax = tm[i];
      }
      any |= visitShape(o, [&](auto shape, const auto& g) {
        return closestHit4<decltype(shape)>(o, g, id, r, raysIn, tm, hits, nodes);
      });
    }
    return any;
  };
  // A single instance needs no top level (as intersect())
  if (topInstances_.size() == 1) return instancesInLeaf(0, 1, active, tMax) & active;
  return top_.traverse4(rays, active, tMax, instancesInLeaf, nodes);
}

Color Scene::transmittance(const Ray& ray, float cutoff, uint64_t* nodes, bool* cutByThreshold,
                           VolumeStep step) const {
  Color atten(1.0f);
  bool cut = false;
  CountedCrossings counted;
  double tMax = ray.tMax;
  // One instance: the world ray itself for an identity transform (no copy), else the object-space ray
  auto instance = [&](uint32_t id) __attribute__((always_inline)) {
    const Instance& in = instances_[id];
    const Object& o = objects_[in.object];
    const Color kt = materials_[in.material].transmittance;
    counted.clear();  // crossings are shared only between primitives of one object
    return in.identity ? crossInObject(o, ray, kt, cutoff, atten, counted, cut, nodes)
                       : crossInObject(o, in.objectRay(ray), kt, cutoff, atten, counted, cut, nodes);
  };
  const bool blocked = topInstances_.size() == 1
                           ? instance(topInstances_[0])
                           : top_.traverse<true>(
                                 ray, tMax,
                                 [&](uint32_t first, uint32_t count, double&) {
                                   for (uint32_t s = first; s < first + count; ++s)
                                     if (instance(topInstances_[s])) return true;
                                   return false;
                                 },
                                 nodes);
  if (cutByThreshold) *cutByThreshold = blocked && cut;
  if (blocked) return Color(0.0f);
  if (features_.volumes) {
    // Through the volumes on the ray (after the surfaces: most shadow rays end at an opaque one)
    VolumeMarch vm;
    marchVolumes(ray, ray.tMax, false, 0.0f, vm, step.scale);
    if (step.error && vm.samples > 0) {
      VolumeMarch coarse;
      marchVolumes(ray, ray.tMax, false, 0.0f, coarse, step.scale, true);
      *step.error += maxComponent(atten) * std::abs(vm.transmittance - coarse.transmittance);
    }
    atten *= vm.transmittance;
  }
  return atten;
}

bool Scene::frustumMayHit(const Frustum& f) const {
  if (!f.valid || features_.volumes) return true;
  auto mayEnter = [&](const Bounds3& b) { return !f.excludes(b); };
  auto instance = [&](uint32_t id) {
    const Instance& in = instances_[id];
    if (!in.identity) return true;  // (its world box passed: counted as a hit)
    return objects_[in.object].bvh.anyLeaf(mayEnter, [](uint32_t, uint32_t) { return true; });
  };
  if (topInstances_.size() == 1) return instance(topInstances_[0]);
  return top_.anyLeaf(mayEnter, [&](uint32_t first, uint32_t count) {
    for (uint32_t s = first; s < first + count; ++s)
      if (instance(topInstances_[s])) return true;
    return false;
  });
}

SurfacePoint Scene::surface(const Ray& ray, const Hit& hit) const {
  const Instance& in = instances_[hit.instance];
  const Object& o = objects_[in.object];
  SurfacePoint sp;
  sp.material = in.material;

  // Object-space surface data from the hit's shape
  const Ray r = in.objectRay(ray);
  visitShape(o, [&](auto shape, const auto& g) { decltype(shape)::surface(g, hit, r, textures_, sp); });
  if (in.hasColor) {
    sp.color = in.color;
    sp.hasColor = true;
  }

  // Object -> world
  if (!in.identity) {
    sp.pError = transformError(in.toWorld, sp.p, sp.pError);
    sp.p = transformPoint(in.toWorld, sp.p);
    sp.ng = safeNormalize(in.normalToWorld * sp.ng, Vec3(0, 0, 1));
    sp.ns = safeNormalize(in.normalToWorld * sp.ns, sp.ng);
  }
  return sp;
}

}  // namespace whitted
