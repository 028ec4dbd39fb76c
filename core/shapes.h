// Geometry containers (triangle meshes, sphere sets, capsule sets) and their ray intersection routines.
//
// All intersection routines work in double precision and take rays whose direction need not be normalised; t is
// the ray parameter. Each routine is exact at edges and vertices where the method allows (the triangle test is
// watertight) and re-centres far-away origins before solving quadratics, so a camera at 1e7 units does not lose
// the hit to cancellation.
#pragma once

#include "math.h"

#include <optional>
#include <vector>

namespace whitted {

/// Indexed triangle mesh in object space.
struct TriangleMesh {
  std::vector<Vec3> positions;         ///< Vertex positions (object space, double).
  std::vector<glm::uvec3> triangles;   ///< Vertex indices per triangle.
  std::vector<Vec3f> normals;          ///< Optional per-vertex normals (empty = use facet normals).
  std::vector<Color4> vertexColors;    ///< Optional per-vertex RGBA in [0,1].
  std::vector<Color4> triangleColors;  ///< Optional per-triangle RGBA in [0,1] (wins over vertexColors).
  std::vector<Vec2f> texcoords;        ///< Optional per-vertex texture coordinates.
  /// Optional per-vertex colour-map coordinate in [0,1] (VTK's InterpolateScalarsBeforeMapping): interpolated,
  /// then looked up in Scene texture colorMap (nearest, clamped, row 0) as the geometry colour, before lighting.
  std::vector<float> colorCoords;
  int32_t colorMap = -1;
};

/// A set of spheres (VTK's points rendered as spheres).
struct SphereSet {
  std::vector<Vec3> centers;
  std::vector<double> radii;   ///< One per sphere, or a single value for all.
  std::vector<Color4> colors;  ///< Optional per-sphere RGBA.
};

/// A set of capsules: cylinders of radius r between two points, closed by hemispheres (VTK's lines as tubes;
/// the caps make joints between consecutive segments seamless).
struct CapsuleSet {
  std::vector<Vec3> p0, p1;              ///< Segment end points.
  std::vector<double> radii;             ///< One per capsule, or a single value for all.
  std::vector<Color4> colors0, colors1;  ///< Optional RGBA at each end (interpolated along the axis).
};

/// Result of a primitive test: ray parameter plus two surface parameters.
/// Triangles: (u, v) = barycentrics of vertices 1 and 2. Capsules: u = position along the axis in [0,1].
struct PrimHit {
  double t;
  double u, v;
  /// Bound on the absolute rounding error of t (ray-parameter units, >= 0): two hits of one crossing computed by
  /// different primitives differ by at most the sum of their bounds. Triangles and capsules; 0 for spheres.
  double tError = 0.0;
  /// The hit lies on the primitive's boundary, where a neighbour sharing that boundary can report the same
  /// crossing: a triangle's edge or vertex (an edge function exactly zero, the only case in which the watertight
  /// test accepts a ray for two triangles), a capsule's end cap or the seam where cap and body meet (where
  /// consecutive capsules of a tube meet). Default false (spheres never set it).
  bool boundary = false;
};

/// Per-ray constants of the watertight triangle test (axis permutation and shear), computed once per ray.
struct TriangleRay {
  int kx = 0, ky = 1, kz = 2;
  double sx = 0.0, sy = 0.0, sz = 0.0;
  bool valid = false;  ///< false for a zero or non-finite direction (then nothing is hit)
  explicit TriangleRay(const Ray& ray);
};

/// Watertight ray/triangle test (Woop, Benthin, Wald 2013). Returns a hit with t in (tMin, tMax).
/// Performance note: pass the precomputed TriangleRay when testing many triangles against one ray.
std::optional<PrimHit> intersectTriangle(const Ray& ray, const TriangleRay& tr, const Vec3& p0, const Vec3& p1,
                                         const Vec3& p2);
inline std::optional<PrimHit> intersectTriangle(const Ray& ray, const Vec3& p0, const Vec3& p1, const Vec3& p2) {
  return intersectTriangle(ray, TriangleRay(ray), p0, p1, p2);
}

/// Ray/sphere test, stable for origins far from the sphere (the origin is moved to the point of closest approach
/// before the quadratic is solved). Returns the nearest t in (tMin, tMax).
std::optional<PrimHit> intersectSphere(const Ray& ray, const Vec3& center, double radius);

/// Ray/capsule test (cylinder between a and b plus spherical caps), with the same re-centring.
std::optional<PrimHit> intersectCapsule(const Ray& ray, const Vec3& a, const Vec3& b, double radius);

/// Per-axis bound on the absolute error of the point b0*p0 + b1*p1 + b2*p2 (pbrt-v4, section 6.8).
Vec3 triangleHitError(const Vec3& p0, const Vec3& p1, const Vec3& p2, double b0, double b1, double b2);

}  // namespace whitted
