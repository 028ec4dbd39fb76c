// Tube sets (VTK's lines as tubes): the container, the ray/tube test, and the tube shape (primitive
// bounds, leaf tester, surface data at a hit) the scene's traversal is templated on.
#pragma once

#include "geometry/shape.h"

namespace whitted {

/// A set of tubes: cylinders of radius r between two points, closed by hemispheres (VTK's lines as tubes;
/// the caps make joints between consecutive segments seamless).
struct TubeSet {
  std::vector<Vec3> p0, p1;              ///< Segment end points.
  std::vector<double> radii;             ///< One per tube, or a single value for all.
  std::vector<Color4> colors0, colors1;  ///< Optional RGBA at each end (interpolated along the axis).
};

/// Ray/tube test (cylinder between a and b plus spherical caps) in double precision, with the origin
/// re-centred before the quadratics are solved so far-away origins keep the hit.
std::optional<PrimHit> intersectTube(const Ray& ray, const Vec3& a, const Vec3& b, double radius);

/// The tube shape. Tubes stay in their given order; leaf slots map to them through the object's leaf order.
struct TubeShape {
  using Geometry = TubeSet;
  static constexpr GeometryType kType = GeometryType::Tubes;
  /// Kept in the given order (leaf slots map to primitives through the object's leaf order).
  static constexpr bool kLeafOrdered = false;
  static constexpr bool kCrossedOnce = false;  ///< A ray can cross a tube twice.

  /// Primitives given (the longer end-point list; tubes past the shorter one are invalid).
  static std::size_t count(const TubeSet& c) { return std::max(c.p0.size(), c.p1.size()); }
  /// Box of tube i; false if it cannot be hit (missing or non-finite end point, radius not positive and finite).
  static bool bounds(const TubeSet& c, uint32_t i, Bounds3& box);
  /// True if a and b have bit-identical end points and radii.
  static bool sameGeometry(const TubeSet& a, const TubeSet& b) {
    return sameBits(a.p0, b.p0) && sameBits(a.p1, b.p1) && sameBits(a.radii, b.radii);
  }
  static void sanitize(TubeSet& c) {
    sanitizeColors(c.colors0);
    sanitizeColors(c.colors1);
  }
  static std::size_t bytes(const TubeSet& c) { return c.p0.capacity() * 2 * sizeof(Vec3); }

  /// Leaf tests of one object visit: slot -> tube through leafPrims.
  class Tester : public LimitedHit<Tester> {
   public:
    Tester(const TubeSet& c, const uint32_t* leafPrims, const Ray&) : set_(c), leafPrims_(leafPrims) {}
    std::optional<PrimHit> operator()(uint32_t slot, const Ray& r) const {
      const uint32_t p = leafPrims_[slot];
      return intersectTube(r, set_.p0[p], set_.p1[p], radiusAt(set_.radii, p));
    }

   private:
    const TubeSet& set_;
    const uint32_t* leafPrims_;
  };

  /// Object-space surface data of hit (found along objectRay): the point re-projected onto the tube, its error
  /// bound, the normal and the colour interpolated along the axis.
  static void surface(const TubeSet& c, const Hit& hit, const Ray& objectRay, const std::vector<Texture>& textures,
                      SurfacePoint& sp);
};

}  // namespace whitted
