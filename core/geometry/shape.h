// What every shape shares: the result of a primitive test (PrimHit), a closest hit (Hit) and the surface data
// at a hit (SurfacePoint). Each shape (shape_triangles.h, shape_spheres.h, shape_tubes.h) provides, in one
// place, its geometry container, its ray intersection routine, and a shape class with the same static interface
// (validity and bounds of a primitive, a per-ray leaf tester, surface data at a hit) that the scene's traversal
// is templated on, so the type is dispatched once per object, never per primitive.
#pragma once

#include "geometry/texture.h"
#include "util/math.h"

#include <cstdint>
#include <cstring>
#include <optional>
#include <type_traits>
#include <vector>

namespace whitted {

/// The shape of an object's primitives.
enum class GeometryType : uint8_t { Triangles, Spheres, Tubes };

/// Result of a primitive test: ray parameter plus two surface parameters.
/// Triangles: (u, v) = barycentrics of vertices 1 and 2. Tubes: u = position along the axis in [0,1].
struct PrimHit {
  double t;
  double u, v;
  /// Bound on the absolute rounding error of t (ray-parameter units, >= 0): two hits of one crossing computed by
  /// different primitives differ by at most the sum of their bounds. Triangles and tubes; 0 for spheres.
  double tError = 0.0;
  /// The hit lies on the primitive's boundary, where a neighbour sharing that boundary can report the same
  /// crossing: a triangle's edge or vertex (an edge function exactly zero, the only case in which the watertight
  /// test accepts a ray for two triangles), a tube's end cap or the seam where cap and body meet (where
  /// consecutive tubes of a tube meet). Default false (spheres never set it).
  bool boundary = false;
};

/// A closest hit: ray parameter, instance, original primitive index and surface parameters.
struct Hit {
  double t = kInfinity;
  uint32_t instance = 0;
  uint32_t prim = 0;  ///< Index of the primitive in the geometry the object was given.
  uint32_t slot = 0;  ///< Where the object stores it (its BVH leaf slot), for the surface lookup.
  double u = 0.0, v = 0.0;
};

/// Everything shading needs at a hit, in world space.
struct SurfacePoint {
  Vec3 p;              ///< Hit point.
  Vec3 pError;         ///< Per-axis bound on the absolute error of p (for robust ray offsets).
  Vec3 ng;             ///< Unit geometric normal (as the geometry winds, not flipped toward the ray).
  Vec3 ns;             ///< Unit shading normal, on the same side as ng.
  Color4 color{1.0f};  ///< Geometry colour (vertex/triangle/sphere), valid when hasColor.
  Vec2f uv{0.0f};      ///< Texture coordinates, valid when hasUV.
  bool hasColor = false;
  bool hasUV = false;
  uint32_t material = 0;
};

/// Radius of primitive i from a per-primitive list, or a single value for all (0 when missing).
inline double radiusAt(const std::vector<double>& radii, std::size_t i) {
  if (radii.empty()) return 0.0;
  return radii.size() == 1 ? radii[0] : (i < radii.size() ? radii[i] : 0.0);
}

/// Same size and same bytes (NaN compares equal to itself, -0 differs from 0: conservative for "unchanged").
template <typename T, typename A>
bool sameBits(const std::vector<T, A>& a, const std::vector<T, A>& b) {
  static_assert(std::is_trivially_copyable_v<T>);
  return a.size() == b.size() && (a.empty() || std::memcmp(a.data(), b.data(), a.size() * sizeof(T)) == 0);
}

/// The limited test of a shape's leaf tester (Tester::hit, what the traversal's leaf loops call) for testers
/// whose test is operator()(slot, ray) returning std::optional<PrimHit>: derive the Tester from
/// LimitedHit<Tester>. Triangles define their own, inline.
template <typename Tester>
struct LimitedHit {
  /// The test of slot on r limited to tMax: true and h set on a hit.
  bool hit(uint32_t slot, const Ray& r, double tMax, PrimHit& h) const {
    Ray limited = r;
    limited.tMax = tMax;
    const std::optional<PrimHit> found = static_cast<const Tester&>(*this)(slot, limited);
    if (found) h = *found;
    return found.has_value();
  }
};

}  // namespace whitted
