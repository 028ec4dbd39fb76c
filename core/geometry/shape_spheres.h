// Sphere sets: the container, the ray/sphere test, and the sphere shape (primitive bounds, leaf tester, surface
// data at a hit) the scene's traversal is templated on.
#pragma once

#include "geometry/shape.h"

namespace whitted {

/// A set of spheres (VTK's points rendered as spheres).
struct SphereSet {
  std::vector<Vec3> centers;
  std::vector<double> radii;   ///< One per sphere, or a single value for all.
  std::vector<Color4> colors;  ///< Optional per-sphere RGBA.
};

/// Ray/sphere test in double precision, stable for origins far from the sphere (the origin is moved to the point
/// of closest approach before the quadratic is solved). Returns the nearest t in (tMin, tMax).
std::optional<PrimHit> intersectSphere(const Ray& ray, const Vec3& center, double radius);

/// The sphere shape. Spheres stay in their given order; leaf slots map to them through the object's leaf order.
struct SphereShape {
  using Geometry = SphereSet;
  static constexpr GeometryType kType = GeometryType::Spheres;
  /// Kept in the given order (leaf slots map to primitives through the object's leaf order).
  static constexpr bool kLeafOrdered = false;
  static constexpr bool kCrossedOnce = false;  ///< A ray can cross a sphere twice.

  static std::size_t count(const SphereSet& s) { return s.centers.size(); }
  /// Box of sphere i; false if it cannot be hit (non-finite centre, radius not positive and finite).
  static bool bounds(const SphereSet& s, uint32_t i, Bounds3& box);
  /// True if a and b have bit-identical centres and radii.
  static bool sameGeometry(const SphereSet& a, const SphereSet& b) {
    return sameBits(a.centers, b.centers) && sameBits(a.radii, b.radii);
  }
  static void sanitize(SphereSet& s) { sanitizeColors(s.colors); }
  static std::size_t bytes(const SphereSet& s) { return s.centers.capacity() * sizeof(Vec3); }

  /// Leaf tests of one object visit: slot -> sphere through leafPrims.
  class Tester : public LimitedHit<Tester> {
   public:
    Tester(const SphereSet& s, const uint32_t* leafPrims, const Ray&) : set_(s), leafPrims_(leafPrims) {}
    std::optional<PrimHit> operator()(uint32_t slot, const Ray& r) const {
      const uint32_t p = leafPrims_[slot];
      return intersectSphere(r, set_.centers[p], radiusAt(set_.radii, p));
    }

   private:
    const SphereSet& set_;
    const uint32_t* leafPrims_;
  };

  /// Object-space surface data of hit (found along objectRay): the point re-projected onto the sphere, its error
  /// bound, the normal and the sphere's colour.
  static void surface(const SphereSet& s, const Hit& hit, const Ray& objectRay, const std::vector<Texture>& textures,
                      SurfacePoint& sp);
};

}  // namespace whitted
